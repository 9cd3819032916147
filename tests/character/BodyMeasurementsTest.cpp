#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/BodyMeasurements.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/import/CharacterIO.h"
#include "support/RestPose.h"

namespace cc {
namespace {

namespace fs = std::filesystem;

void print(const char* what, const BodyMeasurements& m) {
    std::printf("%s (%s): height %.3f, crotch %.3f, hips %.3f (%.3f), waist %.3f (%.3f), chest %.3f (%.3f), shoulders %.3f "
                "(width %.3f), neck %.3f (%.3f), forward (%.2f %.2f %.2f)\n",
                what, m.method.c_str(), m.height, m.crotchY, m.hips.height, m.hips.girth, m.waist.height, m.waist.girth,
                m.chest.height, m.chest.girth, m.shoulderY, m.shoulderWidth, m.neck.height, m.neck.girth, m.forward.x(),
                m.forward.y(), m.forward.z());
}

/// Measures a character the way BodyAsset does: regions at rest, arms relaxed to hang 0.2 rad
/// from vertical when the rest pose holds them higher (T and A poses).
Result<BodyMeasurements> measure(const Character& ch) {
    const std::vector<Vec3> rest = test::restPositionsOf(ch);
    auto regions = findBodyRegions(ch, rest);
    if (!regions.isOk()) return regions.status();
    CharacterPose pose(ch);
    std::vector<Transform> relaxed(ch.skeleton.jointCount());
    relaxedArmsPose(ch, regions.value(), rest, 0.2, 0.5, relaxed);
    std::copy(relaxed.begin(), relaxed.end(), pose.localPose().begin());
    pose.update(ch);
    std::vector<Vec3> p(ch.body.vertexCount()), joints;
    EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    for (const Mat4& g : pose.globalTransforms()) joints.push_back(g.topRightCorner<3, 1>());
    return measureBody(p, ch.body.triangles, regions.value(), joints);
}

/// Perimeter of an ellipse with half-axes a, b (Ramanujan).
double ellipse(double a, double b) {
    const double h = (a - b) * (a - b) / ((a + b) * (a + b));
    return M_PI * (a + b) * (1.0 + 3.0 * h / (10.0 + std::sqrt(4.0 - 3.0 * h)));
}

/// Landmarks any humanoid must show, whatever its proportions (a cartoon's head may be a third of
/// its height): they stack up from the crotch to the neck, the chest lies under the arms, the
/// waist between hips and chest, and the girths are a body's.
void expectHumanoid(const char* what, const BodyMeasurements& m) {
    const double torso = m.shoulderY - m.crotchY;
    EXPECT_LE(m.crotchY, m.hips.height) << what;
    EXPECT_LT(m.hips.height, m.waist.height) << what;
    EXPECT_LT(m.waist.height, m.chest.height) << what;
    EXPECT_LT(m.chest.height, m.shoulderY) << what;
    EXPECT_GT(m.chest.height, m.shoulderY - 0.4 * torso) << what << ": the chest is under the arms";
    EXPECT_GT(m.neck.height, m.shoulderY) << what;
    EXPECT_LT(m.neck.height, m.shoulderY + 0.5 * (m.topY - m.shoulderY)) << what << ": the neck is below the head";
    EXPECT_LT(m.neck.girth, m.chest.girth) << what;
    EXPECT_GT(m.shoulderWidth, 2.0 * m.neck.halfWidth) << what << ": the shoulders are wider than the neck";
    EXPECT_LT(m.shoulderWidth, 0.35 * m.height) << what << ": the shoulder tips are not the hands";
}

/// Landmark heights as fractions of the body height, as tailors' tables give them for an adult
/// (crotch ~0.45-0.48, hips ~0.5-0.53, waist ~0.6-0.63, chest ~0.72, shoulders ~0.8-0.82, neck
/// ~0.84): the mannequin is built to them.
void expectAdultProportions(const char* what, const BodyMeasurements& m) {
    expectHumanoid(what, m);
    const auto at = [&](double y) { return (y - m.groundY) / m.height; };
    EXPECT_NEAR(at(m.crotchY), 0.46, 0.05) << what << ": crotch";
    EXPECT_NEAR(at(m.hips.height), 0.51, 0.05) << what << ": hips";
    EXPECT_NEAR(at(m.waist.height), 0.61, 0.05) << what << ": waist";
    EXPECT_NEAR(at(m.chest.height), 0.72, 0.05) << what << ": chest";
    EXPECT_NEAR(at(m.shoulderY), 0.81, 0.04) << what << ": shoulders";
    EXPECT_NEAR(at(m.neck.height), 0.84, 0.04) << what << ": neck";
    EXPECT_LT(m.waist.girth, m.hips.girth) << what;
    EXPECT_LT(m.neck.girth, 0.6 * m.chest.girth) << what;
}

TEST(BodyMeasurements, MannequinLandmarksMatchItsProportions) {
    const MannequinParams params;
    const Mannequin man = buildMannequin(params).value();
    auto m = measure(man.character);
    ASSERT_TRUE(m.isOk()) << m.status().message();
    print("mannequin", m.value());
    EXPECT_EQ(m.value().method, "joint names");
    EXPECT_NEAR(m.value().height, params.height, 1e-3);
    expectAdultProportions("mannequin", m.value());
    // Girths against the mannequin's own widths: its sections are near ellipses.
    EXPECT_NEAR(2.0 * m.value().hips.halfWidth, params.hipWidth, 0.03);
    EXPECT_NEAR(2.0 * m.value().waist.halfWidth, params.waistWidth, 0.03);
    EXPECT_NEAR(m.value().waist.girth, ellipse(m.value().waist.halfWidth, m.value().waist.halfDepth), 0.05);
    EXPECT_NEAR(m.value().shoulderWidth, params.shoulderWidth, 0.05);
    EXPECT_NEAR(m.value().forward.z(), 1.0, 1e-6);
    EXPECT_LT(m.value().leftShoulder.x(), 0.5 * m.value().shoulderWidth + 1e-6);
    EXPECT_GT(m.value().leftShoulder.x(), 0.0) << "the left shoulder is on the left (+X)";
}

TEST(BodyMeasurements, FromGeometryAloneNearTheSkeletonsOwn) {
    const Mannequin man = buildMannequin().value();
    auto bySkeleton = measure(man.character);
    auto regions = findBodyRegionsFromGeometry(man.character.body);
    ASSERT_TRUE(bySkeleton.isOk() && regions.isOk()) << regions.status().message();
    auto m = measureBody(man.character.body.bindPositions, man.character.body.triangles, regions.value(), {});
    ASSERT_TRUE(m.isOk()) << m.status().message();
    print("mannequin by geometry", m.value());
    EXPECT_EQ(m.value().method, "geometry");
    expectAdultProportions("mannequin by geometry", m.value());
    const BodyMeasurements& s = bySkeleton.value();
    EXPECT_NEAR(m.value().waist.height, s.waist.height, 0.05);
    EXPECT_NEAR(m.value().waist.girth, s.waist.girth, 0.05);
    EXPECT_NEAR(m.value().neck.height, s.neck.height, 0.05);
    EXPECT_NEAR(m.value().shoulderWidth, s.shoulderWidth, 0.05);
}

TEST(BodyMeasurements, ScaleWithTheBodyAndFollowItsWidths) {
    MannequinParams small, wide;
    small.height = 1.5;
    wide.hipWidth = 0.44;
    wide.waistWidth = 0.38;
    const Mannequin base = buildMannequin().value();
    auto m0 = measure(base.character);
    auto ms = measure(buildMannequin(small).value().character);
    auto mw = measure(buildMannequin(wide).value().character);
    ASSERT_TRUE(m0.isOk() && ms.isOk() && mw.isOk());
    const double k = 1.5 / 1.8;
    for (const auto& [a, b, what] : {std::tuple{m0.value().waist.height, ms.value().waist.height, "waist"},
                                     std::tuple{m0.value().hips.height, ms.value().hips.height, "hips"},
                                     std::tuple{m0.value().neck.height, ms.value().neck.height, "neck"},
                                     std::tuple{m0.value().shoulderY, ms.value().shoulderY, "shoulders"}})
        EXPECT_NEAR(b, k * a, 0.02 * 1.5) << what << " heights scale with the body";
    EXPECT_NEAR(mw.value().hips.girth - m0.value().hips.girth, 2.0 * (0.44 - 0.34), 0.08) << "wider hips, larger girth";
    EXPECT_GT(mw.value().waist.girth, m0.value().waist.girth + 0.1);
    EXPECT_NEAR(mw.value().neck.girth, m0.value().neck.girth, 0.02) << "the neck does not follow the hips";
}

TEST(BodyMeasurements, SharedHumanoids) {
    const fs::path dir = CC_HUMANOIDS_DIR;
    if (!fs::is_directory(dir)) GTEST_SKIP() << "shared humanoids folder absent: " << dir;
    for (const char* name : {"CesiumMan.glb", "RiggedFigure.glb", "RobotExpressive.glb"}) {
        if (!fs::exists(dir / name)) continue;
        auto ch = importCharacter((dir / name).string());
        ASSERT_TRUE(ch.isOk()) << ch.status().message();
        auto m = measure(ch.value());
        ASSERT_TRUE(m.isOk()) << name << ": " << m.status().message();
        print(name, m.value());
        expectHumanoid(name, m.value());
        EXPECT_GT(m.value().forward.z(), 0.9) << name;
    }
}

} // namespace
} // namespace cc
