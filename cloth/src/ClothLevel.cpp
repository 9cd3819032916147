#include "crowdcloth/cloth/ClothLevel.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

#include <cholmod.h>

#include "crowdcloth/cloth/ClothTopology.h"

namespace cc::cloth {
namespace {

constexpr uint32_t kNone = 0xffffffffu;

/// CHOLMOD's workspace for one call, released on every path.
struct CholmodCommon {
    cholmod_common c;
    CholmodCommon() {
        cholmod_start(&c);
        c.print = 0;
        c.error_handler = nullptr;
    }
    ~CholmodCommon() { cholmod_finish(&c); }
    CholmodCommon(const CholmodCommon&) = delete;
    CholmodCommon& operator=(const CholmodCommon&) = delete;
};

/// Lower triangle of a symmetric matrix given column-compressed with the diagonal first.
struct LowerMatrix {
    const std::vector<uint32_t>& columnStart;
    const std::vector<uint32_t>& rows;
    const std::vector<double>& values;
};

/// The lower triangle of a symmetric matrix, column-compressed with the diagonal first, owned.
struct CompressedLower {
    std::vector<uint32_t> columnStart{0}, rows;
    std::vector<double> values;
};

/// Compresses per-column (row > column, value) lists and the diagonal; entries of one row in one
/// column (parallel springs) are summed in the order they were added.
CompressedLower compress(std::vector<std::vector<std::pair<uint32_t, double>>>& columns,
                         const std::vector<double>& diagonal) {
    CompressedLower out;
    for (std::size_t j = 0; j < columns.size(); ++j) {
        auto& col = columns[j];
        std::stable_sort(col.begin(), col.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        out.rows.push_back(uint32_t(j));
        out.values.push_back(diagonal[j]);
        for (std::size_t k = 0; k < col.size(); ++k) {
            if (k > 0 && col[k].first == col[k - 1].first) {
                out.values.back() += col[k].second;
                continue;
            }
            out.rows.push_back(col[k].first);
            out.values.push_back(col[k].second);
        }
        out.columnStart.push_back(uint32_t(out.rows.size()));
    }
    return out;
}

/// A CHOLMOD view of `lower` (stype -1: lower triangle stored). Returns null on failure.
cholmod_sparse* toCholmod(const LowerMatrix& lower, cholmod_common& c) {
    const std::size_t n = lower.columnStart.size() - 1;
    cholmod_sparse* a = cholmod_allocate_sparse(n, n, lower.rows.size(), 1, 1, -1, CHOLMOD_REAL, &c);
    if (!a) return nullptr;
    auto* p = static_cast<int*>(a->p);
    auto* i = static_cast<int*>(a->i);
    auto* x = static_cast<double*>(a->x);
    for (std::size_t k = 0; k <= n; ++k) p[k] = int(lower.columnStart[k]);
    for (std::size_t k = 0; k < lower.rows.size(); ++k) i[k] = int(lower.rows[k]), x[k] = lower.values[k];
    return a;
}

/// Nodes: welded copies joined (union-find; the root is the lowest vertex of its group).
std::vector<uint32_t> nodeRoots(uint32_t vertexCount, Span<const std::array<uint32_t, 2>> welds) {
    std::vector<uint32_t> parent(vertexCount);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& [a, b] : welds) {
        const uint32_t ra = find(a), rb = find(b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (uint32_t v = 0; v < vertexCount; ++v) parent[v] = find(v);
    return parent;
}

Status validate(const ClothLevelDesc& d) {
    const uint32_t n = d.vertexCount;
    if (n == 0) return Status::invalidArgument("ClothLevel: no vertices");
    if (d.masses.size() != n)
        return Status::invalidArgument("ClothLevel: " + std::to_string(d.masses.size()) + " masses for " +
                                       std::to_string(n) + " vertices");
    for (uint32_t v = 0; v < n; ++v)
        if (!(d.masses[v] > 0.0 && std::isfinite(d.masses[v])))
            return Status::invalidArgument("ClothLevel: vertex " + std::to_string(v) + " has mass " +
                                           std::to_string(d.masses[v]) + "; need finite > 0");
    for (std::size_t s = 0; s < d.springs.size(); ++s) {
        const Spring& sp = d.springs[s];
        if (sp.a >= n || sp.b >= n || sp.a == sp.b)
            return Status::invalidArgument("ClothLevel: spring " + std::to_string(s) + " joins vertices " +
                                           std::to_string(sp.a) + " and " + std::to_string(sp.b) + " of " +
                                           std::to_string(n));
        if (!(sp.stiffness >= 0.0 && std::isfinite(sp.stiffness)) || !(sp.restLength > 0.0 && std::isfinite(sp.restLength)))
            return Status::invalidArgument("ClothLevel: spring " + std::to_string(s) +
                                           " needs finite stiffness >= 0 and rest length > 0");
    }
    for (uint32_t v : d.attachedVertices)
        if (v >= n) return Status::invalidArgument("ClothLevel: attached vertex " + std::to_string(v) + " out of range");
    for (const auto& [a, b] : d.welds)
        if (a >= n || b >= n) return Status::invalidArgument("ClothLevel: weld names a vertex out of range");
    for (const LimitedEdge& e : d.limitedEdges)
        if (e.a >= n || e.b >= n || !(e.restLength > 0.0))
            return Status::invalidArgument("ClothLevel: a limited edge is out of range or has no length");
    if (!d.restPositions.empty() && d.restPositions.size() != n)
        return Status::invalidArgument("ClothLevel: rest positions must be empty or one per vertex");
    return Status::ok();
}

} // namespace

Result<std::shared_ptr<const ClothLevel>> ClothLevel::cook(const ClothLevelDesc& d) {
    if (Status s = validate(d); !s) return s;
    const uint32_t n = d.vertexCount;
    std::shared_ptr<ClothLevel> level(new ClothLevel());

    // Nodes and which of them are attached.
    const std::vector<uint32_t> root = nodeRoots(n, d.welds);
    std::vector<char> attached(n, 0);
    for (uint32_t v : d.attachedVertices) attached[root[v]] = 1;
    std::vector<uint32_t> freeRoots, attachedRoots;
    for (uint32_t v = 0; v < n; ++v) {
        if (root[v] != v) continue;
        (attached[v] ? attachedRoots : freeRoots).push_back(v);
    }
    if (freeRoots.empty()) return Status::invalidArgument("ClothLevel: every vertex is attached; nothing to simulate");
    const uint32_t freeCount = uint32_t(freeRoots.size());

    // Provisional numbering (free roots in vertex order) and the stiffness graph over free nodes.
    std::vector<uint32_t> provisional(n, kNone);
    for (uint32_t k = 0; k < freeCount; ++k) provisional[freeRoots[k]] = k;
    std::vector<std::vector<std::pair<uint32_t, double>>> lowerColumns(freeCount);  // (row > col, k)
    std::vector<double> diagonal(freeCount, 0.0);
    for (const Spring& s : d.springs) {
        const uint32_t a = provisional[root[s.a]], b = provisional[root[s.b]];
        if (root[s.a] == root[s.b] || s.kind == SpringKind::Bend) continue;  // ordered for stretch and shear
        if (a != kNone) diagonal[a] += s.stiffness;
        if (b != kNone) diagonal[b] += s.stiffness;
        if (a != kNone && b != kNone) lowerColumns[std::min(a, b)].push_back({std::max(a, b), -s.stiffness});
    }

    // Fill-reducing ordering from CHOLMOD's analysis (AMD, METIS and nested dissection tried; the
    // least fill wins), on the pattern with unit masses.
    std::vector<uint32_t> order(freeCount);  // new position -> provisional index
    {
        for (double& entry : diagonal) entry += 1.0;  // unit masses: only the pattern matters here
        const CompressedLower pattern = compress(lowerColumns, diagonal);
        CholmodCommon common;
        common.c.nmethods = 4;  // the default suite after the user ordering: AMD, METIS, NESDIS
        cholmod_sparse* a = toCholmod({pattern.columnStart, pattern.rows, pattern.values}, common.c);
        if (!a) return Status::error(StatusCode::NumericalFailure, "ClothLevel: CHOLMOD could not allocate");
        cholmod_factor* symbolic = cholmod_analyze(a, &common.c);
        cholmod_free_sparse(&a, &common.c);
        if (!symbolic) return Status::error(StatusCode::NumericalFailure, "ClothLevel: CHOLMOD analysis failed");
        const int* perm = static_cast<const int*>(symbolic->Perm);
        for (uint32_t k = 0; k < freeCount; ++k) order[k] = uint32_t(perm[k]);
        cholmod_free_factor(&symbolic, &common.c);
    }

    // Final numbering: free nodes in the factor's order, then attached nodes by vertex.
    std::vector<uint32_t> nodeOfRoot(n, kNone);
    level->mVertexOfNode.resize(freeCount + attachedRoots.size());
    for (uint32_t k = 0; k < freeCount; ++k) {
        nodeOfRoot[freeRoots[order[k]]] = k;
        level->mVertexOfNode[k] = freeRoots[order[k]];
    }
    for (uint32_t k = 0; k < attachedRoots.size(); ++k) {
        nodeOfRoot[attachedRoots[k]] = freeCount + k;
        level->mVertexOfNode[freeCount + k] = attachedRoots[k];
    }
    level->mFreeNodeCount = freeCount;
    level->mNodeOfVertex.resize(n);
    for (uint32_t v = 0; v < n; ++v) level->mNodeOfVertex[v] = nodeOfRoot[root[v]];
    const auto& node = level->mNodeOfVertex;

    level->mNodeMass.assign(level->mVertexOfNode.size(), 0.0);
    for (uint32_t v = 0; v < n; ++v) level->mNodeMass[node[v]] += d.masses[v];
    for (uint32_t k = 0; k < freeCount; ++k) level->mTotalMass += level->mNodeMass[k];

    // Springs over nodes; attached-attached springs exert nothing the solver needs.
    for (const Spring& s : d.springs) {
        uint32_t a = node[s.a], b = node[s.b];
        if (a == b || (a >= freeCount && b >= freeCount)) continue;
        if (a >= freeCount) std::swap(a, b);
        LevelSpring ls{a, b, s.stiffness, s.restLength};
        const bool bend = s.kind == SpringKind::Bend;
        if (b < freeCount) {
            if (ls.a > ls.b) std::swap(ls.a, ls.b);
            (bend ? level->mFreeBendSprings : level->mFreeSprings).push_back(ls);
        } else {
            (bend ? level->mAttachedBendSprings : level->mAttachedSprings).push_back(ls);
        }
    }
    auto byNodes = [](const LevelSpring& x, const LevelSpring& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
    for (auto* list : {&level->mFreeSprings, &level->mAttachedSprings, &level->mFreeBendSprings,
                       &level->mAttachedBendSprings})
        std::stable_sort(list->begin(), list->end(), byNodes);

    for (const LimitedEdge& e : d.limitedEdges) {
        uint32_t a = node[e.a], b = node[e.b];
        if (a == b || (a >= freeCount && b >= freeCount)) continue;
        if (a > b) std::swap(a, b);
        level->mLimitedEdges.push_back({a, b, e.restLength});
    }

    // Tethers to the nearest attached node in pattern space (pattern distances within a panel; a
    // weld's copies are the same point, so the nearest copy counts).
    if (!d.restPositions.empty() && !attachedRoots.empty()) {
        std::vector<uint32_t> attachedVertices;
        for (uint32_t v = 0; v < n; ++v)
            if (node[v] >= freeCount) attachedVertices.push_back(v);
        level->mTethers.assign(freeCount, LevelTether{kNone, INFINITY});
        for (uint32_t v = 0; v < n; ++v) {
            const uint32_t k = node[v];
            if (k >= freeCount) continue;
            LevelTether& t = level->mTethers[k];
            for (uint32_t w : attachedVertices) {
                const double dist = (d.restPositions[v] - d.restPositions[w]).norm();
                if (dist < t.restLength) t = {node[w], dist};
            }
        }
    }

    // Strain-limited edges nearest the attached nodes first: a Gauss-Seidel sweep in this order
    // carries a correction from the attachments to the far edge in one pass, as follow-the-leader
    // does for hair (Mueller et al. 2012), instead of one edge per pass.
    auto distance = [&](uint32_t k) { return k >= freeCount ? 0.0 : level->mTethers.empty() ? 0.0 : level->mTethers[k].restLength; };
    std::stable_sort(level->mLimitedEdges.begin(), level->mLimitedEdges.end(), [&](const LimitedEdge& x, const LimitedEdge& y) {
        const double dx = std::min(distance(x.a), distance(x.b)), dy = std::min(distance(y.a), distance(y.b));
        if (dx != dy) return dx < dy;
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });

    return std::shared_ptr<const ClothLevel>(std::move(level));
}

Result<std::shared_ptr<const ClothLevel>> ClothLevel::cookMesh(const ClothMesh& mesh, const ClothMaterial& material,
                                                               Span<const uint32_t> attachedVertices,
                                                               Span<const std::array<uint32_t, 2>> welds) {
    if (Status s = mesh.validate(); !s) return s;
    if (Status s = material.validate(); !s) return s;
    auto topology = ClothTopology::build(mesh);
    if (!topology.isOk()) return topology.status();
    const std::vector<Spring> springs = provotSprings(mesh, topology.value(), material);
    const std::vector<double> masses = lumpedMasses(mesh, material.arealDensity);
    std::vector<LimitedEdge> edges;
    edges.reserve(topology.value().edges.size());
    for (const auto& [a, b] : topology.value().edges)
        edges.push_back({a, b, (mesh.restPositions[b] - mesh.restPositions[a]).norm()});
    ClothLevelDesc desc;
    desc.vertexCount = uint32_t(mesh.vertexCount());
    desc.springs = springs;
    desc.masses = masses;
    desc.attachedVertices = attachedVertices;
    desc.welds = welds;
    desc.limitedEdges = edges;
    desc.restPositions = mesh.restPositions;
    return cook(desc);
}

Result<std::shared_ptr<const SubstepFactor>> ClothLevel::buildFactor(double h) const {
    if (!(h > 0.0 && h <= 1.0)) return Status::invalidArgument("ClothLevel::buildFactor: h = " + std::to_string(h) + " s is outside (0, 1]");
    const uint32_t n = mFreeNodeCount;
    // Bending joins the matrix only where explicit bending would be near its stability limit.
    std::vector<double> bendLoad(n, 0.0);
    for (const auto* list : {&mFreeBendSprings, &mAttachedBendSprings})
        for (const LevelSpring& s : *list) {
            bendLoad[s.a] += s.stiffness;
            if (s.b < n) bendLoad[s.b] += s.stiffness;
        }
    bool includeBending = false;
    // Explicit springs are stable while h^2 sum_k / m < 2 at every node (Gershgorin); a quarter of that.
    for (uint32_t k = 0; k < n; ++k) includeBending = includeBending || h * h * bendLoad[k] / mNodeMass[k] > 0.5;

    // Lower triangle of M / h^2 + L over the free nodes, column-compressed, diagonal first.
    std::vector<std::vector<std::pair<uint32_t, double>>> columns(n);
    std::vector<double> diagonal(n);
    for (uint32_t k = 0; k < n; ++k) diagonal[k] = mNodeMass[k] / (h * h);
    auto add = [&](const std::vector<LevelSpring>& springs) {
        for (const LevelSpring& s : springs) {
            diagonal[s.a] += s.stiffness;
            if (s.b >= n) continue;  // attached end: known, on the right-hand side
            diagonal[s.b] += s.stiffness;
            columns[std::min(s.a, s.b)].push_back({std::max(s.a, s.b), -s.stiffness});
        }
    };
    add(mFreeSprings);
    add(mAttachedSprings);
    if (includeBending) {
        add(mFreeBendSprings);
        add(mAttachedBendSprings);
    }
    const CompressedLower matrix = compress(columns, diagonal);

    CholmodCommon common;
    // The nodes are already in the fill-reducing order of the stretch and shear springs: without
    // bending the factor needs no permutation. Bending springs (two edges apart) widen the stencil,
    // so a factor with them gets its own ordering. Simplicial LL^T: our own solves read it column
    // by column.
    if (includeBending) {
        common.c.nmethods = 4;  // AMD, METIS, NESDIS: the least fill wins
    } else {
        common.c.nmethods = 1;
        common.c.method[0].ordering = CHOLMOD_NATURAL;
        common.c.postorder = 0;
    }
    common.c.supernodal = CHOLMOD_SIMPLICIAL;
    common.c.final_ll = 1;
    cholmod_sparse* a = toCholmod({matrix.columnStart, matrix.rows, matrix.values}, common.c);
    if (!a) return Status::error(StatusCode::NumericalFailure, "ClothLevel::buildFactor: CHOLMOD could not allocate");
    cholmod_factor* l = cholmod_analyze(a, &common.c);
    bool ok = l && cholmod_factorize(a, l, &common.c) && common.c.status == CHOLMOD_OK &&
              cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, l, &common.c);
    cholmod_free_sparse(&a, &common.c);
    if (!ok) {
        if (l) cholmod_free_factor(&l, &common.c);
        return Status::error(StatusCode::NumericalFailure,
                             "ClothLevel::buildFactor: the local/global matrix is not positive definite");
    }
    std::shared_ptr<SubstepFactor> f(new SubstepFactor());
    f->mSubstep = h;
    f->mIncludesBending = includeBending;
    if (includeBending) {
        const int* perm = static_cast<const int*>(l->Perm);
        f->mPermutation.assign(perm, perm + n);
    }
    const int* p = static_cast<const int*>(l->p);
    const int* lRows = static_cast<const int*>(l->i);
    const double* x = static_cast<const double*>(l->x);
    f->mColumnStart.assign(1, 0);
    f->mInverseDiagonal.resize(n);
    for (uint32_t j = 0; j < n; ++j) {
        // Simplicial LL^T keeps the diagonal first in each column.
        f->mInverseDiagonal[j] = 1.0 / x[p[j]];
        for (int k = p[j] + 1; k < p[j + 1]; ++k) {
            f->mRows.push_back(uint32_t(lRows[k]));
            f->mValues.push_back(x[k]);
        }
        f->mColumnStart.push_back(uint32_t(f->mRows.size()));
    }
    cholmod_free_factor(&l, &common.c);
    // The same strictly lower part by rows, for the forward solve.
    f->mRowStart.assign(n + 1, 0);
    for (uint32_t r : f->mRows) ++f->mRowStart[r + 1];
    for (uint32_t i = 0; i < n; ++i) f->mRowStart[i + 1] += f->mRowStart[i];
    f->mRowColumns.resize(f->mRows.size());
    f->mRowValues.resize(f->mRows.size());
    std::vector<uint32_t> fill(f->mRowStart.begin(), f->mRowStart.end() - 1);
    for (uint32_t j = 0; j < n; ++j) {
        for (uint32_t k = f->mColumnStart[j]; k < f->mColumnStart[j + 1]; ++k) {
            const uint32_t slot = fill[f->mRows[k]]++;
            f->mRowColumns[slot] = j;
            f->mRowValues[slot] = f->mValues[k];
        }
    }
    return std::shared_ptr<const SubstepFactor>(std::move(f));
}

namespace {

// Two doubles: the SIMD width every x86-64 machine has (SSE2); rows are padded to whole vectors.
typedef double Pair __attribute__((vector_size(16)));

inline Pair loadPair(const double* p) {
    Pair v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void storePair(double* p, Pair v) { std::memcpy(p, &v, sizeof v); }

// x_i = (x_i - sum_k l_k x_{index_k}) * scale over one compressed row or column of L, for the C
// columns of x from `x` on (rows R apart): the dot product form, so the running sums stay in
// registers. Two sums (even and odd k) halve the dependency chain; the split depends only on k, so
// every column of x sees the same operations whatever the width.
template <int R, int C>
inline void eliminate(double* x, uint32_t i, const uint32_t* index, const double* l, uint32_t count, double scale) {
    constexpr int kPairs = C / 2;
    Pair even[kPairs], odd[kPairs];
    for (int v = 0; v < kPairs; ++v) even[v] = loadPair(x + std::size_t(i) * R + 2 * v), odd[v] = Pair{0.0, 0.0};
    uint32_t k = 0;
    for (; k + 1 < count; k += 2) {
        const double* xa = x + std::size_t(index[k]) * R;
        const double* xb = x + std::size_t(index[k + 1]) * R;
        for (int v = 0; v < kPairs; ++v) {
            even[v] -= l[k] * loadPair(xa + 2 * v);
            odd[v] -= l[k + 1] * loadPair(xb + 2 * v);
        }
    }
    if (k < count) {
        const double* xa = x + std::size_t(index[k]) * R;
        for (int v = 0; v < kPairs; ++v) even[v] -= l[k] * loadPair(xa + 2 * v);
    }
    for (int v = 0; v < kPairs; ++v) storePair(x + std::size_t(i) * R + 2 * v, (even[v] + odd[v]) * scale);
}

} // namespace

template <int R>
void SubstepFactor::solve(double* x) const {
    const uint32_t n = size();
    // L y = b by rows of L (y_i needs the y_j, j < i, already found), then L^T x = y by columns
    // of L (x_j needs the x_i, i > j).
    // Wide batches go 12 columns at a time: 2 x 6 running pairs fill the 16 SSE registers.
    constexpr int C = std::min(R, 12);
    for (int offset = 0; offset < R; offset += C) {
        for (uint32_t i = 0; i < n; ++i)
            eliminate<R, C>(x + offset, i, mRowColumns.data() + mRowStart[i], mRowValues.data() + mRowStart[i],
                            mRowStart[i + 1] - mRowStart[i], mInverseDiagonal[i]);
        for (uint32_t j = n; j-- > 0;)
            eliminate<R, C>(x + offset, j, mRows.data() + mColumnStart[j], mValues.data() + mColumnStart[j],
                            mColumnStart[j + 1] - mColumnStart[j], mInverseDiagonal[j]);
    }
}

void SubstepFactor::solveInPlace(double* x, int stride, std::vector<double>& scratch) const {
    double* rows = x;
    if (!mPermutation.empty()) {
        // The factor is of P A P^T: solve for P x, in the scratch.
        scratch.resize(mPermutation.size() * std::size_t(stride));
        for (std::size_t i = 0; i < mPermutation.size(); ++i)
            std::memcpy(&scratch[i * stride], x + std::size_t(mPermutation[i]) * stride, sizeof(double) * stride);
        rows = scratch.data();
    }
    switch (stride) {
    case 4: solve<4>(rows); break;
    case 8: solve<8>(rows); break;
    case 12: solve<12>(rows); break;
    case 24: solve<24>(rows); break;
    default: return;  // callers pass a supported stride (see the header)
    }
    if (!mPermutation.empty())
        for (std::size_t i = 0; i < mPermutation.size(); ++i)
            std::memcpy(x + std::size_t(mPermutation[i]) * stride, &scratch[i * stride], sizeof(double) * stride);
}

} // namespace cc::cloth
