// cc_collision_bench: the per-frame collision cost of one character (issue 3): skinning the
// mannequin's ~5k-triangle body, refitting its Embree scene, and the contact queries of 1-3
// garments (proximity and swept, before and after the solve, as one garment step uses them),
// the capsule-proxy alternative, and a cloth step of the same size for the collision share.
//
//   cc_collision_bench --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/character/SkinnedMesh.h"
#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/BodyContactStage.h"
#include "crowdcloth/collision/CapsuleCollider.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::collision;

namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr uint32_t kRingVertices = 48;  // around a garment tube
constexpr uint32_t kRings = 40;         // along it: 1,920 vertices per garment

// The mannequin running, its body skinned each frame, and garment point sets (tubes around the
// hips, 3 mm off the skin at the bind pose, ringed down the legs) that follow the hips joint.
struct Frame {
    Mannequin mannequin;
    CharacterPose pose;
    int clip = -1;
    std::vector<Vec3> body, bodyNormals;
    std::vector<std::vector<Vec3>> garmentBind, garmentNow, garmentBefore;
    double time = 0.0;

    explicit Frame(int garments) : mannequin(buildMannequin().value()), pose(mannequin.character) {
        clip = mannequin.character.findClip("run");
        const SkinnedMesh& mesh = mannequin.character.body;
        body.resize(mesh.bindPositions.size());
        bodyNormals.resize(body.size());
        const BodyLandmarks& l = mannequin.landmarks;
        for (int g = 0; g < garments; ++g) {
            std::vector<Vec3> points;
            const double flare = 1.0 + 0.05 * g;  // layered garments
            for (uint32_t r = 0; r < kRings; ++r) {
                const double y = l.waistCentre.y() - 0.6 * r / (kRings - 1);
                for (uint32_t k = 0; k < kRingVertices; ++k) {
                    const double a = 2.0 * 3.14159265358979 * k / kRingVertices;
                    points.push_back(Vec3(l.hipCentre.x() + flare * (l.hipRadiusX + 0.003) * std::cos(a), y,
                                          l.hipCentre.z() + flare * (l.hipRadiusZ + 0.003) * std::sin(a)));
                }
            }
            garmentBind.push_back(points);
        }
        garmentNow = garmentBefore = garmentBind;
        advance();
    }

    // The next frame: pose, skin, and move the garments with the hips joint.
    void advance() {
        time += kDt;
        (void)pose.evaluate(mannequin.character, clip, time, ClipWrap::Loop);
        (void)skinVertices(mannequin.character.body, pose.skinMatrices(), body, bodyNormals);
        const Mat4& hips = pose.skinMatrices()[int(MannequinJoint::Hips)];
        for (std::size_t g = 0; g < garmentNow.size(); ++g) {
            garmentBefore[g] = garmentNow[g];
            for (std::size_t i = 0; i < garmentBind[g].size(); ++i) {
                garmentNow[g][i] = (hips * garmentBind[g][i].homogeneous()).head<3>();
            }
        }
    }
};

std::unique_ptr<CollisionDevice> device() { return CollisionDevice::create({}).value(); }

BodyContactSettings contactSettings() {
    BodyContactSettings s;
    s.query.thickness = 0.004;
    s.query.margin = 0.004;
    s.query.parallel.maxThreads = 1;  // one garment per thread in the engine
    return s;
}

void BM_SkinOnly(benchmark::State& state) {
    Frame frame(1);
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        frame.advance();
        benchmark::DoNotOptimize(frame.body.data());
    }
    state.counters["triangles"] = double(frame.mannequin.character.body.triangles.size());
}

void BM_SkinAndRefit(benchmark::State& state) {
    Frame frame(1);
    auto dev = device();
    auto body = BodyCollider::create(*dev, frame.mannequin.character.body.triangles, frame.body).value();
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        frame.advance();
        if (!body->update(frame.body, kDt)) state.SkipWithError("update failed");
    }
    state.counters["rebuilds"] = double(body->stats().rebuilds);
    state.counters["refits"] = double(body->stats().refits);
}

// One frame of one character: skin, refit, and for each garment the contact stage twice (before
// the solve: still cloth against the moving body; after: the cloth's own motion), proximity only
// or with the swept test.
void BM_CharacterFrame(benchmark::State& state) {
    const int garments = int(state.range(0));
    const bool continuous = state.range(1) != 0;
    Frame frame(garments);
    auto dev = device();
    auto body = BodyCollider::create(*dev, frame.mannequin.character.body.triangles, frame.body).value();
    BodyContactSettings settings = contactSettings();
    settings.continuous = continuous;
    BodyContactStage stage;
    std::vector<Contact> contacts;
    const std::vector<const Collider*> colliders{body.get()};
    double contactCount = 0;
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        frame.advance();
        if (!body->update(frame.body, kDt)) state.SkipWithError("update failed");
        for (int g = 0; g < garments; ++g) {
            (void)stage.gather(colliders, frame.garmentBefore[g], frame.garmentBefore[g], settings, contacts);
            (void)stage.gather(colliders, frame.garmentBefore[g], frame.garmentNow[g], settings, contacts);
            contactCount += double(contacts.size());
        }
    }
    state.counters["cloth_vertices"] = double(garments * kRings * kRingVertices);
    state.counters["contacts_per_garment"] = contactCount / double(state.iterations()) / garments;
}

// The same queries against the mannequin's fitted capsules instead of the mesh.
void BM_CharacterFrameCapsules(benchmark::State& state) {
    const int garments = int(state.range(0));
    Frame frame(garments);
    auto capsulesAt = [&] {
        std::vector<Capsule> out;
        for (const BodyCapsule& c : frame.mannequin.capsules) {
            const Mat4& skin = frame.pose.skinMatrices()[c.joint];
            out.push_back({(skin * c.a.homogeneous()).head<3>(), (skin * c.b.homogeneous()).head<3>(), c.radius});
        }
        return out;
    };
    CapsuleCollider proxies = CapsuleCollider::create(capsulesAt()).value();
    const BodyContactSettings settings = contactSettings();
    BodyContactStage stage;
    std::vector<Contact> contacts;
    const std::vector<const Collider*> colliders{&proxies};
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        frame.advance();
        if (!proxies.update(capsulesAt(), kDt)) state.SkipWithError("update failed");
        for (int g = 0; g < garments; ++g) {
            (void)stage.gather(colliders, frame.garmentBefore[g], frame.garmentBefore[g], settings, contacts);
            (void)stage.gather(colliders, frame.garmentBefore[g], frame.garmentNow[g], settings, contacts);
        }
    }
    state.counters["capsules"] = double(frame.mannequin.capsules.size());
}

// A cloth step of about the garment's size (44 x 44 squares = 2,025 vertices, implicit PCG,
// one thread), for the collision share of a garment step.
void BM_ClothStepSameSize(benchmark::State& state) {
    RectanglePanel panel;
    panel.columns = panel.rows = 44;
    const ClothMesh mesh = panel.build().value();
    cloth::SimulationSettings settings;
    settings.parallel.maxThreads = 1;
    auto sim = cloth::ClothSimulation::create(mesh, cloth::ClothMaterial{}, settings).value();
    for (uint32_t i = 0; i <= panel.columns; i += panel.columns) {
        const uint32_t v = panel.vertexIndex(i, panel.rows);
        (void)sim->constraints().pin(v, mesh.positions[v]);
    }
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        if (!sim->step(kDt)) state.SkipWithError("step failed");
    }
    state.counters["cloth_vertices"] = double(mesh.vertexCount());
}

} // namespace

BENCHMARK(BM_SkinOnly)->Unit(benchmark::kMicrosecond)->MinTime(0.2);
BENCHMARK(BM_SkinAndRefit)->Unit(benchmark::kMicrosecond)->MinTime(0.2);
BENCHMARK(BM_CharacterFrame)
    ->ArgNames({"garments", "continuous"})
    ->Args({1, 0})->Args({1, 1})->Args({2, 1})->Args({3, 1})
    ->Unit(benchmark::kMicrosecond)->MinTime(0.3);
BENCHMARK(BM_CharacterFrameCapsules)->ArgName("garments")->Arg(1)->Arg(3)->Unit(benchmark::kMicrosecond)->MinTime(0.2);
BENCHMARK(BM_ClothStepSameSize)->Unit(benchmark::kMicrosecond)->MinTime(0.3);

BENCHMARK_MAIN();
