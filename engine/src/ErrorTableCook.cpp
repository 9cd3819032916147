// Cooking an error table (crowdcloth/ErrorTable.h): the design on the built-in mannequin, walking
// and running, measured level by level against a reference one level above the finest (converged
// in time, not yet in space: README) in windows restarted from the reference's state
// (RestartedWindows.h, as cc_crowd --tradeoff).
#include <algorithm>
#include <cmath>
#include <string>

#include "RestartedWindows.h"
#include "crowdcloth/ErrorTable.h"
#include "crowdcloth/World.h"
#include "crowdcloth/core/BoundingSphere.h"
#include "crowdcloth/core/Statistics.h"

namespace cc {
namespace {

/// [m] bounding radius about the centroid of xyz float positions: the garment's size the errors
/// are divided by (as CookedAsset::radius, taken at the window's end).
double boundingRadius(const std::vector<float>& xyz) {
    std::vector<Vec3> points(xyz.size() / 3);
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    return centroidSphere(points).radius;
}

} // namespace

Result<ErrorTable> cookErrorTable(const ClothAssetDesc& design, const WorldDesc& world, const ErrorCookDesc& cook) {
    if (Status s = design.validate(); !s) return Status::invalidArgument("cookErrorTable: " + s.message());
    if (Status s = world.validate(); !s) return Status::invalidArgument("cookErrorTable: " + s.message());
    if (Status s = cook.validate(); !s) return Status::invalidArgument("cookErrorTable: " + s.message());
    const uint32_t levels = design.levelCount;
    if (levels + 1 > 10)
        return Status::invalidArgument("cookErrorTable: the reference runs a level above the finest: levelCount must be < 10");

    ErrorTable table;
    table.key = errorTableKey(design, world, cook);
    table.cook = cook;
    table.errorPerRadius.assign(std::size_t(levels) * ErrorTable::kMotions, 0.0);
    table.medianErrorPerRadius = table.errorPerRadius;
    const char* clips[ErrorTable::kMotions] = {"walk", "run"};
    for (uint32_t m = 0; m < ErrorTable::kMotions; ++m) {
        detail::WindowScene scene;
        scene.name = clips[m];
        scene.asset = design;
        scene.clip = clips[m];
        scene.speed = table.speeds[m];
        scene.seconds = cook.seconds;
        scene.window = cook.windowSeconds;
        scene.levelCount = levels + 1;
        WorldDesc base = detail::studyDesc(1, 1, world.strainLimit);
        for (int k = 0; k < 3; ++k) base.gravity[k] = world.gravity[k];
        WorldDesc referenceDesc = base;
        referenceDesc.substeps = cook.referenceSubsteps;
        referenceDesc.solverIterations = cook.referenceIterations;
        const detail::ReferenceRun reference = detail::recordReference(scene, referenceDesc);
        if (!reference.ok || reference.startFrames.empty())
            return Status::error(StatusCode::NumericalFailure,
                                 std::string("cookErrorTable: the reference run failed (") + clips[m] + ")");
        // Each level under the effort the World gives it among the design's own levels.
        std::vector<detail::WindowConfig> configs;
        for (uint32_t l = 0; l < levels; ++l) {
            auto desc = detail::descGiving(base, int(l), levels + 1, world.effortAt(l, levels));
            if (!desc.isOk()) return Status::invalidArgument("cookErrorTable: " + desc.status().message());
            configs.push_back({desc.value(), int(l)});
        }
        const std::vector<detail::WindowResult> results = detail::runWindows(scene, reference, configs);
        table.windows = uint32_t(reference.startFrames.size());
        for (uint32_t l = 0; l < levels; ++l) {
            const detail::WindowResult& r = results[l];
            if (!r.ok || r.windows.size() != reference.endMeshes.size())
                return Status::error(StatusCode::NumericalFailure, "cookErrorTable: level " + std::to_string(l) +
                                                                       " failed in a window (" + clips[m] + ")");
            std::vector<double> relative;
            for (std::size_t k = 0; k < r.windows.size(); ++k)
                relative.push_back(r.windows[k].rmsMetres / std::max(1e-6, boundingRadius(reference.endMeshes[k])));
            table.errorPerRadius[l * ErrorTable::kMotions + m] = percentile(relative, 0.95);
            table.medianErrorPerRadius[l * ErrorTable::kMotions + m] = percentile(relative, 0.5);
        }
    }
    if (Status s = table.validate(); !s) return s;
    return table;
}

} // namespace cc
