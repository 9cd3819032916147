// cc_crowd --self-collision: what self-collision costs a garment seen close (issue 10's bar: at
// most the garment's own solve at the same level). Garments that fold onto themselves, at their
// finest level on a walking mannequin 1.3 m from the camera, each stepped twice frame by frame in
// two Worlds, with self-collision and without (interleaved, so both see the machine alike); one
// thread, so every figure is one garment's CPU time.
#include <cstdio>
#include <string>
#include <vector>

#include "Studies.h"

namespace crowd {
namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr double kSpeed = 1.2;  // [m/s] the walk along +Z

struct Case {
    const char* name;
    cc::GarmentKind kind;
    cc::GarmentCut cut;
};

/// One World: a walking mannequin in one garment forced to its finest level.
struct Scene {
    WorldPtr world;
    cc::CharacterId character;
    cc::GarmentId garment;
};

cc::Result<Scene> makeScene(const Case& c, bool selfCollision) {
    cc::WorldDesc desc;
    desc.maxThreads = 1;
    desc.fixedCostModel = true;
    desc.selfCollision = selfCollision;
    auto created = cc::World::create(desc);
    if (!created.isOk()) return created.status();
    Scene scene{WorldPtr(created.value()), {}, {}};
    cc::ClothAssetDesc asset;
    asset.kind = c.kind;
    asset.cut = c.cut;
    auto assetId = scene.world->addClothAsset(asset);
    auto body = scene.world->addMannequinBody({});
    if (!assetId.isOk()) return assetId.status();
    if (!body.isOk()) return body.status();
    cc::CharacterDesc character;
    character.body = body.value();
    auto characterId = scene.world->addCharacter(character);
    if (!characterId.isOk()) return characterId.status();
    scene.character = characterId.value();
    cc::GarmentDesc garment;
    garment.forceLevel = int32_t(asset.levelCount) - 1;
    auto garmentId = scene.world->addGarment(assetId.value(), scene.character, garment);
    if (!garmentId.isOk()) return garmentId.status();
    scene.garment = garmentId.value();
    return scene;
}

cc::Status stepScene(Scene& scene, int frame) {
    const double z = kSpeed * frame * kDt;
    const double root[3] = {0.0, 0.0, z};
    if (cc::Status s = scene.world->setCharacterRoot(scene.character, root, 0.0); !s) return s;
    cc::CameraDesc camera;  // in front and to the side, as close as a dialogue shot
    lookAt(Eigen::Vector3d(-0.6, 1.0, z + 1.1), Eigen::Vector3d(0.0, 0.8, z), 16.0 / 9.0, camera.viewProjection);
    if (cc::Status s = scene.world->setCameras(&camera, 1); !s) return s;
    return scene.world->step(kDt);
}

double mean(const std::vector<double>& v) {
    double sum = 0.0;
    for (double x : v) sum += x;
    return v.empty() ? 0.0 : sum / double(v.size());
}

} // namespace

int runSelfCollisionStudy(double seconds) {
    const Case cases[] = {{"circle_skirt", cc::GarmentKind::Skirt, cc::GarmentCut::Circle},
                          {"dress", cc::GarmentKind::Dress, cc::GarmentCut::ALine},
                          {"half_circle_cape", cc::GarmentKind::Cape, cc::GarmentCut::Circle},
                          {"poncho", cc::GarmentKind::Poncho, cc::GarmentCut::Straight}};
    const int warmup = 30, frames = std::max(1, int(seconds / kDt));
    std::printf("# self-collision's cost per frame against the garment's own solve: finest level, walking mannequin,\n"
                "# camera 1.3 m away, one thread, %d frames at 60 Hz after %d; means per updated frame [ms]\n",
                frames, warmup);
    std::printf("%-18s %9s %9s %9s %9s %9s %9s %8s\n", "garment", "vertices", "solve", "self", "self/solve", "body",
                "added", "frames");
    double worst = 0.0;
    for (const Case& c : cases) {
        auto on = makeScene(c, true);
        auto off = makeScene(c, false);
        if (!on.isOk() || !off.isOk()) {
            std::fprintf(stderr, "self-collision study: %s\n", (on.isOk() ? off : on).status().message().c_str());
            return 1;
        }
        std::vector<double> solve, self, body, totalOn, totalOff;
        uint32_t vertices = 0;
        int selfFrames = 0;
        for (int f = 1; f <= warmup + frames; ++f) {
            for (Scene* scene : {&on.value(), &off.value()}) {
                if (cc::Status s = stepScene(*scene, f); !s) {
                    std::fprintf(stderr, "self-collision study: %s, frame %d: %s\n", c.name, f, s.message().c_str());
                    return 1;
                }
            }
            const cc::GarmentStats a = on.value().world->garmentStats(on.value().garment).value();
            const cc::GarmentStats b = off.value().world->garmentStats(off.value().garment).value();
            if (f <= warmup || !a.updated || !b.updated) continue;
            vertices = a.vertexCount;
            selfFrames += a.selfCollision;
            solve.push_back(a.measuredMs - a.collisionMs);
            self.push_back(a.selfCollisionMs);
            body.push_back(a.collisionMs - a.selfCollisionMs);
            totalOn.push_back(a.measuredMs);
            totalOff.push_back(b.measuredMs);
        }
        const double ratio = mean(self) / std::max(1e-9, mean(solve));
        worst = std::max(worst, ratio);
        // `added`: the whole update's time with self-collision less without it (the planes also
        // lengthen the solve's contact lists and the body's corrections); two diverging runs, so
        // it carries their difference in motion too.
        std::printf("%-18s %9u %9.2f %9.2f %9.2f %9.2f %9.2f %5d/%zu\n", c.name, vertices, mean(solve), mean(self), ratio,
                    mean(body), mean(totalOn) - mean(totalOff), selfFrames, self.size());
        std::printf("BAR selfcollision garment=%s vertices=%u self_ms=%.3f solve_ms=%.3f ratio=%.2f added_ms=%.3f "
                    "self_frames=%d/%zu\n",
                    c.name, vertices, mean(self), mean(solve), ratio, mean(totalOn) - mean(totalOff), selfFrames,
                    self.size());
    }
    std::printf("BAR selfcollision worst_ratio=%.2f goal=1.00\n", worst);
    return 0;
}

} // namespace crowd
