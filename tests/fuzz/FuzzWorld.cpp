// Fuzz target: any sequence of World calls with any values (NaN, infinities, huge, negative,
// stale handles, broken meshes) is refused with a message or carried out; never a crash, a hang,
// a leak or a non-finite render mesh; and the World's snapshot, damaged, is refused or taken, and
// restores the World exactly when whole. Built for libFuzzer with -DCC_BUILD_FUZZERS=ON (clang), and
// always as cc_fuzz_world_replay, which runs the committed corpus (tests/fuzz/corpus) in CTest.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "crowdcloth/World.h"
#include "FuzzInput.h"
#include "SnapshotStream.h"  // engine/src: the header layout

namespace {

using cc::fuzz::Input;

/// Sizes that keep one input fast: a fuzzer that cooks a 10^6-vertex garment learns nothing.
bool affordable(const cc::ClothAssetDesc& d) {
    return d.cellSize >= 0.08 && d.levelCount <= 4 && d.renderLevel <= 4 && d.width <= 3.0 && d.length <= 3.0 &&
           d.hemWidth <= 8.0;
}

void checkFinite(const cc::RenderMeshView& m, const char* what) {
    for (uint32_t i = 0; i < 3 * m.vertexCount; ++i)
        if (!std::isfinite(m.positions[i]) || !std::isfinite(m.normals[i])) {
            std::fprintf(stderr, "FuzzWorld: %s has a non-finite render vertex %u\n", what, i / 3);
            std::abort();
        }
}

/// The World saved, a copy with one byte changed (its checksum made to match, so the reader
/// meets it) restored: refused by name or taken, never a crash; then the good copy restored
/// puts the World back where it was.
void checkSnapshot(cc::World& world, Input& in) {
    auto saved = world.saveState();
    if (!saved.isOk()) return;
    const std::vector<uint8_t> bytes = std::move(saved).value();
    const uint64_t hash = world.stateHash();
    constexpr std::size_t kHeader = cc::detail::kSnapshotHeaderBytes;
    std::vector<uint8_t> bad = bytes;
    if (bad.size() > kHeader) {
        bad[kHeader + in.u32() % (bad.size() - kHeader)] ^= uint8_t(1 + in.byte() % 255);
        cc::detail::sealSnapshot(bad);
    }
    if (const cc::Status s = world.restoreState(bad.data(), bad.size()); !s && s.message().find("restoreState") != 0) {
        std::fprintf(stderr, "FuzzWorld: a refused snapshot's message does not name the call: %s\n", s.message().c_str());
        std::abort();
    }
    if (const cc::Status s = world.restoreState(bytes.data(), bytes.size()); !s || world.stateHash() != hash) {
        std::fprintf(stderr, "FuzzWorld: the World's own snapshot did not restore it: %s\n", s.message().c_str());
        std::abort();
    }
}

void run(Input& in) {
    cc::WorldDesc wd;
    wd.fixedCostModel = true;
    wd.maxThreads = 1 + in.byte() % 2;
    if (in.byte() % 4 == 0) wd.frameBudgetMs = in.real(0.1, 50.0);
    if (in.byte() % 4 == 0) wd.gravity[in.byte() % 3] = in.real(-20.0, 20.0);
    if (in.byte() % 4 == 0) wd.substeps = in.u32() % 80;
    if (in.byte() % 4 == 0) wd.strainLimit = in.real(0.0, 1.0);
    auto created = cc::World::create(wd);
    if (!created.isOk()) return;
    cc::World* world = created.value();
    std::vector<cc::AssetId> assets;
    std::vector<cc::BodyId> bodies;
    std::vector<cc::CharacterId> characters;
    std::vector<cc::GarmentId> garments;
    auto pick = [&](const auto& ids) { return ids.empty() ? decltype(ids[0]){} : ids[in.byte() % ids.size()]; };
    for (int op = 0; op < 40 && !in.empty(); ++op) {
        switch (in.byte() % 10) {
        case 0: {
            cc::ClothAssetDesc d;
            d.kind = cc::GarmentKind(in.byte() % 5);
            d.cut = cc::GarmentCut(in.byte() % 4);
            d.levelCount = 1 + in.byte() % 4;
            d.renderLevel = d.levelCount - 1 + in.byte() % 2;
            if (in.byte() % 2) d.width = in.real(0.0, 3.0);
            if (in.byte() % 2) d.length = in.real(0.0, 3.0);
            if (in.byte() % 2) d.hemWidth = in.real(0.0, 8.0);
            if (in.byte() % 3 == 0) d.cellSize = in.real(0.08, 1.0);
            if (in.byte() % 3 == 0) d.stretchStiffness = in.real(1.0, 1e7);
            if (in.byte() % 3 == 0) d.bendStiffness = in.real(0.0, 1.0);
            if (in.byte() % 3 == 0) d.thickness = in.real(0.0, 0.1);
            if (in.byte() % 3 == 0) d.velocityDamping = in.real(0.0, 100.0);
            if (!affordable(d)) break;
            if (auto a = world->addClothAsset(d); a.isOk()) assets.push_back(a.value());
            break;
        }
        case 1: {
            cc::MannequinDesc m;
            m.height = in.real(1.0, 2.5);
            m.shoulderWidth = in.real(0.25, 0.6);
            m.limbGirth = in.real(0.6, 1.6);
            if (auto b = world->addMannequinBody(m); b.isOk()) bodies.push_back(b.value());
            break;
        }
        case 2: {  // a host-skinned body with any mesh
            const uint32_t n = in.byte() % 12, t = in.byte() % 12;
            std::vector<float> v(3 * n);
            for (float& x : v) x = float(in.real(-1.0, 1.0));
            std::vector<uint32_t> tri(3 * t);
            for (uint32_t& i : tri) i = in.byte() % (n + 2);
            if (auto b = world->addSkinnedBody(v.data(), n, 12, tri.data(), t); b.isOk()) bodies.push_back(b.value());
            break;
        }
        case 3: {
            cc::CharacterDesc c;
            c.body = pick(bodies);
            const char* clips[] = {"walk", "run", "idle", "", "no such clip"};
            c.clip = clips[in.byte() % 5];
            c.clipTime = in.real(0.0, 10.0);
            c.playbackRate = in.real(0.0, 10.0);
            c.position[0] = in.real(-50.0, 50.0);
            c.yaw = in.real(-7.0, 7.0);
            if (auto id = world->addCharacter(c); id.isOk()) characters.push_back(id.value());
            break;
        }
        case 4: {
            cc::GarmentDesc g;
            g.importance = in.real(0.1, 10.0);
            g.forceLevel = int32_t(in.byte() % 6) - 2;
            g.inertiaScale = in.real(0.0, 2.0);
            if (auto id = world->addGarment(pick(assets), pick(characters), g); id.isOk()) garments.push_back(id.value());
            break;
        }
        case 5: {
            const double p[3] = {in.real(-50.0, 50.0), in.real(-1.0, 1.0), in.real(-50.0, 50.0)};
            (void)world->setCharacterRoot(pick(characters), p, in.real(-7.0, 7.0));
            break;
        }
        case 6: {
            const uint32_t n = in.byte() % 12;
            std::vector<float> v(3 * n);
            for (float& x : v) x = float(in.real(-1.0, 1.0));
            (void)world->setCharacterSkinnedVertices(pick(characters), v.data(), n, 12);
            break;
        }
        case 7: {
            cc::CameraDesc camera;
            for (double& x : camera.viewProjection) x = in.byte() % 2 ? in.real(-2.0, 2.0) : x;
            camera.viewportWidth = in.real(1.0, 4000.0);
            (void)world->setCameras(&camera, in.byte() % 2);
            break;
        }
        case 8: (void)world->removeGarment(pick(garments)); break;
        default:
            for (int s = 0, steps = 1 + in.byte() % 4; s < steps; ++s)
                (void)world->step(in.byte() % 8 ? 1.0 / 60.0 : in.real(0.0, 0.2));
            break;
        }
    }
    for (cc::GarmentId g : garments)
        if (auto mesh = world->renderMesh(g); mesh.isOk()) checkFinite(mesh.value(), "a garment");
    for (cc::CharacterId c : characters)
        if (auto mesh = world->characterMesh(c); mesh.isOk()) checkFinite(mesh.value(), "a body");
    (void)world->statsJson();
    checkSnapshot(*world, in);
    cc::World::destroy(world);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    Input in(data, size);
    run(in);
    return 0;
}
