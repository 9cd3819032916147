#include "crowdcloth/character/SkinBinding.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "TopWeights.h"

namespace cc {

Status SkinBindingSettings::validate() const {
    if (!std::isfinite(maxBindDistance) || !(maxBindDistance > 0.0)) {
        return Status::invalidArgument("SkinBindingSettings.maxBindDistance must be finite and > 0");
    }
    if (!std::isfinite(gridCell) || gridCell < 0.0) {
        return Status::invalidArgument("SkinBindingSettings.gridCell must be finite and >= 0");
    }
    return Status::ok();
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            std::array<double, 3>& outBarycentric) {
    // Voronoi-region walk of Ericson, Real-Time Collision Detection (2005), section 5.1.5.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        outBarycentric = {1.0, 0.0, 0.0};
        return a;
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) {
        outBarycentric = {0.0, 1.0, 0.0};
        return b;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        outBarycentric = {1.0 - v, v, 0.0};
        return a + v * ab;
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) {
        outBarycentric = {0.0, 0.0, 1.0};
        return c;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        outBarycentric = {1.0 - w, 0.0, w};
        return a + w * ac;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        outBarycentric = {0.0, 1.0 - w, w};
        return b + w * (c - b);
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    outBarycentric = {1.0 - v - w, v, w};
    return a + ab * v + ac * w;
}

namespace {

// Uniform grid of triangle bounding boxes over the body (padded by the bind distance), in
// compressed rows: cell c holds triangles mItems[mStart[c] .. mStart[c + 1]).
class TriangleGrid {
public:
    /// Covers the body's box only: a point outside searches from the cell its projection onto
    /// the box falls in (a grid padded by the bind distance, 10 m for a garment carried by the
    /// body, was 4 million cells to clear per binding).
    TriangleGrid(const SkinnedMesh& body, Span<const Vec3> positions, double cell) : mBody(body), mPositions(positions) {
        Vec3 lo = positions[0], hi = lo;
        for (const Vec3& q : positions) {
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
        lo.array() -= cell;
        hi.array() += cell;
        // Keep the cell count bounded whatever the body's extent.
        constexpr double kMaxCells = 4.0e6;
        const Vec3 ext = hi - lo;
        while ((std::floor(ext.x() / cell) + 1) * (std::floor(ext.y() / cell) + 1) * (std::floor(ext.z() / cell) + 1) > kMaxCells) {
            cell *= 1.5;
        }
        mCell = cell;
        mLo = lo;
        for (int a = 0; a < 3; ++a) mDims[a] = static_cast<int>(std::floor(ext[a] / cell)) + 1;
        const std::size_t cells = static_cast<std::size_t>(mDims[0]) * mDims[1] * mDims[2];
        std::vector<uint32_t> counts(cells + 1, 0);
        const auto forCells = [&](std::size_t t, auto&& fn) {
            const auto& tri = body.triangles[t];
            Vec3 tlo = positions[tri[0]], thi = tlo;
            for (int k = 1; k < 3; ++k) {
                tlo = tlo.cwiseMin(positions[tri[static_cast<std::size_t>(k)]]);
                thi = thi.cwiseMax(positions[tri[static_cast<std::size_t>(k)]]);
            }
            const auto c0 = cellOf(tlo), c1 = cellOf(thi);
            for (int z = c0[2]; z <= c1[2]; ++z)
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x) fn(index(x, y, z));
        };
        for (std::size_t t = 0; t < body.triangles.size(); ++t) forCells(t, [&](std::size_t c) { ++counts[c + 1]; });
        for (std::size_t c = 0; c < cells; ++c) counts[c + 1] += counts[c];
        mStart = counts;
        mItems.resize(mStart.back());
        std::vector<uint32_t> fill(mStart.begin(), mStart.end() - 1);
        for (std::size_t t = 0; t < body.triangles.size(); ++t) {
            forCells(t, [&](std::size_t c) { mItems[fill[c]++] = static_cast<uint32_t>(t); });
        }
        mStamp.assign(body.triangles.size(), 0);
    }

    // Closest triangle to p within maxDistance; returns false if there is none.
    bool closest(const Vec3& p, double maxDistance, uint32_t& outTriangle, Vec3& outPoint,
                 std::array<double, 3>& outBary) {
        ++mQuery;
        // Rings around the cell of p's projection onto the grid's box: every grid point is at
        // least as far from p as from that projection, so the ring bounds below still hold.
        const auto c = cellOf(p);
        double best = std::numeric_limits<double>::infinity();
        bool found = false;
        const int maxShell = std::max({mDims[0], mDims[1], mDims[2]});
        for (int r = 0; r <= maxShell; ++r) {
            for (int z = c[2] - r; z <= c[2] + r; ++z) {
                for (int y = c[1] - r; y <= c[1] + r; ++y) {
                    for (int x = c[0] - r; x <= c[0] + r; ++x) {
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
                        if (x < 0 || y < 0 || z < 0 || x >= mDims[0] || y >= mDims[1] || z >= mDims[2]) continue;
                        const std::size_t cell = index(x, y, z);
                        for (uint32_t i = mStart[cell]; i < mStart[cell + 1]; ++i) {
                            const uint32_t t = mItems[i];
                            if (mStamp[t] == mQuery) continue;
                            mStamp[t] = mQuery;
                            const auto& tri = mBody.triangles[t];
                            std::array<double, 3> bary;
                            const Vec3 q = closestPointOnTriangle(p, mPositions[tri[0]], mPositions[tri[1]],
                                                                  mPositions[tri[2]], bary);
                            const double d = (q - p).norm();
                            if (d < best || (d == best && t < outTriangle)) {
                                best = d;
                                found = true;
                                outTriangle = t;
                                outPoint = q;
                                outBary = bary;
                            }
                        }
                    }
                }
            }
            // Unvisited cells lie at least r cells away: nothing there can beat `best`.
            if (found && best <= r * mCell) break;
            if (r * mCell > maxDistance) break;
        }
        return found && best <= maxDistance;
    }

private:
    std::array<int, 3> cellOf(const Vec3& q) const {
        std::array<int, 3> c{};
        for (int a = 0; a < 3; ++a) {
            c[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor((q[a] - mLo[a]) / mCell)), 0, mDims[a] - 1);
        }
        return c;
    }
    std::size_t index(int x, int y, int z) const {
        return (static_cast<std::size_t>(z) * mDims[1] + static_cast<std::size_t>(y)) * mDims[0] + static_cast<std::size_t>(x);
    }

    const SkinnedMesh& mBody;
    Span<const Vec3> mPositions;
    double mCell = 1.0;
    Vec3 mLo = Vec3::Zero();
    int mDims[3] = {1, 1, 1};
    std::vector<uint32_t> mStart, mItems, mStamp;
    uint32_t mQuery = 0;
};

} // namespace

Result<SkinBinding> SkinBinding::bind(const SkinnedMesh& body, Span<const Vec3> garmentBindPositions,
                                      const SkinBindingSettings& settings) {
    return bindAt(body, body.bindPositions, {}, garmentBindPositions, settings);
}

Result<SkinBinding> SkinBinding::bindPosed(const SkinnedMesh& body, Span<const Vec3> posedPositions,
                                           Span<const Mat4> skinMatrices, Span<const Vec3> garmentPositions,
                                           const SkinBindingSettings& settings) {
    if (posedPositions.size() != body.vertexCount())
        return Status::invalidArgument("SkinBinding::bindPosed: " + std::to_string(posedPositions.size()) +
                                       " posed positions for a body of " + std::to_string(body.vertexCount()));
    if (skinMatrices.size() != body.inverseBindMatrices.size())
        return Status::invalidArgument("SkinBinding::bindPosed: " + std::to_string(skinMatrices.size()) +
                                       " skin matrices for " + std::to_string(body.inverseBindMatrices.size()) + " joints");
    return bindAt(body, posedPositions, skinMatrices, garmentPositions, settings);
}

Result<SkinBinding> SkinBinding::bindAt(const SkinnedMesh& body, Span<const Vec3> positions, Span<const Mat4> skinMatrices,
                                        Span<const Vec3> garmentPositions, const SkinBindingSettings& settings) {
    Status s = settings.validate();
    if (!s) return s;
    s = body.validate(body.inverseBindMatrices.size());
    if (!s) return Status::invalidArgument("SkinBinding::bind: " + s.message());
    if (body.triangles.empty()) return Status::invalidArgument("SkinBinding::bind: body has no triangles");
    for (std::size_t i = 0; i < garmentPositions.size(); ++i) {
        if (!isFinite(garmentPositions[i])) {
            return Status::invalidArgument("SkinBinding::bind: garment vertex " + std::to_string(i) + " is not finite");
        }
    }
    double cell = settings.gridCell;
    if (cell == 0.0) {
        double sum = 0.0;
        for (const auto& tri : body.triangles) sum += (positions[tri[1]] - positions[tri[0]]).norm();
        cell = std::max(2.0 * sum / static_cast<double>(body.triangles.size()), 1e-4);
    }
    TriangleGrid grid(body, positions, cell);

    SkinBinding binding;
    binding.mBodyVertexCount = body.vertexCount();
    binding.mBodyTriangleCount = body.triangles.size();
    binding.mVertices.resize(garmentPositions.size());
    for (std::size_t i = 0; i < garmentPositions.size(); ++i) {
        BoundVertex& bv = binding.mVertices[i];
        Vec3 point = Vec3::Zero();
        if (!grid.closest(garmentPositions[i], settings.maxBindDistance, bv.triangle, point, bv.barycentric)) {
            return Status::invalidArgument("SkinBinding::bind: garment vertex " + std::to_string(i) +
                                           " is farther than maxBindDistance " +
                                           std::to_string(settings.maxBindDistance) + " m from the body");
        }
        bv.offset = garmentPositions[i] - point;
        detail::TopWeights top;
        const auto& tri = body.triangles[bv.triangle];
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = tri[static_cast<std::size_t>(c)];
            for (int k = 0; k < kMaxInfluences; ++k) {
                top.add(body.jointIndices[v][static_cast<std::size_t>(k)],
                        bv.barycentric[static_cast<std::size_t>(c)] * body.jointWeights[v][static_cast<std::size_t>(k)]);
            }
        }
        if (!top.write(bv.joints, bv.weights)) {
            return Status::invalidArgument("SkinBinding::bind: body triangle " + std::to_string(bv.triangle) +
                                           " has no skin weights");
        }
        if (!skinMatrices.empty()) {
            // evaluate() carries the offset with the point's blended skin matrix: store it in bind
            // space so the binding reproduces the posed position at the pose it was made in.
            Mat3 a = Mat3::Zero();
            for (int k = 0; k < kMaxInfluences; ++k) {
                const double w = bv.weights[static_cast<std::size_t>(k)];
                if (w != 0.0) a += w * skinMatrices[bv.joints[static_cast<std::size_t>(k)]].topLeftCorner<3, 3>();
            }
            const Eigen::FullPivLU<Mat3> lu(a);
            if (!lu.isInvertible())
                return Status::invalidArgument("SkinBinding::bindPosed: the skin at body triangle " +
                                               std::to_string(bv.triangle) + " is degenerate");
            bv.offset = lu.solve(bv.offset);
        }
    }
    return binding;
}

Status SkinBinding::checkSizes(const SkinnedMesh& body, Span<Vec3> outTargets, Span<Vec3> outSurfacePoints,
                               Span<Vec3> outSurfaceNormals) const {
    const std::size_t n = mVertices.size();
    if (body.vertexCount() != mBodyVertexCount || body.triangles.size() != mBodyTriangleCount) {
        return Status::invalidArgument("SkinBinding: body has " + std::to_string(body.vertexCount()) +
                                       " vertices, the binding was made on " + std::to_string(mBodyVertexCount));
    }
    if ((!outTargets.empty() && outTargets.size() != n) || (!outSurfacePoints.empty() && outSurfacePoints.size() != n) ||
        (!outSurfaceNormals.empty() && outSurfaceNormals.size() != n)) {
        return Status::invalidArgument("SkinBinding: output spans must be empty or have " + std::to_string(n) + " entries");
    }
    return Status::ok();
}

namespace {

// Orthonormal frame of a triangle: first edge, in-plane perpendicular, normal (as columns).
Mat3 triangleFrame(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e = (b - a).normalized();
    const Vec3 n = (b - a).cross(c - a).normalized();
    Mat3 f;
    f.col(0) = e;
    f.col(1) = n.cross(e);
    f.col(2) = n;
    return f;
}

} // namespace

Status SkinBinding::evaluateSkinned(const SkinnedMesh& body, Span<const Vec3> skinnedPositions,
                                    Span<const Vec3> skinnedNormals, Span<const Mat4> skinMatrices,
                                    Span<Vec3> outTargets, Span<Vec3> outSurfacePoints,
                                    Span<Vec3> outSurfaceNormals) const {
    Status s = checkSizes(body, outTargets, outSurfacePoints, outSurfaceNormals);
    if (!s) return s;
    if (skinnedPositions.size() != body.vertexCount() || skinnedNormals.size() != body.vertexCount()) {
        return Status::invalidArgument("SkinBinding::evaluateSkinned: skinned arrays must have " +
                                       std::to_string(body.vertexCount()) + " entries");
    }
    if (!skinMatrices.empty() && skinMatrices.size() != body.inverseBindMatrices.size()) {
        return Status::invalidArgument("SkinBinding::evaluateSkinned: " + std::to_string(skinMatrices.size()) +
                                       " skin matrices for " + std::to_string(body.inverseBindMatrices.size()) + " joints");
    }
    for (std::size_t i = 0; i < mVertices.size(); ++i) {
        const BoundVertex& bv = mVertices[i];
        const auto& tri = body.triangles[bv.triangle];
        Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
        for (int c = 0; c < 3; ++c) {
            point += bv.barycentric[static_cast<std::size_t>(c)] * skinnedPositions[tri[static_cast<std::size_t>(c)]];
            normal += bv.barycentric[static_cast<std::size_t>(c)] * skinnedNormals[tri[static_cast<std::size_t>(c)]];
        }
        if (!outSurfacePoints.empty()) outSurfacePoints[i] = point;
        if (!outSurfaceNormals.empty()) {
            const double len = normal.norm();
            outSurfaceNormals[i] = len > 0.0 ? Vec3(normal / len) : Vec3::UnitY();
        }
        if (outTargets.empty()) continue;
        if (!skinMatrices.empty()) {
            Mat3 a = Mat3::Zero();
            for (int k = 0; k < kMaxInfluences; ++k) {
                const double w = bv.weights[static_cast<std::size_t>(k)];
                if (w != 0.0) a += w * skinMatrices[bv.joints[static_cast<std::size_t>(k)]].topLeftCorner<3, 3>();
            }
            outTargets[i] = point + a * bv.offset;
        } else {
            const Mat3 bindFrame = triangleFrame(body.bindPositions[tri[0]], body.bindPositions[tri[1]], body.bindPositions[tri[2]]);
            const Mat3 frame = triangleFrame(skinnedPositions[tri[0]], skinnedPositions[tri[1]], skinnedPositions[tri[2]]);
            outTargets[i] = point + frame * (bindFrame.transpose() * bv.offset);
        }
    }
    return Status::ok();
}

Status SkinBinding::evaluate(const SkinnedMesh& body, Span<const Mat4> skinMatrices, Span<Vec3> outTargets,
                             Span<Vec3> outSurfacePoints, Span<Vec3> outSurfaceNormals) const {
    const std::size_t n = mVertices.size();
    Status s = checkSizes(body, outTargets, outSurfacePoints, outSurfaceNormals);
    if (!s) return s;
    if (skinMatrices.size() != body.inverseBindMatrices.size()) {
        return Status::invalidArgument("SkinBinding::evaluate: " + std::to_string(skinMatrices.size()) +
                                       " skin matrices for " + std::to_string(body.inverseBindMatrices.size()) + " joints");
    }
    for (std::size_t i = 0; i < n; ++i) {
        const BoundVertex& bv = mVertices[i];
        const auto& tri = body.triangles[bv.triangle];
        Vec3 point = Vec3::Zero();
        Vec3 normal = Vec3::Zero();
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = tri[static_cast<std::size_t>(c)];
            Eigen::Matrix<double, 3, 4> m = Eigen::Matrix<double, 3, 4>::Zero();
            for (int k = 0; k < kMaxInfluences; ++k) {
                const double w = body.jointWeights[v][static_cast<std::size_t>(k)];
                if (w != 0.0) m += w * skinMatrices[body.jointIndices[v][static_cast<std::size_t>(k)]].topRows<3>();
            }
            const double b = bv.barycentric[static_cast<std::size_t>(c)];
            point += b * (m.leftCols<3>() * body.bindPositions[v] + m.col(3));
            normal += b * (m.leftCols<3>() * body.bindNormals[v]).normalized();
        }
        if (!outSurfacePoints.empty()) outSurfacePoints[i] = point;
        if (!outSurfaceNormals.empty()) {
            const double len = normal.norm();
            outSurfaceNormals[i] = len > 0.0 ? Vec3(normal / len) : Vec3::UnitY();
        }
        if (!outTargets.empty()) {
            Mat3 a = Mat3::Zero();
            for (int k = 0; k < kMaxInfluences; ++k) {
                const double w = bv.weights[static_cast<std::size_t>(k)];
                if (w != 0.0) a += w * skinMatrices[bv.joints[static_cast<std::size_t>(k)]].topLeftCorner<3, 3>();
            }
            outTargets[i] = point + a * bv.offset;
        }
    }
    return Status::ok();
}

} // namespace cc
