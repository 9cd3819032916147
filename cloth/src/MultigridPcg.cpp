#include "crowdcloth/cloth/MultigridPcg.h"

#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Eigenvalues>

#include "PaddedBlocks.h"

namespace cc::cloth {
namespace {

using detail::Block;
using detail::chunkedPass;
using detail::padBlock;
using detail::padVector;
using detail::times;
using detail::Vec4;

// A coarse direction whose fine support keeps less than this fraction of its weight (an
// eigenvalue of sum w^2 S_i / sum w^2) is constrained on the coarse level too. Only exact losses
// (every supporting vertex pinned, or contacts with one plane) fall below it; partial ones keep
// the direction, which stays correct and merely coarsens less well.
constexpr double kLostDirection = 1e-8;
// Cholesky pivots of the coarsest operator relative to their diagonal entry: below kNullPivot
// the pivot is rounding noise of a null direction; below -kIndefinitePivot the operator is not
// positive semi-definite.
constexpr double kNullPivot = 1e-12;
constexpr double kIndefinitePivot = 1e-8;

Mat3 top(const Block& b) { return b.topRows<3>(); }

// The numeric data of one level, rebuilt every solve from the matrix and filters.
struct LevelState {
    std::vector<Block> blocks;           // S A S (Galerkin products below the finest), padded,
                                         // in the level's storage order
    std::vector<Block> inverseDiagonal;  // (S A_ii S + I - S)^-1, by position
    std::vector<Block> product;          // T = A P for the next level's Galerkin product
    std::vector<Block> filter;           // S_i, read where constrained[i]
    std::vector<uint8_t> constrained;    // S_i != I
    std::vector<uint8_t> indefinite;     // diagonal block not positive definite
    std::vector<Vec4> x, rhs, residual;
};

} // namespace

struct MultigridPcg::Impl {
    MultigridSettings settings;
    std::optional<MultigridHierarchy> hierarchy;
    int builds = 0;
    std::vector<LevelState> levels;
    std::vector<double> dense, denseRhs;  // coarsest level: Cholesky factor (lower, row-major)
    std::vector<Vec4> solution, residual, direction, product, preconditioned;
    std::vector<double> partials;

    const MultigridLevel& level(int k) const { return hierarchy->level(k); }
    int last() const { return hierarchy->levelCount() - 1; }

    EIGEN_STRONG_INLINE static Vec4 project(const LevelState& s, int64_t i, const Vec4& v) {
        return s.constrained[i] ? times(s.filter[i], v) : v;
    }
    // S A S x for the vertex at position q.
    EIGEN_STRONG_INLINE static Vec4 filteredRow(const MultigridLevel& l, const LevelState& s,
                                                int64_t q, const std::vector<Vec4>& x) {
        Vec4 sum = Vec4::Zero();
        for (uint32_t k = l.storageStart[q]; k < l.storageStart[q + 1]; ++k)
            sum += times(s.blocks[k], x[l.storageColumns[k]]);
        return sum;
    }
    // Row (of the vertex at position q) of the level's operator S A S + (I - S) applied to x.
    EIGEN_STRONG_INLINE static Vec4 row(const MultigridLevel& l, const LevelState& s, int64_t q,
                                        const std::vector<Vec4>& x) {
        Vec4 sum = filteredRow(l, s, q, x);
        const uint32_t v = l.colourVertices[q];
        if (s.constrained[v]) sum += x[v] - times(s.filter[v], x[v]);
        return sum;
    }

    Status ensureHierarchy(const BlockSparseMatrix& a);
    void allocate();
    Status setUp(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f,
                 const ParallelSettings& par);
    void coarseFilters(int k, const ParallelSettings& par);
    void galerkin(int k, const ParallelSettings& par);
    Status inverseDiagonal(int k, const ParallelSettings& par);
    Status factorCoarsest();
    void smooth(int k, bool forward, const ParallelSettings& par);
    void solveCoarsest(const ParallelSettings& par);
    void vcycle(int k, const ParallelSettings& par);
};

Status MultigridPcg::Impl::ensureHierarchy(const BlockSparseMatrix& a) {
    if (hierarchy && hierarchy->matches(a)) return Status::ok();
    auto built = MultigridHierarchy::build(a, settings);
    if (!built.isOk()) return built.status();
    hierarchy = std::move(built.value());
    ++builds;
    allocate();
    return Status::ok();
}

void MultigridPcg::Impl::allocate() {
    levels.assign(hierarchy->levelCount(), LevelState{});
    for (int k = 0; k <= last(); ++k) {
        const MultigridLevel& l = level(k);
        LevelState& s = levels[k];
        s.blocks.resize(l.columns.size());
        s.inverseDiagonal.resize(l.size);
        s.product.resize(l.productColumns.size());
        s.filter.resize(l.size);
        s.constrained.resize(l.size);
        s.indefinite.resize(l.size);
        for (auto* v : {&s.x, &s.rhs, &s.residual}) v->assign(l.size, Vec4::Zero());
    }
    const std::size_t m = 3 * std::size_t(level(last()).size);
    if (hierarchy->directCoarsest()) {
        dense.assign(m * m, 0.0);
        denseRhs.assign(m, 0.0);
    }
}

// Filter of each coarse vertex from G_c = sum_i w_ic^2 S_i over its fine support: the directions
// G_c keeps (Tamstorf et al. 2015, prefiltering). A vertex no fine vertex interpolates from is
// fully constrained (its operator row is empty).
void MultigridPcg::Impl::coarseFilters(int k, const ParallelSettings& par) {
    const MultigridLevel& fine = level(k);
    const LevelState& fs = levels[k];
    LevelState& cs = levels[k + 1];
    parallelFor(level(k + 1).size, par, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
            bool any = false;
            double total = 0.0;
            Mat3 g = Mat3::Zero();
            for (uint32_t t = fine.restrictStart[c]; t < fine.restrictStart[c + 1]; ++t) {
                const uint32_t i = fine.restrictSource[t];
                const double w2 = fine.restrictWeight[t] * fine.restrictWeight[t];
                total += w2;
                if (fs.constrained[i]) {
                    any = true;
                    g += w2 * top(fs.filter[i]);
                } else {
                    g.diagonal().array() += w2;
                }
            }
            if (!any && total > 0.0) {
                cs.constrained[c] = 0;
                continue;
            }
            Mat3 s = Mat3::Zero();
            int kept = 0;
            if (total > 0.0) {
                const Eigen::SelfAdjointEigenSolver<Mat3> eigen(g / total);
                for (int e = 0; e < 3; ++e) {
                    if (eigen.eigenvalues()[e] > kLostDirection) {
                        s += eigen.eigenvectors().col(e) * eigen.eigenvectors().col(e).transpose();
                        ++kept;
                    }
                }
            }
            cs.constrained[c] = kept < 3;
            cs.filter[c] = padBlock(s);
        }
    });
}

// A_k+1 = S_k+1 P^T A_k P S_k+1 (A_k is already filtered by S_k on both sides, so this is the
// Galerkin product with P' = S_k P S_k+1).
void MultigridPcg::Impl::galerkin(int k, const ParallelSettings& par) {
    const MultigridLevel& fine = level(k);
    const MultigridLevel& coarse = level(k + 1);
    LevelState& fs = levels[k];
    LevelState& cs = levels[k + 1];
    parallelFor(fine.size, par, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            for (uint32_t s = fine.productStart[i]; s < fine.productStart[i + 1]; ++s)
                fs.product[s].setZero();
            uint32_t q = fine.productMapStart[i];
            const uint32_t stored = fine.storageOf[i];
            for (uint32_t k2 = fine.storageStart[stored]; k2 < fine.storageStart[stored + 1];
                 ++k2) {
                const Block& b = fs.blocks[k2];
                const uint32_t j = fine.storageColumns[k2];
                for (uint32_t t = fine.prolongStart[j]; t < fine.prolongStart[j + 1]; ++t) {
                    fs.product[fine.productMap[q++]] += fine.prolongWeight[t] * b;
                }
            }
        }
    });
    parallelFor(coarse.size, par, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
            const uint32_t first = coarse.storageStart[coarse.storageOf[c]];
            const uint32_t end = coarse.storageStart[coarse.storageOf[c] + 1];
            for (uint32_t s = first; s < end; ++s) cs.blocks[s].setZero();
            uint32_t q = fine.galerkinMapStart[c];
            for (uint32_t t = fine.restrictStart[c]; t < fine.restrictStart[c + 1]; ++t) {
                const uint32_t i = fine.restrictSource[t];
                const double w = fine.restrictWeight[t];
                for (uint32_t s = fine.productStart[i]; s < fine.productStart[i + 1]; ++s) {
                    cs.blocks[fine.galerkinMap[q++]] += w * fs.product[s];
                }
            }
            for (uint32_t s = first; s < end; ++s) {
                const uint32_t d = coarse.storageColumns[s];
                if (!cs.constrained[c] && !cs.constrained[d]) continue;
                Mat3 m = top(cs.blocks[s]);
                if (cs.constrained[c]) m = top(cs.filter[c]) * m;
                if (cs.constrained[d]) m = m * top(cs.filter[d]);
                cs.blocks[s] = padBlock(m);
            }
        }
    });
}

Status MultigridPcg::Impl::inverseDiagonal(int k, const ParallelSettings& par) {
    const MultigridLevel& l = level(k);
    LevelState& s = levels[k];
    parallelFor(l.size, par, [&](int64_t q0, int64_t q1) {
        for (int64_t q = q0; q < q1; ++q) {
            const uint32_t i = l.colourVertices[q];
            Mat3 d = top(s.blocks[l.storageDiagonal[i]]);
            if (s.constrained[i]) d += Mat3::Identity() - top(s.filter[i]);
            // A symmetric 3x3 block is positive definite iff its leading minors are positive.
            const bool definite = d(0, 0) > 0.0 && d.topLeftCorner<2, 2>().determinant() > 0.0 &&
                                  d.determinant() > 0.0;
            s.indefinite[i] = !definite;
            s.inverseDiagonal[q] = padBlock(definite ? Mat3(d.inverse()) : Mat3::Zero());
        }
    });
    for (uint32_t i = 0; i < l.size; ++i) {
        if (s.indefinite[i]) {
            return Status::error(StatusCode::NumericalFailure,
                                 "MultigridPcg: diagonal block of vertex " + std::to_string(i) +
                                     " on level " + std::to_string(k) +
                                     " is not positive definite (or not finite)");
        }
    }
    return Status::ok();
}

// Dense Cholesky of the coarsest operator S A S + (I - S), serial and in a fixed order.
Status MultigridPcg::Impl::factorCoarsest() {
    const MultigridLevel& l = level(last());
    const LevelState& s = levels[last()];
    const std::size_t m = 3 * std::size_t(l.size);
    std::fill(dense.begin(), dense.end(), 0.0);
    for (uint32_t q = 0; q < l.size; ++q) {
        const uint32_t i = l.colourVertices[q];
        for (uint32_t k = l.storageStart[q]; k < l.storageStart[q + 1]; ++k) {
            const std::size_t j = l.storageColumns[k];
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) dense[(3 * i + r) * m + 3 * j + c] = s.blocks[k](r, c);
            }
        }
        if (s.constrained[i]) {
            const Mat3 complement = Mat3::Identity() - top(s.filter[i]);
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) dense[(3 * i + r) * m + 3 * i + c] += complement(r, c);
            }
        }
    }
    for (std::size_t j = 0; j < m; ++j) {
        const double diagonal = dense[j * m + j];
        double d = diagonal;
        for (std::size_t p = 0; p < j; ++p) d -= dense[j * m + p] * dense[j * m + p];
        if (!std::isfinite(d) || !(diagonal > 0.0) || d < -kIndefinitePivot * diagonal) {
            return Status::error(
                StatusCode::NumericalFailure,
                "MultigridPcg: the coarsest operator is not positive definite (row " +
                    std::to_string(j) + ")");
        }
        if (d <= kNullPivot * diagonal) {
            // A direction of the coarse null space: coarse vertices whose filtered fine supports
            // together span less than they do (a sheet lying on one plane but for a few free
            // vertices). P' maps it to zero, so the pivot's value cannot change the correction;
            // the diagonal entry as the pivot, on its own, keeps the factor definite.
            dense[j * m + j] = std::sqrt(diagonal);
            for (std::size_t i = j + 1; i < m; ++i) dense[i * m + j] = 0.0;
            continue;
        }
        const double root = std::sqrt(d);
        dense[j * m + j] = root;
        for (std::size_t i = j + 1; i < m; ++i) {
            double v = dense[i * m + j];
            for (std::size_t p = 0; p < j; ++p) v -= dense[i * m + p] * dense[j * m + p];
            dense[i * m + j] = v / root;
        }
    }
    return Status::ok();
}

Status MultigridPcg::Impl::setUp(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f,
                                 const ParallelSettings& par) {
    if (f.size() != a.size()) {
        return Status::invalidArgument("MultigridPcg: " + std::to_string(f.size()) +
                                       " filters for a matrix of " + std::to_string(a.size()) +
                                       " rows");
    }
    if (Status st = ensureHierarchy(a); !st) return st;
    const MultigridLevel& l0 = level(0);
    LevelState& s0 = levels[0];
    parallelFor(l0.size, par, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            s0.constrained[i] = f[i].kind != ConstraintKind::Free;
            s0.filter[i] = padBlock(f[i].matrix());
        }
    });
    // S A S on the finest level; only rows and columns of constrained vertices change.
    parallelFor(l0.size, par, [&](int64_t q0, int64_t q1) {
        for (int64_t q = q0; q < q1; ++q) {
            const uint32_t i = l0.colourVertices[q];
            const Mat3 si = f[i].matrix();
            for (uint32_t k = l0.storageStart[q]; k < l0.storageStart[q + 1]; ++k) {
                const uint32_t j = l0.storageColumns[k];
                const Mat3& block = a.block(l0.sourceSlot[k]);
                if (!s0.constrained[i] && !s0.constrained[j]) {
                    s0.blocks[k] = padBlock(block);
                } else {
                    s0.blocks[k] = padBlock(si * block * f[j].matrix());
                }
            }
        }
    });
    if (Status st = inverseDiagonal(0, par); !st) return st;
    for (int k = 0; k < last(); ++k) {
        coarseFilters(k, par);
        galerkin(k, par);
        if (Status st = inverseDiagonal(k + 1, par); !st) return st;
    }
    return hierarchy->directCoarsest() ? factorCoarsest() : Status::ok();
}

// One multicolour block Gauss-Seidel sweep on level k: colours in order (forward) or reversed
// (backward, the adjoint of the forward sweep, which makes the V-cycle symmetric).
void MultigridPcg::Impl::smooth(int k, bool forward, const ParallelSettings& par) {
    const MultigridLevel& l = level(k);
    LevelState& s = levels[k];
    const int colours = int(l.colourStart.size()) - 1;
    for (int n = 0; n < colours; ++n) {
        const int c = forward ? n : colours - 1 - n;
        const uint32_t first = l.colourStart[c];
        parallelFor(l.colourStart[c + 1] - first, par, [&](int64_t b, int64_t e) {
            for (int64_t q = first + b; q < first + e; ++q) {
                const uint32_t v = l.colourVertices[q];
                s.x[v] += times(s.inverseDiagonal[q], s.rhs[v] - row(l, s, q, s.x));
            }
        });
    }
}

void MultigridPcg::Impl::solveCoarsest(const ParallelSettings& par) {
    const int k = last();
    LevelState& s = levels[k];
    const uint32_t n = level(k).size;
    if (!hierarchy->directCoarsest()) {
        // Cut short by maxLevels: symmetric Gauss-Seidel pairs keep the preconditioner symmetric.
        std::fill(s.x.begin(), s.x.end(), Vec4::Zero());
        for (int sweep = 0; sweep < settings.smoothingSweeps; ++sweep) {
            smooth(k, true, par);
            smooth(k, false, par);
        }
        return;
    }
    const std::size_t m = 3 * std::size_t(n);
    for (uint32_t i = 0; i < n; ++i) {
        for (int r = 0; r < 3; ++r) denseRhs[3 * i + r] = s.rhs[i][r];
    }
    for (std::size_t i = 0; i < m; ++i) {  // L y = b
        double v = denseRhs[i];
        for (std::size_t p = 0; p < i; ++p) v -= dense[i * m + p] * denseRhs[p];
        denseRhs[i] = v / dense[i * m + i];
    }
    for (std::size_t i = m; i-- > 0;) {  // L^T x = y
        double v = denseRhs[i];
        for (std::size_t p = i + 1; p < m; ++p) v -= dense[p * m + i] * denseRhs[p];
        denseRhs[i] = v / dense[i * m + i];
    }
    for (uint32_t i = 0; i < n; ++i)
        s.x[i] = Vec4(denseRhs[3 * i], denseRhs[3 * i + 1], denseRhs[3 * i + 2], 0.0);
}

// x_k = V(rhs_k): pre-smoothing, coarse correction through P' = S_k P S_k+1, post-smoothing.
void MultigridPcg::Impl::vcycle(int k, const ParallelSettings& par) {
    if (k == last()) {
        solveCoarsest(par);
        return;
    }
    const MultigridLevel& l = level(k);
    LevelState& s = levels[k];
    LevelState& cs = levels[k + 1];
    std::fill(s.x.begin(), s.x.end(), Vec4::Zero());
    for (int sweep = 0; sweep < settings.smoothingSweeps; ++sweep) smooth(k, true, par);
    parallelFor(l.size, par, [&](int64_t q0, int64_t q1) {
        for (int64_t q = q0; q < q1; ++q) {
            const uint32_t i = l.colourVertices[q];
            s.residual[i] = project(s, i, s.rhs[i] - row(l, s, q, s.x));
        }
    });
    parallelFor(level(k + 1).size, par, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
            Vec4 sum = Vec4::Zero();
            for (uint32_t t = l.restrictStart[c]; t < l.restrictStart[c + 1]; ++t) {
                sum += l.restrictWeight[t] * s.residual[l.restrictSource[t]];
            }
            cs.rhs[c] = project(cs, c, sum);
        }
    });
    vcycle(k + 1, par);
    parallelFor(level(k + 1).size, par, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) cs.residual[c] = project(cs, c, cs.x[c]);
    });
    parallelFor(l.size, par, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            Vec4 sum = Vec4::Zero();
            for (uint32_t t = l.prolongStart[i]; t < l.prolongStart[i + 1]; ++t) {
                sum += l.prolongWeight[t] * cs.residual[l.prolongSource[t]];
            }
            s.x[i] += project(s, i, sum);
        }
    });
    for (int sweep = 0; sweep < settings.smoothingSweeps; ++sweep) smooth(k, false, par);
}

MultigridPcg::MultigridPcg(MultigridSettings settings) : mImpl(std::make_unique<Impl>()) {
    mImpl->settings = std::move(settings);
}
MultigridPcg::~MultigridPcg() = default;
MultigridPcg::MultigridPcg(MultigridPcg&&) noexcept = default;
MultigridPcg& MultigridPcg::operator=(MultigridPcg&&) noexcept = default;

const MultigridHierarchy* MultigridPcg::hierarchy() const {
    return mImpl->hierarchy ? &*mImpl->hierarchy : nullptr;
}
int MultigridPcg::hierarchyBuilds() const { return mImpl->builds; }
const MultigridSettings& MultigridPcg::settings() const { return mImpl->settings; }

Status MultigridPcg::setUp(const BlockSparseMatrix& a, const std::vector<VertexFilter>& filters,
                           const ParallelSettings& parallel) {
    return mImpl->setUp(a, filters, parallel);
}

void MultigridPcg::applyPreconditioner(const std::vector<Vec3>& r, std::vector<Vec3>& outZ,
                                       const ParallelSettings& parallel) {
    Impl& m = *mImpl;
    LevelState& s0 = m.levels[0];
    const int64_t n = m.level(0).size;
    for (int64_t i = 0; i < n; ++i) s0.rhs[i] = Impl::project(s0, i, padVector(r[i]));
    m.vcycle(0, parallel);
    outZ.resize(n);
    for (int64_t i = 0; i < n; ++i) outZ[i] = Impl::project(s0, i, s0.x[i]).head<3>();
}

Status MultigridPcg::solve(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f,
                           const std::vector<Vec3>& b, const std::vector<Vec3>& z,
                           std::vector<Vec3>& dv, const PcgSettings& settings,
                           const ParallelSettings& parallel, PcgResult& outResult) {
    outResult = PcgResult{};
    const int64_t n = a.size();
    if (b.size() != a.size() || z.size() != a.size() || dv.size() != a.size()) {
        return Status::invalidArgument(
            "MultigridPcg::solve: b, z and dv must have one entry per matrix row (" +
            std::to_string(n) + ")");
    }
    if (!(settings.relativeTolerance > 0.0 && settings.relativeTolerance < 1.0) ||
        settings.maxIterations < 1) {
        return Status::invalidArgument(
            "MultigridPcg::solve: PcgSettings.relativeTolerance must be in (0, 1) and "
            "maxIterations >= 1");
    }
    Impl& m = *mImpl;
    if (Status s = m.setUp(a, f, parallel); !s) return s;
    for (auto* v : {&m.solution, &m.residual, &m.direction, &m.product, &m.preconditioned})
        v->resize(n);
    auto& x = m.solution;
    auto& r = m.residual;
    auto& p = m.direction;
    auto& q = m.product;
    auto& sv = m.preconditioned;
    LevelState& s0 = m.levels[0];
    const MultigridLevel& l0 = m.level(0);

    // As in solveFilteredPcg: the warm guess keeps its free part and takes z on the constrained
    // one, and the tolerance is relative to |S (b - A z)|, with the unfiltered A.
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) x[i] = padVector(z[i] + f[i].project(dv[i] - z[i]));
    });
    const double rhsNorm2 = chunkedPass(n, parallel, m.partials, [&](int64_t i) {
        Vec3 az = Vec3::Zero();
        for (uint32_t k = a.rowStart()[i]; k < a.rowStart()[i + 1]; ++k)
            az += a.block(k) * z[a.columns()[k]];
        return Eigen::Vector2d(f[i].project(b[i] - az).squaredNorm(), 0.0);
    })[0];
    if (rhsNorm2 == 0.0) {
        dv = z;
        return Status::ok();
    }
    double r2 = chunkedPass(n, parallel, m.partials, [&](int64_t i) {
        Vec3 ax = Vec3::Zero();
        for (uint32_t k = a.rowStart()[i]; k < a.rowStart()[i + 1]; ++k) {
            ax += a.block(k) * x[a.columns()[k]].head<3>();
        }
        r[i] = padVector(f[i].project(b[i] - ax));
        s0.rhs[i] = Impl::project(s0, i, r[i]);
        return Eigen::Vector2d(r[i].squaredNorm(), 0.0);
    })[0];
    const double tol2 = settings.relativeTolerance * settings.relativeTolerance * rhsNorm2;
    // s = S V(S r), then rho = r . s.
    auto precondition = [&]() {
        m.vcycle(0, parallel);
        return chunkedPass(n, parallel, m.partials, [&](int64_t i) {
            sv[i] = Impl::project(s0, i, s0.x[i]);
            return Eigen::Vector2d(r[i].dot(sv[i]), 0.0);
        })[0];
    };
    double rho = 0.0;
    if (r2 > tol2) {
        rho = precondition();
        parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) p[i] = sv[i];
        });
    }
    while (r2 > tol2 && outResult.iterations < settings.maxIterations) {
        // q = S A S p, row by row in the storage order (and p . q summed in that order).
        const double pq = chunkedPass(n, parallel, m.partials, [&](int64_t position) {
            const uint32_t i = l0.colourVertices[position];
            q[i] = Impl::project(s0, i, Impl::filteredRow(l0, s0, position, p));
            return Eigen::Vector2d(p[i].dot(q[i]), 0.0);
        })[0];
        if (!(pq > 0.0) || !(rho > 0.0)) break;  // no curvature left (or not SPD): nothing to gain
        const double alpha = rho / pq;
        r2 = chunkedPass(n, parallel, m.partials, [&](int64_t i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            s0.rhs[i] = Impl::project(s0, i, r[i]);
            return Eigen::Vector2d(r[i].squaredNorm(), 0.0);
        })[0];
        ++outResult.iterations;
        if (r2 <= tol2) break;
        const double rhoNext = precondition();
        const double beta = rhoNext / rho;
        rho = rhoNext;
        parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) p[i] = sv[i] + beta * p[i];
        });
    }
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) dv[i] = x[i].head<3>();
    });
    outResult.relativeResidual = std::sqrt(r2 / rhsNorm2);
    outResult.converged = r2 <= tol2;
    return Status::ok();
}

} // namespace cc::cloth
