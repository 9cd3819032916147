// Every garment kind, fitted to the mannequin and to the shared humanoids, through the World on
// their walk, run and dance clips at 60 Hz (and some at 30 Hz). Checked independently of the
// solver: attachments on their skinned targets, nothing non-finite, no failed update; reported:
// the largest edge strain per update (median, 95th percentile, worst, updates over the limit) and
// how deep garment vertices got inside the body (generalised winding number over the posed body).
//
// Holding the strain limit and the thickness under contact and fast limbs is the solver's job; the
// current one does not everywhere (see the printed figures). DISABLED_WithinStrainAndThickness
// asserts both for every case: run it with --gtest_also_run_disabled_tests.
//
// Where the strain comes from (2026-12-07, the poncho on RobotExpressive walking, 465 % at its
// worst, 84 % on most frames; the largest strain after each phase of an update): the solve holds
// it at 10-12 %; the body's corrections after it make 128-623 %, the strain limit around them 10 %,
// and the body's last word (back to the surface) 84-465 %. The corrections move 5-13 cm: a vertex
// with a contact plane of a small part (a hand, 10 cm across) keeps to the plane in the solve (it
// ends a thickness in front of it) but slides along it past the part's edge and into the part
// through another face, whose normal is 90-180 degrees from the plane's; the push out through that
// face moves it away from its neighbours. A plane is a half-space: it cannot hold a vertex that
// wraps round a small part. Measured and not landed: a floor of 5 or 15 cm on the contact search's
// reach (465 -> 114 or 136 %: the planes were there already), and alternating the push and the
// strain limit 2-8 times (74-90 %: 20 vertices pushed every round, never settling; the cloth is
// caught between parts). The same holds in every case here (largest strain over each run, the
// first half second included): after the solve 8-28 % (most 10-16 %), after the body's
// corrections 79-676 %, at the update's end 10-465 %. Shorter substeps take most of it away (the
// poncho on RobotExpressive walking / the dress on CesiumMan in cc_dress, worst strain at 60 Hz:
// 465 / 111 % with 4 substeps, 86 / 24 % with 8, 43 / 23 % with 16; updated at 120 Hz, the
// contacts gathered twice a frame, 57 / 19 %). What would hold it: substeps chosen from the body's
// surface speed, and contacts that follow the surface inside the solve (the body queried again
// between substeps, or a curved contact for a small part).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "crowdcloth/core/Statistics.h"
#include "support/BodyInside.h"
#include "support/CrowdScenes.h"
#include "support/HumanoidBodies.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

using test::distanceToSurface;
using test::vertexOf;
using test::windingNumber;

struct Case {
    const char* body;  ///< "mannequin" or a file in the shared humanoids folder
    const char* clip;  ///< clip name; "" = the body's first clip
    GarmentKind kind;
    double rate;       ///< [Hz]
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << test::kindName(c.kind) << " on " << c.body << " " << (c.clip[0] ? c.clip : "clip 0") << " " << c.rate << " Hz";
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
    std::string name = std::string(test::kindName(info.param.kind)) + "_" + info.param.body + "_" +
                       (info.param.clip[0] ? info.param.clip : "clip0") + "_" + std::to_string(int(info.param.rate)) + "Hz";
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
}

struct Outcome {
    double deepest = 0.0;          ///< [m] deepest garment vertex inside the body
    double worstStrain = 0.0;      ///< [-] after the first half second
    double worstAttachment = 0.0;  ///< [m]
    std::vector<double> strains;   ///< [-] largest edge strain of each update after the first half second
    double thickness = 0.0;        ///< [m]
    int inside = 0, checked = 0;
};

/// Simulates the case for two seconds at its rate and measures it; fails the test on a failed
/// update, a non-finite vertex or an attachment more than 1 mm off its target.
void run(const Case& c, Outcome& out) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    WorldPtr world(World::create(desc).value());
    bool absent = false;
    const Result<BodyId> added = test::addNamedBody(*world, c.body, CC_HUMANOIDS_DIR, absent);
    if (absent) GTEST_SKIP() << added.status().message();
    ASSERT_TRUE(added.isOk()) << added.status().message();
    const BodyId body = added.value();
    // [m/s] root motion (the mannequin's clips are in place with a velocity)
    double speed = 0.0;
    if (std::string(c.body) == "mannequin")
        speed = std::string(c.clip) == "run" ? 4.6 : std::string(c.clip) == "walk" ? 1.35 : 0.0;
    ClothAssetDesc assetDesc;
    assetDesc.kind = c.kind;
    const AssetId asset = world->addClothAsset(assetDesc).value();
    CharacterDesc cd;
    cd.body = body;
    cd.clip = c.clip[0] ? c.clip : nullptr;
    cd.clipIndex = c.clip[0] ? -1 : 0;
    const auto character = world->addCharacter(cd);
    ASSERT_TRUE(character.isOk()) << character.status().message();
    GarmentDesc gd;
    gd.forceLevel = int32_t(assetDesc.levelCount) - 1;
    const auto garment = world->addGarment(asset, character.value(), gd);
    ASSERT_TRUE(garment.isOk()) << garment.status().message();
    const BodyLandmarkDesc landmarks = world->bodyLandmarks(body).value();
    const double height = landmarks.neckY * 1.15;  // about the standing height
    out.thickness = assetDesc.thickness;

    const double dt = 1.0 / c.rate, seconds = 2.0;
    const int frames = int(seconds * c.rate), checkEvery = std::max(1, int(c.rate / 5.0));
    for (int f = 1; f <= frames; ++f) {
        const double z = speed * f * dt, position[3] = {0.0, 0.0, z};
        ASSERT_TRUE(world->setCharacterRoot(character.value(), position, 0.0).isOk());
        const CameraDesc camera = test::closeUpCamera(height, z);
        ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
        ASSERT_TRUE(world->step(dt).isOk());
        const GarmentStats stats = world->garmentStats(garment.value()).value();
        ASSERT_FALSE(stats.failed) << "frame " << f;
        out.worstAttachment = std::max(out.worstAttachment, stats.maxAttachmentError);
        if (f > int(0.5 * c.rate)) {
            out.worstStrain = std::max(out.worstStrain, stats.maxStrain);
            out.strains.push_back(stats.maxStrain);
        }
        const RenderMeshView cloth = world->renderMesh(garment.value()).value();
        for (uint32_t v = 0; v < cloth.vertexCount; ++v) ASSERT_TRUE(isFinite(vertexOf(cloth.positions, v))) << "frame " << f;
        if (f % checkEvery != 0 || f < int(0.5 * c.rate)) continue;  // after half a second of settling
        const RenderMeshView posed = world->characterMesh(character.value()).value();
        for (uint32_t v = 0; v < cloth.vertexCount; ++v) {
            const Vec3 p = vertexOf(cloth.positions, v);
            ++out.checked;
            if (windingNumber(posed, p) < 0.5) continue;
            ++out.inside;
            out.deepest = std::max(out.deepest, distanceToSurface(posed, p));
        }
    }
    // One run's worst update is a single extreme of a chaotic motion; the median and 95th percentile
    // over the updates, and how many exceed the limit, compare between versions more steadily.
    std::size_t over = 0;
    for (double s : out.strains) over += s > desc.strainLimit + 0.01;
    std::printf("%s on %s, %s at %.0f Hz: strain per update median %.1f %%, 95th percentile %.1f %%, worst %.1f %%, "
                "%zu of %zu over the limit; attachment error %.3f mm, %d of %d vertex checks inside, deepest %.2f mm "
                "(thickness %.1f mm)\n",
                test::kindName(c.kind), c.body, c.clip[0] ? c.clip : "clip 0", c.rate,
                100.0 * percentile(out.strains, 0.5), 100.0 * percentile(out.strains, 0.95), 100.0 * out.worstStrain,
                over, out.strains.size(), 1e3 * out.worstAttachment, out.inside, out.checked, 1e3 * out.deepest,
                1e3 * out.thickness);
    EXPECT_LE(out.worstAttachment, 1e-3) << "attachments follow their skinned targets";
}

class GarmentOnHumanoid : public ::testing::TestWithParam<Case> {};

TEST_P(GarmentOnHumanoid, FollowsItsAttachmentsWithoutFailing) {
    Outcome out;
    run(GetParam(), out);
}

TEST_P(GarmentOnHumanoid, DISABLED_WithinStrainAndThickness) {
    Outcome out;
    run(GetParam(), out);
    if (HasFatalFailure() || IsSkipped()) return;
    EXPECT_LE(out.deepest, out.thickness) << "no garment vertex deeper than the thickness inside the body";
    EXPECT_LE(out.worstStrain, 0.1 * 1.05) << "edge strain within the world's strain limit (10 %)";
}

std::vector<Case> cases() {
    std::vector<Case> out;
    for (GarmentKind k : {GarmentKind::Cape, GarmentKind::Skirt, GarmentKind::Dress, GarmentKind::Poncho}) {
        for (const auto& [body, clip] : std::vector<std::pair<const char*, const char*>>{
                 {"mannequin", "walk"}, {"mannequin", "run"}, {"CesiumMan.glb", ""}, {"RiggedFigure.glb", ""},
                 {"RobotExpressive.glb", "Walking"}, {"RobotExpressive.glb", "Running"}, {"RobotExpressive.glb", "Dance"}})
            out.push_back({body, clip, k, 60.0});
        for (const auto& [body, clip] : std::vector<std::pair<const char*, const char*>>{
                 {"mannequin", "walk"}, {"CesiumMan.glb", ""}, {"RobotExpressive.glb", "Walking"}})
            out.push_back({body, clip, k, 30.0});
    }
    return out;
}

INSTANTIATE_TEST_SUITE_P(Humanoids, GarmentOnHumanoid, ::testing::ValuesIn(cases()), caseName);

} // namespace
} // namespace cc
