#include "RestartedWindows.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "crowdcloth/core/Camera.h"
#include "crowdcloth/core/Statistics.h"

namespace cc::detail {
namespace {

constexpr double kDt = 1.0 / 60.0;

struct WorldDeleter {
    void operator()(World* w) const { World::destroy(w); }
};
using WorldPtr = std::unique_ptr<World, WorldDeleter>;

/// [m] root position along +Z at time t: the speed eases in over the first second (smoothstep),
/// so the start is a walker setting off, not a jolt.
double rootZ(const WindowScene& scene, double t) {
    if (t < 1.0) return scene.speed * (t * t * t - 0.5 * t * t * t * t);
    return scene.speed * (0.5 + (t - 1.0));
}

struct StudyWorld {
    WorldPtr world;
    CharacterId walker{};
    GarmentId garment{};
    Status status;
};

/// A World with the scene's walker wearing its garment, cut with `levelCount` levels (0 = the
/// scene's); `level` forced (-1 = the top one), or left to the scheduler with kScheduled.
constexpr int kScheduled = -2;
StudyWorld makeWorld(const WindowScene& scene, const WorldDesc& desc, int level, uint32_t levelCount = 0) {
    if (levelCount == 0) levelCount = scene.levelCount;
    StudyWorld s;
    auto created = World::create(desc);
    if (!created.isOk()) {
        s.status = created.status();
        return s;
    }
    s.world.reset(created.value());
    ClothAssetDesc asset = scene.asset;
    asset.levelCount = levelCount;
    asset.renderLevel = std::max(levelCount - 1, ClothAssetDesc{}.renderLevel);
    auto assetId = s.world->addClothAsset(asset);
    auto body = s.world->addMannequinBody({});
    if (!assetId.isOk() || !body.isOk()) {
        s.status = !assetId.isOk() ? assetId.status() : body.status();
        return s;
    }
    CharacterDesc cd;
    cd.body = body.value();
    cd.clip = scene.clip.c_str();
    auto walker = s.world->addCharacter(cd);
    if (!walker.isOk()) {
        s.status = walker.status();
        return s;
    }
    s.walker = walker.value();
    GarmentDesc gd;
    gd.forceLevel = level == kScheduled ? -1 : level < 0 ? int(levelCount) - 1 : level;
    auto garment = s.world->addGarment(assetId.value(), s.walker, gd);
    s.status = garment.status();
    if (garment.isOk()) s.garment = garment.value();
    return s;
}

/// The study camera at frame f: behind the walker and above, looking at its back.
CameraDesc studyCamera(const WindowScene& scene, int frame) {
    const double z = rootZ(scene, frame * kDt);
    const Eigen::Vector3d target(0.0, 1.1, z);
    const Eigen::Vector3d eye = target + scene.cameraDistance * Eigen::Vector3d(-1.2, 0.4, -2.2).normalized();
    CameraDesc camera;
    lookAt(eye, target, camera.viewportWidth / camera.viewportHeight, camera.viewProjection);
    return camera;
}

lod::SchedulerCamera toScheduler(const CameraDesc& c) {
    lod::SchedulerCamera s;
    for (int k = 0; k < 16; ++k) s.viewProjection(k % 4, k / 4) = c.viewProjection[k];
    s.viewportWidth = c.viewportWidth;
    s.viewportHeight = c.viewportHeight;
    return s;
}

/// Steps frame `frame` (root, camera, step); adds the garment's update time to `ms`.
bool advance(const WindowScene& scene, StudyWorld& s, int frame, double& ms, GarmentStats* stats) {
    const double position[3] = {0.0, 0.0, rootZ(scene, frame * kDt)};
    const CameraDesc camera = studyCamera(scene, frame);
    if (!s.world->setCharacterRoot(s.walker, position, 0.0) || !s.world->setCameras(&camera, 1) ||
        !s.world->step(kDt))
        return false;
    const GarmentStats g = s.world->garmentStats(s.garment).value();
    ms += g.measuredMs;
    if (stats) *stats = g;
    return !g.failed;
}

std::vector<float> renderPositions(const StudyWorld& s) {
    const RenderMeshView m = s.world->renderMesh(s.garment).value();
    return std::vector<float>(m.positions, m.positions + 3 * std::size_t(m.vertexCount));
}

/// Percentile `p` over the windows of one figure of their deviations.
template <typename Figure>
double overWindows(const std::vector<lod::MeshDeviation>& windows, double p, Figure figure) {
    std::vector<double> v;
    v.reserve(windows.size());
    for (const lod::MeshDeviation& w : windows) v.push_back(figure(w));
    return percentile(std::move(v), p);
}

} // namespace

double WindowResult::medianMs() const { return percentile(windowMs, 0.5); }
double WindowResult::medianRmsMm() const {
    return overWindows(windows, 0.5, [](const lod::MeshDeviation& w) { return 1e3 * w.rmsMetres; });
}
double WindowResult::p95MaxMm() const {
    return overWindows(windows, 0.95, [](const lod::MeshDeviation& w) { return 1e3 * w.maxMetres; });
}
double WindowResult::p95MaxPx() const {
    return overWindows(windows, 0.95, [](const lod::MeshDeviation& w) { return w.maxPixels; });
}

WorldDesc studyDesc(uint32_t substeps, uint32_t iterations, double strainLimit) {
    WorldDesc desc;
    desc.maxThreads = 1;
    desc.fixedCostModel = true;
    desc.substeps = substeps;
    desc.solverIterations = iterations;
    desc.strainLimit = strainLimit;
    // The study sweeps the solve's knobs against a reference that runs without self-collision;
    // what self-collision costs is measured apart (cc_crowd --self-collision).
    desc.selfCollision = false;
    return desc;
}

Result<WorldDesc> descGiving(const WorldDesc& base, int level, uint32_t levelCount, WorldDesc::Effort effort) {
    const int below = int(levelCount) - 1 - level;
    WorldDesc desc = base;
    desc.substeps = effort.substeps << ((below + 1) / 2);
    desc.solverIterations = effort.iterations + uint32_t(below);
    const WorldDesc::Effort given = desc.effortAt(uint32_t(level), levelCount);
    if (!desc.validate() || given.substeps != effort.substeps || given.iterations != effort.iterations)
        return Status::invalidArgument("no World desc gives level " + std::to_string(level) + " of " +
                                       std::to_string(levelCount) + " " + std::to_string(effort.substeps) + " x " +
                                       std::to_string(effort.iterations));
    return desc;
}

ReferenceRun recordReference(const WindowScene& scene, const WorldDesc& desc, int level) {
    ReferenceRun run;
    StudyWorld s = makeWorld(scene, desc, level);
    if (!s.status) {
        run.ok = false;
        return run;
    }
    const int frames = int(std::lround(scene.seconds / kDt));
    const int first = int(std::lround(scene.firstWindow / kDt)), length = int(std::lround(scene.window / kDt));
    double ms = 0.0;
    for (int f = 1; f <= frames && run.ok; ++f) {
        run.ok = advance(scene, s, f, ms, nullptr);
        const bool start = f >= first && (f - first) % length == 0 && f + length <= frames;
        const bool end = f > first && (f - first) % length == 0;
        if (end) {
            run.endMeshes.push_back(renderPositions(s));
            run.cameras.push_back(toScheduler(studyCamera(scene, f)));
        }
        if (start) {
            run.startFrames.push_back(f);
            run.snapshots.push_back(s.world->saveState().value());
        }
    }
    run.meanMs = ms / frames;
    return run;
}

std::vector<WindowResult> runWindows(const WindowScene& scene, const ReferenceRun& reference,
                                     const std::vector<WindowConfig>& configs) {
    std::vector<WindowResult> results(configs.size());
    std::vector<StudyWorld> worlds;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        worlds.push_back(makeWorld(scene, configs[c].desc, configs[c].level));
        results[c].ok = worlds.back().status.isOk() && reference.ok;
    }
    const int length = int(std::lround(scene.window / kDt));
    // Window by window across the configurations: a slow minute of a shared machine then falls on
    // every configuration alike instead of on whichever ran in it.
    for (std::size_t k = 0; k < reference.startFrames.size(); ++k)
        for (std::size_t c = 0; c < configs.size(); ++c) {
            WindowResult& result = results[c];
            StudyWorld& s = worlds[c];
            if (!result.ok) continue;
            const std::vector<uint8_t>& saved = reference.snapshots[k];
            result.ok = s.world->restoreState(saved.data(), saved.size(), RestoreMode::OtherSolver).isOk() &&
                        s.world->setGarmentLevel(s.garment, configs[c].level).isOk();
            GarmentStats stats;
            double ms = 0.0;
            for (int f = reference.startFrames[k] + 1; f <= reference.startFrames[k] + length && result.ok; ++f) {
                result.ok = advance(scene, s, f, ms, &stats);
                result.maxStrain = std::max(result.maxStrain, stats.maxStrain);
            }
            result.windowMs.push_back(ms / length);
            result.vertices = stats.vertexCount;
            result.substeps = stats.substeps;
            result.iterationsPerSubstep = stats.iterations / std::max(1u, stats.substeps);
            const std::vector<float> mesh = renderPositions(s);
            result.windows.push_back(lod::meshDeviation(mesh.data(), reference.endMeshes[k].data(), mesh.size() / 3,
                                                            &reference.cameras[k]));
        }
    return results;
}

WindowResult runWindows(const WindowScene& scene, const ReferenceRun& reference, const WorldDesc& desc, int level) {
    return runWindows(scene, reference, {{desc, level}}).front();
}

int scheduledLevel(const WindowScene& scene, const WorldDesc& desc, uint32_t levelCount) {
    StudyWorld s = makeWorld(scene, desc, kScheduled, levelCount);
    if (!s.status) return -1;
    std::vector<int> updatesAt(levelCount, 0);
    const int frames = int(std::lround(scene.seconds / kDt)), first = int(std::lround(scene.firstWindow / kDt));
    double ms = 0.0;
    GarmentStats stats;
    for (int f = 1; f <= frames; ++f) {
        if (!advance(scene, s, f, ms, &stats)) return -1;
        if (f > first && stats.updated && stats.level >= 0 && stats.level < int(levelCount)) ++updatesAt[stats.level];
    }
    return int(std::max_element(updatesAt.begin(), updatesAt.end()) - updatesAt.begin());
}

} // namespace cc::detail
