// GarmentHierarchy::adapt and the refinement criteria (RefinementSettings).
#include <algorithm>
#include <cmath>
#include <string>

#include "crowdcloth/lod/GarmentHierarchy.h"
#include "crowdcloth/lod/RefinementSettings.h"

namespace cc::lod {

namespace {

Status checkRange(double value, double lo, double hi, const char* field) {
    if (!std::isfinite(value) || value < lo || value > hi) {
        return Status::invalidArgument(std::string("RefinementSettings.") + field + " = " + std::to_string(value) +
                                       " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return Status::ok();
}

} // namespace

Status RefinementSettings::validate() const {
    for (Status s : {checkRange(maxEdgePixels, 0.0, 1e4, "maxEdgePixels"),
                     checkRange(maxDihedralAngle, 0.0, 3.14159265358979323846, "maxDihedralAngle"),
                     checkRange(maxStrain, 0.0, 10.0, "maxStrain"),
                     checkRange(maxKineticEnergy, 0.0, 1e6, "maxKineticEnergy"),
                     checkRange(proximityDistance, 0.0, 10.0, "proximityDistance")}) {
        if (!s) return s;
    }
    if (!(coarsenFraction > 0.0 && coarsenFraction < 1.0)) {
        return Status::invalidArgument("RefinementSettings.coarsenFraction = " + std::to_string(coarsenFraction) +
                                       " is outside (0, 1)");
    }
    if (quietFrames > 100000) return Status::invalidArgument("RefinementSettings.quietFrames is above 100000");
    if (maxLevel != 0 && minLevel > maxLevel) {
        return Status::invalidArgument("RefinementSettings.minLevel = " + std::to_string(minLevel) +
                                       " is above maxLevel = " + std::to_string(maxLevel));
    }
    return Status::ok();
}

double GarmentHierarchy::triangleDemand(uint32_t t, const RefinementSettings& settings, const AdaptInput& input,
                                        const std::vector<uint32_t>& vertexToSim) const {
    const Triangle& tri = mTriangles[t];
    std::array<const Vertex*, 3> v{&mVertices[tri.vertices[0]], &mVertices[tri.vertices[1]], &mVertices[tri.vertices[2]]};
    double demand = 0.0;
    if (settings.maxEdgePixels > 0.0 && input.viewProjection) {
        std::array<Eigen::Vector2d, 3> px;
        bool visible = true;
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector4d clip = *input.viewProjection * v[k]->position.homogeneous();
            if (!(clip.w() > 1e-9)) {
                visible = false;  // behind the eye: the view does not ask for detail
                break;
            }
            px[k] = Eigen::Vector2d((clip.x() / clip.w() + 1.0) * 0.5 * input.viewportWidth,
                                    (clip.y() / clip.w() + 1.0) * 0.5 * input.viewportHeight);
        }
        if (visible) {
            double longest = 0.0;
            for (int k = 0; k < 3; ++k) longest = std::max(longest, (px[k] - px[(k + 1) % 3]).norm());
            demand = std::max(demand, longest / settings.maxEdgePixels);
        }
    }
    if (settings.maxDihedralAngle > 0.0) {
        const Vec3 n = (v[1]->position - v[0]->position).cross(v[2]->position - v[0]->position);
        const double len = n.norm();
        for (int k = 0; k < 3 && len > 0.0; ++k) {
            const uint32_t other = neighbour(t, tri.vertices[k], tri.vertices[(k + 1) % 3]);
            if (other == kNone) continue;  // a border edge (a conforming mesh has no finer half-edges)
            const auto& o = mTriangles[other].vertices;
            const Vec3 m = (mVertices[o[1]].position - mVertices[o[0]].position)
                               .cross(mVertices[o[2]].position - mVertices[o[0]].position);
            const double mlen = m.norm();
            if (!(mlen > 0.0)) continue;
            const double c = std::clamp(n.dot(m) / (len * mlen), -1.0, 1.0);
            demand = std::max(demand, std::acos(c) / settings.maxDihedralAngle);
        }
    }
    if (settings.maxStrain > 0.0) {
        for (int k = 0; k < 3; ++k) {
            const int j = (k + 1) % 3;
            const double rest = (tri.rest[j] - tri.rest[k]).norm();
            const double strain = std::abs((v[j]->position - v[k]->position).norm() / rest - 1.0);
            demand = std::max(demand, strain / settings.maxStrain);
        }
    }
    if (settings.maxKineticEnergy > 0.0) {
        const double specific =
            (v[0]->velocity.squaredNorm() + v[1]->velocity.squaredNorm() + v[2]->velocity.squaredNorm()) / 6.0;
        demand = std::max(demand, specific / settings.maxKineticEnergy);
    }
    if (settings.proximityDistance > 0.0 && !input.bodyDistance.empty()) {
        double nearest = 1e300;
        for (uint32_t id : tri.vertices) nearest = std::min(nearest, input.bodyDistance[vertexToSim[id]]);
        demand = std::max(demand, settings.proximityDistance / std::max(nearest, 1e-6 * settings.proximityDistance));
    }
    return demand;
}

Result<AdaptStats> GarmentHierarchy::adapt(const RefinementSettings& settings, const AdaptInput& input) {
    if (Status s = settings.validate(); !s) return s;
    if (input.viewProjection) {
        if (!input.viewProjection->allFinite()) return Status::invalidArgument("AdaptInput.viewProjection is not finite");
        if (!(input.viewportWidth > 0.0 && input.viewportHeight > 0.0) || !std::isfinite(input.viewportWidth) ||
            !std::isfinite(input.viewportHeight)) {
            return Status::invalidArgument("AdaptInput.viewportWidth/Height must be finite and > 0 with a view");
        }
    }
    const uint32_t maxLevel = settings.maxLevel ? std::min(settings.maxLevel, mSettings.maxLevel) : mSettings.maxLevel;
    if (settings.minLevel > maxLevel) {
        return Status::invalidArgument("RefinementSettings.minLevel = " + std::to_string(settings.minLevel) +
                                       " is above the hierarchy's maxLevel = " + std::to_string(maxLevel));
    }
    const uint32_t budget = settings.vertexBudget ? settings.vertexBudget : mSettings.vertexBudget;
    ActiveMesh numbering;
    if (settings.proximityDistance > 0.0 && !input.bodyDistance.empty()) {
        numberSimVertices(numbering, false);
        if (input.bodyDistance.size() != numbering.simToVertex.size()) {
            return Status::invalidArgument("AdaptInput.bodyDistance has " + std::to_string(input.bodyDistance.size()) +
                                           " entries; the active mesh has " +
                                           std::to_string(numbering.simToVertex.size()) + " vertices");
        }
        for (std::size_t i = 0; i < input.bodyDistance.size(); ++i) {
            if (std::isnan(input.bodyDistance[i])) {
                return Status::invalidArgument("AdaptInput.bodyDistance[" + std::to_string(i) + "] is NaN");
            }
        }
    }

    // 1. Demand and quiet counters of every active triangle.
    const std::vector<uint32_t> active = activeTriangles();
    std::vector<double> demand(mTriangles.size(), 0.0);
    for (uint32_t t : active) {
        demand[t] = triangleDemand(t, settings, input, numbering.vertexToSim);
        mQuiet[t] = demand[t] < settings.coarsenFraction ? mQuiet[t] + 1 : 0;
    }

    // 2. Refine the most demanding first, within the budget.
    AdaptStats stats;
    const uint32_t opCap = settings.maxOperationsPerFrame ? settings.maxOperationsPerFrame : 0xffffffffu;
    std::vector<std::pair<double, uint32_t>> wanted;
    for (uint32_t t : active) {
        const uint32_t level = mTriangles[t].level;
        if (level < settings.minLevel) {
            wanted.push_back({1e300, t});
        } else if (demand[t] > 1.0 && level < maxLevel) {
            wanted.push_back({demand[t], t});
        }
    }
    std::sort(wanted.begin(), wanted.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    std::vector<uint32_t> split;
    for (const auto& [d, t] : wanted) {
        if (stats.refined >= opCap || (budget && mActiveVertexCount >= budget)) break;
        if (!mTriangles[t].active) continue;
        std::vector<uint32_t> made;
        if (Status s = splitLeaf(t, &made, 0); !s) return s;
        stats.refined += static_cast<uint32_t>(made.size());
        split.insert(split.end(), made.begin(), made.end());
    }
    std::vector<uint8_t> splitNow(mVertices.size(), 0);
    for (uint32_t m : split) splitNow[m] = 1;

    // 3. Merge diamonds whose triangles have all been quiet long enough; then, if still over the
    //    budget, the least demanding diamonds.
    auto childrenOf = [&](uint32_t m, auto&& visit) {
        for (uint32_t d : mVertices[m].diamond) {
            if (d == kNone) continue;
            visit(mTriangles[d].children[0]);
            visit(mTriangles[d].children[1]);
        }
    };
    std::vector<std::pair<double, uint32_t>> mergeable;
    for (uint32_t m : coarsenableVertices()) {
        if (splitNow[m] || mVertices[m].level <= settings.minLevel) continue;
        bool quiet = true;
        double most = 0.0;
        childrenOf(m, [&](uint32_t c) {
            quiet = quiet && mQuiet[c] >= std::max<uint32_t>(settings.quietFrames, 1);
            most = std::max(most, c < demand.size() ? demand[c] : 0.0);
        });
        if (quiet && stats.refined + stats.coarsened < opCap) {
            if (Status s = coarsen(m); !s) return s;
            ++stats.coarsened;
        } else {
            mergeable.push_back({most, m});
        }
    }
    if (budget && mActiveVertexCount > budget) {
        std::sort(mergeable.begin(), mergeable.end());
        for (const auto& [d, m] : mergeable) {
            if (mActiveVertexCount <= budget) break;
            if (!canCoarsen(m)) continue;
            if (Status s = coarsen(m); !s) return s;
            ++stats.coarsened;
        }
    }
    stats.activeVertices = mActiveVertexCount;
    return stats;
}

} // namespace cc::lod
