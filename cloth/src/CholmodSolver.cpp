#include "crowdcloth/cloth/CholmodSolver.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace cc::cloth {

struct CholmodSolver::Impl {
    using SparseMatrix = Eigen::SparseMatrix<double>;
    SparseMatrix matrix;
    // For each stored scalar (in CSC order): the block slot it reads and its (row, col) in that block.
    std::vector<uint32_t> sourceSlot;
    std::vector<uint8_t> sourceEntry;
    std::vector<uint32_t> patternRowStart, patternColumns;  // the block pattern this was built for
    Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower> factor;
    Eigen::VectorXd rhs, solution;
    std::vector<Mat3> filterMatrices;
    int analyses = 0;

    bool samePattern(const BlockSparseMatrix& a) const {
        return a.rowStart() == patternRowStart && a.columns() == patternColumns;
    }

    // Column 3j+cj holds, for each block (j, i) of block row j (the pattern is symmetric), the rows
    // 3i..3i+2; entry (3i+ri, 3j+cj) of a symmetric A equals entry (cj, ri) of block (j, i).
    void buildPattern(const BlockSparseMatrix& a) {
        const uint32_t n = a.size();
        std::vector<Eigen::Triplet<double>> triplets;
        sourceSlot.clear();
        sourceEntry.clear();
        for (uint32_t j = 0; j < n; ++j) {
            for (int cj = 0; cj < 3; ++cj) {
                for (uint32_t k = a.rowStart()[j]; k < a.rowStart()[j + 1]; ++k) {
                    const uint32_t i = a.columns()[k];
                    for (int ri = 0; ri < 3; ++ri) {
                        triplets.emplace_back(3 * i + ri, 3 * j + cj, 1.0);
                        sourceSlot.push_back(k);
                        sourceEntry.push_back(uint8_t(3 * cj + ri));
                    }
                }
            }
        }
        matrix.resize(3 * n, 3 * n);
        matrix.setFromTriplets(triplets.begin(), triplets.end());
        matrix.makeCompressed();
        patternRowStart = a.rowStart();
        patternColumns = a.columns();
        // Simplicial: with Debian's reference BLAS the supernodal path is ~1.7x slower at cloth sizes.
        factor.setMode(Eigen::CholmodSimplicialLLt);
        factor.analyzePattern(matrix);
        ++analyses;
        rhs.resize(3 * n);
        solution.resize(3 * n);
    }
};

CholmodSolver::CholmodSolver() : mImpl(std::make_unique<Impl>()) {}
CholmodSolver::~CholmodSolver() = default;
CholmodSolver::CholmodSolver(CholmodSolver&&) noexcept = default;
CholmodSolver& CholmodSolver::operator=(CholmodSolver&&) noexcept = default;

int CholmodSolver::analysisCount() const { return mImpl->analyses; }

Status CholmodSolver::solve(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f, const std::vector<Vec3>& b,
                            const std::vector<Vec3>& z, std::vector<Vec3>& dv) {
    Impl& m = *mImpl;
    if (!m.samePattern(a)) m.buildPattern(a);
    const uint32_t n = a.size();

    // Values of S A S + (I - S), written straight into the compressed storage (the setFromTriplets
    // order within a column is by row, as is ours: rows 3i+ri ascend with block column i).
    std::vector<Mat3>& s = m.filterMatrices;
    s.resize(n);
    for (uint32_t i = 0; i < n; ++i) s[i] = f[i].matrix();
    double* values = m.matrix.valuePtr();
    std::size_t entry = 0;
    for (uint32_t j = 0; j < n; ++j) {
        for (int cj = 0; cj < 3; ++cj) {
            for (uint32_t k = a.rowStart()[j]; k < a.rowStart()[j + 1]; ++k) {
                const uint32_t i = a.columns()[k];
                // Block (j, i) of S A S is S_j A_ji S_i; we need its entry (cj, ri).
                const Mat3 filtered = s[j] * a.block(k) * s[i];
                for (int ri = 0; ri < 3; ++ri, ++entry) {
                    double value = filtered(cj, ri);
                    if (i == j && cj == ri) value += 1.0 - s[i](ri, ri);
                    else if (i == j) value -= s[i](ri, cj);  // (I - S) off-diagonal entries
                    values[entry] = value;
                }
            }
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        Vec3 az = Vec3::Zero();
        for (uint32_t k = a.rowStart()[i]; k < a.rowStart()[i + 1]; ++k) az += a.block(k) * z[a.columns()[k]];
        m.rhs.segment<3>(3 * i) = f[i].project(b[i] - az);
    }
    m.factor.factorize(m.matrix);
    if (m.factor.info() != Eigen::Success) {
        return Status::error(StatusCode::NumericalFailure, "CHOLMOD factorisation failed (matrix not positive definite)");
    }
    m.solution = m.factor.solve(m.rhs);
    if (m.factor.info() != Eigen::Success) return Status::error(StatusCode::NumericalFailure, "CHOLMOD solve failed");
    for (uint32_t i = 0; i < n; ++i) dv[i] = z[i] + f[i].project(m.solution.segment<3>(3 * i));
    return Status::ok();
}

} // namespace cc::cloth
