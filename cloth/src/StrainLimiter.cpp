#include "crowdcloth/cloth/StrainLimiter.h"

#include <algorithm>
#include <atomic>

namespace cc::cloth {

StrainLimiter::StrainLimiter(uint32_t vertexCount, const std::vector<LimitedEdge>& edges, std::vector<Vec2> restPositions)
    : mRest(std::move(restPositions)) {
    for (const LimitedEdge& e : edges) mStencils.vertices.push_back({e.a, e.b});
    mEdges = permute(edges, mStencils.colour(vertexCount));
}

double StrainLimiter::maxStrain(const std::vector<Vec3>& x) const {
    double worst = 0.0;
    for (const LimitedEdge& e : mEdges) worst = std::max(worst, (x[e.b] - x[e.a]).norm() / e.restLength - 1.0);
    return worst;
}

bool StrainLimiter::bindTethers(const ConstraintSet& constraints) const {
    if (mRest.empty()) return false;
    mTargets.clear();
    for (uint32_t i = 0; i < constraints.vertexCount(); ++i) {
        if (constraints.kind(i) == ConstraintKind::Target) mTargets.push_back(i);
    }
    if (mTargets.empty()) return false;
    const std::size_t n = mRest.size();
    mAnchor.resize(n);
    mTetherLength.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        uint32_t anchor = mTargets[0];
        double best = (mRest[i] - mRest[anchor]).squaredNorm();
        for (uint32_t t : mTargets) {
            const double d2 = (mRest[i] - mRest[t]).squaredNorm();
            if (d2 < best) best = d2, anchor = t;
        }
        mAnchor[i] = anchor;
        mTetherLength[i] = std::sqrt(best);
    }
    return true;
}

bool StrainLimiter::applyTethers(double limit, double h, const ConstraintSet& constraints, ClothState& state,
                                 const ParallelSettings& parallel) const {
    std::atomic<bool> corrected{false};
    auto& x = state.positions;
    parallelFor(state.vertexCount(), parallel, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            if (constraints.kind(uint32_t(i)) == ConstraintKind::Target) continue;
            const uint32_t anchor = mAnchor[i];
            const double maxLength = (1.0 + limit) * mTetherLength[i];
            const Vec3 d = x[i] - x[anchor];
            const double length = d.norm();
            if (length <= maxLength * (1.0 + 1e-3 * limit)) continue;
            const Vec3 shift = (maxLength / length - 1.0) * d;
            x[i] += shift;
            state.velocities[i] += shift / h;
            corrected.store(true, std::memory_order_relaxed);
        }
    });
    return corrected.load();
}

int StrainLimiter::apply(double limit, int maxPasses, double h, const ConstraintSet& constraints, ClothState& state,
                         const ParallelSettings& parallel) const {
    auto& x = state.positions;
    auto& v = state.velocities;
    auto weight = [&](uint32_t i) {
        return constraints.kind(i) == ConstraintKind::Target ? 0.0 : 1.0 / state.masses[i];
    };
    const double tolerance = 1e-3 * limit;
    const bool tethered = bindTethers(constraints);
    int pass = 0;
    for (; pass < maxPasses; ++pass) {
        // Each colour's edges share no vertex, so they correct in parallel; the flag is only ever set.
        std::atomic<bool> corrected{tethered && applyTethers(limit, h, constraints, state, parallel)};
        for (std::size_t c = 0; c < mStencils.colourCount(); ++c) {
            const int64_t first = mStencils.colourStart[c];
            parallelFor(int64_t(mStencils.colourStart[c + 1]) - first, parallel, [&](int64_t b, int64_t e) {
                for (int64_t k = first + b; k < first + e; ++k) {
                    const LimitedEdge& edge = mEdges[k];
                    const Vec3 d = x[edge.b] - x[edge.a];
                    const double length = d.norm();
                    const double maxLength = (1.0 + limit) * edge.restLength;
                    if (length <= maxLength + tolerance * edge.restLength) continue;
                    const double wa = weight(edge.a), wb = weight(edge.b);
                    if (wa + wb == 0.0) continue;
                    const Vec3 shift = (length - maxLength) / (length * (wa + wb)) * d;
                    x[edge.a] += wa * shift;
                    v[edge.a] += wa * shift / h;
                    x[edge.b] -= wb * shift;
                    v[edge.b] -= wb * shift / h;
                    corrected.store(true, std::memory_order_relaxed);
                }
            });
        }
        if (!corrected.load()) break;
    }
    return pass;
}

} // namespace cc::cloth
