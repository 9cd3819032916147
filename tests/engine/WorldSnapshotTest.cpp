// World snapshots: a crowd saved mid-run and restored into a fresh World continues bit for bit
// (levels, schedule, update phases, colliders' sweeps, sleeping, handles); a truncated, corrupted,
// foreign or mismatched snapshot is refused by name and leaves the World as it was.

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "SnapshotStream.h"
#include "crowdcloth/lod/ScreenError.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr int kSnapshotFrame = 45;
constexpr int kLastFrame = 105;
constexpr int kCrowd = 12;

struct WorldDeleter {
    void operator()(World* w) const { World::destroy(w); }
};
using WorldPtr = std::unique_ptr<World, WorldDeleter>;

WorldDesc sceneDesc(uint32_t threads) {
    WorldDesc desc;
    desc.maxThreads = threads;
    desc.fixedCostModel = true;  // with budgetThreads: the same schedule on any thread count
    desc.budgetThreads = 1;
    desc.frameBudgetMs = 2.0;    // tight: garments at several levels and update rates
    desc.selfCollision = true;   // for the garments the camera sees largest
    return desc;
}

/// A host-skinned body's frames: a walking mannequin skinned in a helper World (world space).
struct HostFrames {
    std::vector<float> bind;
    std::vector<uint32_t> triangles;
    std::vector<std::vector<float>> frames;  ///< [frame] xyz per vertex
};

const HostFrames& hostFrames() {
    static const HostFrames frames = [] {
        HostFrames f;
        WorldPtr helper(World::create({}).value());
        CharacterDesc c;
        c.body = helper->addMannequinBody({}).value();
        const CharacterId walker = helper->addCharacter(c).value();
        auto copy = [&] {
            const RenderMeshView m = helper->characterMesh(walker).value();
            return std::vector<float>(m.positions, m.positions + 3 * std::size_t(m.vertexCount));
        };
        f.bind = copy();
        const RenderMeshView m = helper->characterMesh(walker).value();
        f.triangles.assign(m.indices, m.indices + 3 * std::size_t(m.triangleCount));
        f.frames.push_back(f.bind);
        for (int frame = 1; frame <= kLastFrame; ++frame) {
            EXPECT_TRUE(helper->step(kDt).isOk());
            f.frames.push_back(copy());
        }
        return f;
    }();
    return frames;
}

/// The cooked layer, added to the saving and the restoring World alike.
struct Cooked {
    AssetId cape, skirt;
    BodyId bodies[2];
    BodyId host;
};

Cooked addCooked(World& world) {
    Cooked s;
    ClothAssetDesc cape;
    cape.levelCount = 4;
    cape.renderLevel = 3;
    s.cape = world.addClothAsset(cape).value();
    ClothAssetDesc skirt;
    skirt.kind = GarmentKind::Skirt;
    skirt.levelCount = 4;
    skirt.renderLevel = 3;
    s.skirt = world.addClothAsset(skirt).value();
    MannequinDesc tall;
    tall.height = 1.9;
    s.bodies[0] = world.addMannequinBody({}).value();
    s.bodies[1] = world.addMannequinBody(tall).value();
    const HostFrames& f = hostFrames();
    s.host = world.addSkinnedBody(f.bind.data(), uint32_t(f.bind.size() / 3), 0, f.triangles.data(),
                                  uint32_t(f.triangles.size() / 3))
                 .value();
    return s;
}

/// The crowd and what happens to it: joins and leaves (slots reused, generations bumped), a
/// garment swapped, a teleport, a playback rate change, a camera closing in. Applied before the
/// step of `frame`, from handles only, so both runs get the same inputs.
struct Crowd {
    std::vector<CharacterId> characters;  ///< by role; removed ones stay stale
    std::vector<GarmentId> garments;
    CharacterId late{};
    CharacterId hostCharacter{};
};

/// Where character i walks at time t [s]; number 9 stands still behind the camera (it sleeps).
Vec3 rootOf(int i, double t) {
    if (i == 9) return Vec3(0.0, 0.0, 25.0);
    const int row = i / 4; // four to a row
    return Vec3(1.2 * (i % 4) - 1.5 + 0.6 * t, 0.0, -1.6 * row);
}

void addWalker(World& world, const Cooked& s, Crowd& run, int i) {
    CharacterDesc c;
    c.body = s.bodies[i % 2];
    c.clipTime = 0.11 * i;
    c.playbackRate = i == 9 ? 0.0 : 1.0;
    const Vec3 p = rootOf(i, 0.0);
    for (int k = 0; k < 3; ++k) c.position[k] = p[k];
    c.yaw = 0.5 * kPi;
    const CharacterId id = world.addCharacter(c).value();
    run.characters[i] = id;
    run.garments[i] = world.addGarment(i % 2 ? s.skirt : s.cape, id, {}).value();
}

void populate(World& world, const Cooked& s, Crowd& run) {
    run.characters.resize(kCrowd);
    run.garments.resize(kCrowd);
    for (int i = 0; i < kCrowd - 1; ++i) addWalker(world, s, run, i);
    CharacterDesc c;
    c.body = s.host;
    run.hostCharacter = world.addCharacter(c).value();
    run.characters[kCrowd - 1] = run.hostCharacter;
    // The host's body is a mannequin's mesh: its landmarks are measured from the geometry.
    // Nearest the camera at the end, and weighted so the tight budget refines it to the levels
    // that self-collide once it is seen large.
    GarmentDesc important;
    important.importance = 20.0;
    run.garments[kCrowd - 1] = world.addGarment(s.cape, run.hostCharacter, important).value();
}

void events(World& world, const Cooked& s, Crowd& run, int frame) {
    const double t = frame * kDt;
    if (frame == 8) {
        ASSERT_TRUE(world.removeCharacter(run.characters[3]).isOk());
        ASSERT_TRUE(world.removeCharacter(run.characters[7]).isOk());
    }
    if (frame == 9) addWalker(world, s, run, 7), addWalker(world, s, run, 3);
    if (frame == 20) {
        ASSERT_TRUE(world.removeGarment(run.garments[4]).isOk());
        run.garments[4] = world.addGarment(s.skirt, run.characters[4], {}).value();
    }
    if (frame == 40) {
        ASSERT_TRUE(world.setCharacterPlaybackRate(run.characters[5], 0.5).isOk());
    }
    if (frame == 60) {
        CharacterDesc c;
        c.body = s.bodies[0];
        c.position[2] = 2.0;
        run.late = world.addCharacter(c).value();
        ASSERT_TRUE(world.addGarment(s.cape, run.late, {}).isOk());
    }
    if (frame == 75) {
        ASSERT_TRUE(world.removeCharacter(run.characters[0]).isOk());
    }
    for (int i = 0; i < kCrowd - 1; ++i) {
        if ((i == 0 && frame >= 75) || ((i == 3 || i == 7) && frame == 8)) continue;  // gone
        // Character 2 jumps 3 m at frame 30 (a teleport: 180 m/s).
        const Vec3 p = rootOf(i, t) + Vec3(i == 2 && frame >= 30 ? 3.0 : 0.0, 0.0, 0.0);
        const double position[3] = {p.x(), p.y(), p.z()};
        ASSERT_TRUE(world.setCharacterRoot(run.characters[i], position, 0.5 * kPi).isOk());
    }
    const std::vector<float>& host = hostFrames().frames[frame];
    ASSERT_TRUE(world.setCharacterSkinnedVertices(run.hostCharacter, host.data(), uint32_t(host.size() / 3), 0).isOk());
    const double a = std::min(1.0, t / (kLastFrame * kDt));
    const Vec3 eye = Vec3(0.5, 1.6, 9.0) * (1.0 - a) + Vec3(0.5, 1.3, 1.2) * a;
    const CameraDesc camera = test::cameraLookingAt(eye, Vec3(0.5, 1.0, -2.0));
    ASSERT_TRUE(world.setCameras(&camera, 1).isOk());
}

/// What a frame left behind, to compare the two runs by.
struct FrameRecord {
    uint64_t hash = 0;
    uint32_t updated = 0, asleep = 0, levelSwitches = 0, failed = 0;
    std::vector<int32_t> levels;
    std::vector<uint32_t> intervals;
    std::vector<uint32_t> collision;
    std::vector<uint8_t> self;

    bool operator==(const FrameRecord& o) const {
        return hash == o.hash && updated == o.updated && asleep == o.asleep && levelSwitches == o.levelSwitches &&
               failed == o.failed && levels == o.levels && intervals == o.intervals && collision == o.collision &&
               self == o.self;
    }
};

FrameRecord record(World& world, const Crowd& run) {
    FrameRecord r;
    r.hash = world.stateHash();
    const FrameStats& fs = world.frameStats();
    r.updated = fs.updated, r.asleep = fs.asleep, r.levelSwitches = fs.levelSwitches, r.failed = fs.failed;
    for (GarmentId g : run.garments) {
        const auto stats = world.garmentStats(g);
        if (!stats.isOk()) continue;  // left with its character
        r.levels.push_back(stats.value().level);
        r.intervals.push_back(stats.value().updateInterval);
        r.collision.push_back(uint32_t(stats.value().collision));
        r.self.push_back(stats.value().selfCollision);
    }
    return r;
}

std::vector<float> renderBytes(World& world, const Crowd& run) {
    std::vector<float> all;
    for (GarmentId g : run.garments) {
        const auto mesh = world.renderMesh(g);
        if (!mesh.isOk()) continue;
        all.insert(all.end(), mesh.value().positions, mesh.value().positions + 3 * std::size_t(mesh.value().vertexCount));
        all.insert(all.end(), mesh.value().normals, mesh.value().normals + 3 * std::size_t(mesh.value().vertexCount));
    }
    return all;
}

/// The saved run up to the snapshot: its world, handles and snapshot bytes.
struct Saved {
    WorldPtr world;
    Cooked setup;
    Crowd run;
    std::vector<uint8_t> bytes;
};

Saved runToSnapshot() {
    Saved s;
    s.world.reset(World::create(sceneDesc(2)).value());
    s.setup = addCooked(*s.world);
    populate(*s.world, s.setup, s.run);
    for (int frame = 1; frame <= kSnapshotFrame; ++frame) {
        events(*s.world, s.setup, s.run, frame);
        EXPECT_TRUE(s.world->step(kDt).isOk());
    }
    auto bytes = s.world->saveState();
    EXPECT_TRUE(bytes.isOk()) << bytes.status().message();
    if (bytes.isOk()) s.bytes = std::move(bytes).value();
    return s;
}

TEST(WorldSnapshot, ARestoredCrowdContinuesBitForBitWithTheSameHandles) {
    Saved saved = runToSnapshot();
    ASSERT_FALSE(saved.bytes.empty());
    // The restoring World: the same desc on another thread count, the same assets and bodies.
    WorldPtr restored(World::create(sceneDesc(1)).value());
    const Cooked setup = addCooked(*restored);
    const Status s = restored->restoreState(saved.bytes.data(), saved.bytes.size());
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(restored->stateHash(), saved.world->stateHash());
    EXPECT_EQ(restored->frameStats().frame, saved.world->frameStats().frame);
    EXPECT_EQ(renderBytes(*restored, saved.run), renderBytes(*saved.world, saved.run)) << "render meshes as saved";
    // Saved again at once, it gives the same bytes.
    EXPECT_EQ(restored->saveState().value(), saved.bytes);

    Crowd run = saved.run;  // the host's handles are valid in the restored World
    bool selfCollided = false, meshCollided = false, slept = false, switched = false;
    for (int frame = kSnapshotFrame + 1; frame <= kLastFrame; ++frame) {
        events(*saved.world, saved.setup, saved.run, frame);
        events(*restored, setup, run, frame);
        ASSERT_TRUE(saved.world->step(kDt).isOk());
        ASSERT_TRUE(restored->step(kDt).isOk());
        const FrameRecord a = record(*saved.world, saved.run), b = record(*restored, run);
        ASSERT_TRUE(a == b) << "frame " << frame << ": hash " << a.hash << " vs " << b.hash << ", updated "
                            << a.updated << " vs " << b.updated;
        if (frame == 60) {
            EXPECT_EQ(run.late.index1, saved.run.late.index1);
            EXPECT_EQ(run.late.generation, saved.run.late.generation);
        }
        for (std::size_t k = 0; k < a.levels.size(); ++k) {
            selfCollided |= a.self[k] != 0;
            meshCollided |= a.collision[k] >= uint32_t(CollisionKind::Mesh);
            slept |= a.intervals[k] == 0;
        }
        switched |= a.levelSwitches > 0;
        EXPECT_EQ(a.failed, 0u) << "frame " << frame;
    }
    EXPECT_EQ(renderBytes(*restored, run), renderBytes(*saved.world, saved.run));
    // The run exercised what a snapshot must carry.
    EXPECT_TRUE(meshCollided) << "no garment met the body mesh";
    EXPECT_TRUE(switched) << "no level switch after the snapshot";
    EXPECT_TRUE(selfCollided) << "no garment self-collided";
    EXPECT_TRUE(slept) << "no garment slept";
}

/// Restoring `bytes` into a World that is mid-run fails with a message containing `expected`, and
/// the World goes on as if nothing had been tried.
void expectRefused(World& world, const std::vector<uint8_t>& bytes, const std::string& expected, const char* what) {
    const uint64_t hash = world.stateHash();
    const Status s = world.restoreState(bytes.data(), bytes.size());
    ASSERT_FALSE(s.isOk()) << what;
    EXPECT_EQ(s.code(), StatusCode::InvalidArgument) << what;
    EXPECT_NE(s.message().find("restoreState"), std::string::npos) << what << ": " << s.message();
    EXPECT_NE(s.message().find(expected), std::string::npos) << what << ": " << s.message();
    EXPECT_EQ(world.stateHash(), hash) << what;
}

std::vector<uint8_t> withChecksum(std::vector<uint8_t> bytes) {
    detail::sealSnapshot(bytes);
    return bytes;
}

TEST(WorldSnapshot, TruncatedCorruptedForeignAndMismatchedSnapshotsAreRefusedByName) {
    Saved saved = runToSnapshot();
    ASSERT_GT(saved.bytes.size(), 64u);
    World& world = *saved.world;
    const std::vector<uint8_t>& good = saved.bytes;
    for (std::size_t size : {std::size_t(0), std::size_t(7), std::size_t(31), std::size_t(32), good.size() / 2, good.size() - 1})
        expectRefused(world, std::vector<uint8_t>(good.begin(), good.begin() + size),
                      size < 32 ? "too short" : "truncated", "truncated");
    std::vector<uint8_t> padded = good;
    padded.push_back(0);
    expectRefused(world, padded, "padded", "padded");
    std::vector<uint8_t> flipped = good;
    flipped[good.size() / 3] ^= 0x10;
    expectRefused(world, flipped, "corrupted", "a flipped bit");
    std::mt19937 random(7);
    std::vector<uint8_t> noise(good.size());
    for (uint8_t& b : noise) b = uint8_t(random());
    expectRefused(world, noise, "not a crowdcloth World snapshot", "random bytes");
    std::vector<uint8_t> later = good;
    later[8] = 99;
    expectRefused(world, later, "version 99", "another format version");
    // A forged count, checksum and all: no allocation of its size, an error naming the section.
    std::vector<uint8_t> forged = good;
    const uint64_t huge = 1ull << 60;
    std::memcpy(forged.data() + detail::kSnapshotHeaderBytes + 4, &huge, 8);  // the WorldDesc field count
    expectRefused(world, withChecksum(forged), "runs past the end", "a forged count");
    // Bytes overwritten all through the payload, checksums recomputed: refused or restored, never
    // a crash; a refusal leaves the World as it was (expectRefused checks the hash).
    int refusedCount = 0, restoredCount = 0;
    for (std::size_t at = detail::kSnapshotHeaderBytes; at < good.size(); at += good.size() / 23 + 1) {
        std::vector<uint8_t> bad = good;
        bad[at] ^= 0xff;
        bad = withChecksum(bad);
        const uint64_t hash = world.stateHash();
        const Status s = world.restoreState(bad.data(), bad.size());
        if (s.isOk()) {
            ++restoredCount;  // a value nothing checks (a stat, a velocity): a valid state
            ASSERT_TRUE(world.restoreState(good.data(), good.size()).isOk());
        } else {
            ++refusedCount;
            EXPECT_EQ(world.stateHash(), hash) << "byte " << at << ": " << s.message();
        }
    }
    EXPECT_GT(refusedCount, 0);
    RecordProperty("overwritten_restored", restoredCount);
    events(world, saved.setup, saved.run, kSnapshotFrame + 1);
    ASSERT_TRUE(world.step(kDt).isOk()) << "the World goes on";

    // Worlds that do not match the snapshot.
    {
        WorldDesc other = sceneDesc(1);
        other.substeps = 8;
        WorldPtr w(World::create(other).value());
        addCooked(*w);
        const Status s = w->restoreState(good.data(), good.size());
        EXPECT_NE(s.message().find("WorldDesc.substeps"), std::string::npos) << s.message();
        // Restarting under other solver settings, asked for: restored.
        EXPECT_TRUE(w->restoreState(good.data(), good.size(), RestoreMode::OtherSolver).isOk());
        EXPECT_FALSE(w->restoreState(good.data(), good.size(), RestoreMode(7)).isOk());
    }
    {
        WorldDesc other = sceneDesc(1);
        other.gravity[1] = -1.62;  // not a solver setting: refused even when restarting
        WorldPtr w(World::create(other).value());
        addCooked(*w);
        const Status s = w->restoreState(good.data(), good.size(), RestoreMode::OtherSolver);
        EXPECT_NE(s.message().find("WorldDesc.gravity[1]"), std::string::npos) << s.message();
    }
    {
        WorldPtr w(World::create(sceneDesc(1)).value());
        ClothAssetDesc longer, skirt;
        longer.length = 0.9;
        skirt.kind = GarmentKind::Skirt;
        (void)w->addClothAsset(longer);
        (void)w->addClothAsset(skirt);
        const Status s = w->restoreState(good.data(), good.size());
        EXPECT_NE(s.message().find("cloth asset 1 differs"), std::string::npos) << s.message();
    }
    {
        WorldPtr w(World::create(sceneDesc(1)).value());
        ClothAssetDesc cape, skirt;
        cape.levelCount = skirt.levelCount = 4;
        cape.renderLevel = skirt.renderLevel = 3;
        skirt.kind = GarmentKind::Skirt;
        (void)w->addClothAsset(cape);
        (void)w->addClothAsset(skirt);
        (void)w->addMannequinBody({});
        const Status s = w->restoreState(good.data(), good.size());
        EXPECT_NE(s.message().find("bodies"), std::string::npos) << s.message();
    }
}

/// A window of an error study: the run saved at a level, restarted in another World at the same
/// level and settings, reproduces the saved run's next frames bit for bit (zero error); restarted
/// at a coarser level or under other solver settings it differs, by a bounded amount.
TEST(WorldSnapshot, ARestartedWindowReproducesTheRunAtItsLevelAndDiffersAtAnother) {
    constexpr int kStart = 40, kWindow = 20, kLevel = 3;
    auto makeWorld = [](uint32_t substeps, GarmentId* garment, CharacterId* walker) {
        WorldDesc desc;
        desc.fixedCostModel = true;
        desc.maxThreads = 1;
        desc.substeps = substeps;
        WorldPtr world(World::create(desc).value());
        const AssetId cape = world->addClothAsset({}).value();
        CharacterDesc c;
        c.body = world->addMannequinBody({}).value();
        *walker = world->addCharacter(c).value();
        GarmentDesc g;
        g.forceLevel = kLevel;
        *garment = world->addGarment(cape, *walker, g).value();
        return world;
    };
    auto walk = [](World& world, CharacterId walker, int from, int frames) {
        for (int f = from + 1; f <= from + frames; ++f) {
            const double root[3] = {0.0, 0.0, 1.3 * f * kDt};
            ASSERT_TRUE(world.setCharacterRoot(walker, root, 0.0).isOk());
            ASSERT_TRUE(world.step(kDt).isOk());
        }
    };
    auto mesh = [](const World& world, GarmentId g) {
        const RenderMeshView m = world.renderMesh(g).value();
        return std::vector<float>(m.positions, m.positions + 3 * std::size_t(m.vertexCount));
    };
    auto rms = [](const std::vector<float>& a, const std::vector<float>& b) {
        return lod::meshDeviation(a.data(), b.data(), a.size() / 3).rmsMetres;
    };
    GarmentId garment;
    CharacterId walker;
    WorldPtr reference = makeWorld(4, &garment, &walker);
    walk(*reference, walker, 0, kStart);
    const std::vector<uint8_t> saved = reference->saveState().value();
    walk(*reference, walker, kStart, kWindow);
    const std::vector<float> end = mesh(*reference, garment);

    GarmentId g;
    CharacterId c;
    WorldPtr same = makeWorld(4, &g, &c);
    ASSERT_TRUE(same->restoreState(saved.data(), saved.size()).isOk());
    ASSERT_TRUE(same->setGarmentLevel(garment, kLevel).isOk());
    walk(*same, walker, kStart, kWindow);
    EXPECT_EQ(mesh(*same, garment), end) << "the same level and settings: zero error";

    ASSERT_TRUE(same->restoreState(saved.data(), saved.size()).isOk());
    ASSERT_TRUE(same->setGarmentLevel(garment, 1).isOk());
    walk(*same, walker, kStart, kWindow);
    EXPECT_EQ(same->garmentStats(garment).value().level, 1);
    const double coarse = rms(mesh(*same, garment), end);
    EXPECT_GT(coarse, 1e-4) << "level 1 is not level 3";
    EXPECT_LT(coarse, 0.1) << "a 1/3 s window from the reference's state stays near it";

    // Under other solver settings (restarted, asked for): the World's own, from the saved state.
    WorldPtr finer = makeWorld(16, &g, &c);
    ASSERT_FALSE(finer->restoreState(saved.data(), saved.size()).isOk());
    ASSERT_TRUE(finer->restoreState(saved.data(), saved.size(), RestoreMode::OtherSolver).isOk());
    walk(*finer, walker, kStart, kWindow);
    EXPECT_EQ(finer->garmentStats(garment).value().substeps, 8u) << "16 at the finest level, 8 at level 3";
    const double substepped = rms(mesh(*finer, garment), end);
    EXPECT_GT(substepped, 0.0);
    EXPECT_LT(substepped, 0.5);
    WorldPtr again = makeWorld(4, &g, &c);
    ASSERT_TRUE(again->restoreState(saved.data(), saved.size(), RestoreMode::OtherSolver).isOk());
    walk(*again, walker, kStart, kWindow);
    EXPECT_EQ(mesh(*again, garment), end) << "OtherSolver under the saved settings is Continue";

    EXPECT_FALSE(same->setGarmentLevel(garment, 99).isOk());
    EXPECT_FALSE(same->setGarmentLevel(garment, -2).isOk());
    EXPECT_FALSE(same->setGarmentLevel(GarmentId{}, 1).isOk());
    ASSERT_TRUE(same->setGarmentLevel(garment, -1).isOk());  // scheduled again
    walk(*same, walker, kStart + kWindow, 1);
}

} // namespace
} // namespace cc
