#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/Character.h"
#include "crowdcloth/character/Mannequin.h"

namespace cc {
namespace {


Mannequin makeMannequin() {
    Result<Mannequin> m = buildMannequin();
    EXPECT_TRUE(m.isOk()) << m.status().message();
    return std::move(m).value();
}

TEST(Skinning, RestPoseReproducesBindPositions) {
    const Mannequin man = makeMannequin();
    const Character& ch = man.character;
    CharacterPose pose(ch);
    ASSERT_TRUE(pose.evaluate(ch, -1, 0.0, ClipWrap::Loop).isOk());
    std::vector<Vec3> p(ch.body.vertexCount()), n(ch.body.vertexCount());
    ASSERT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, n).isOk());
    for (std::size_t v = 0; v < p.size(); ++v) {
        ASSERT_LT((p[v] - ch.body.bindPositions[v]).norm(), 1e-12) << "vertex " << v;
        ASSERT_LT((n[v] - ch.body.bindNormals[v]).norm(), 1e-12) << "vertex " << v;
    }
}

TEST(Skinning, RootRotationMovesEveryVertexRigidly) {
    const Mannequin man = makeMannequin();
    const Character& ch = man.character;
    CharacterPose pose(ch);
    ch.skeleton.restPose(pose.localPose());
    const Quat r(Eigen::AngleAxisd(0.7, Vec3(0.3, 1.0, -0.2).normalized()));
    pose.localPose()[0].rotation = r;
    pose.update(ch);
    std::vector<Vec3> p(ch.body.vertexCount()), n(ch.body.vertexCount());
    ASSERT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, n).isOk());
    const Vec3 pivot = ch.skeleton.joints[0].restLocal.translation;
    for (std::size_t v = 0; v < p.size(); ++v) {
        const Vec3 expected = pivot + r * (ch.body.bindPositions[v] - pivot);
        ASSERT_LT((p[v] - expected).norm(), 1e-12) << "vertex " << v;
        ASSERT_LT((n[v] - r * ch.body.bindNormals[v]).norm(), 1e-12) << "vertex " << v;
    }
}

// Two joints: root at the origin, child at (0, 1, 0). A vertex at (1, 1, 0) half on each; the
// child turns 90 degrees about Z: its half moves the point to (0, 2, 0), the root's keeps it.
TEST(Skinning, TwoBoneWeightsBlendLinearly) {
    Character ch;
    ch.name = "two-bone";
    ch.skeleton.joints.push_back({"root", -1, {}});
    Joint child{"child", 0, {}};
    child.restLocal.translation = {0, 1, 0};
    ch.skeleton.joints.push_back(child);
    for (const Vec3& at : {Vec3(0, 0, 0), Vec3(0, 1, 0)}) {
        Mat4 inv = Mat4::Identity();
        inv.topRightCorner<3, 1>() = -at;
        ch.body.inverseBindMatrices.push_back(inv);
    }
    ch.body.bindPositions = {{1, 1, 0}, {0, 0, 1}, {1, 0, 0}};
    ch.body.triangles = {{0, 1, 2}};
    ch.body.computeBindNormals();
    ch.body.jointIndices = {{0, 1, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}};
    ch.body.jointWeights = {{0.5, 0.5, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}};
    ASSERT_TRUE(ch.validate().isOk()) << ch.validate().message();

    CharacterPose pose(ch);
    pose.localPose()[1].rotation = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
    pose.update(ch);
    std::vector<Vec3> p(3);
    ASSERT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    // Child alone: (1,1,0) -> pivot (0,1,0) + Rz(90)(1,0,0) = (0,2,0). Blend: (0.5, 1.5, 0).
    EXPECT_LT((p[0] - Vec3(0.5, 1.5, 0)).norm(), 1e-12);
    EXPECT_LT((p[1] - Vec3(0, 0, 1)).norm(), 1e-12);
    // Vertex 2 fully on the child: (1,0,0) -> (0,1,0) + Rz(90)(1,-1,0) = (1, 2, 0).
    EXPECT_LT((p[2] - Vec3(1, 2, 0)).norm(), 1e-12);
}

TEST(Transform, SlerpHalfwayIsTheHalfAngleRotation) {
    const Vec3 axis = Vec3(1, 2, 3).normalized();
    for (double angle : {0.1, 1.0, 2.5, 3.0}) {
        const Quat a = Quat::Identity();
        const Quat b(Eigen::AngleAxisd(angle, axis));
        const Quat half(Eigen::AngleAxisd(0.5 * angle, axis));
        EXPECT_LT(slerpShortest(a, b, 0.5).angularDistance(half), 1e-12) << angle;
        // The same rotation written as -b must give the same (shorter-arc) result.
        const Quat negB(-b.w(), -b.x(), -b.y(), -b.z());
        EXPECT_LT(slerpShortest(a, negB, 0.5).angularDistance(half), 1e-12) << angle;
    }
}

AnimationClip makeTwoKeyClip() {
    AnimationClip clip;
    clip.name = "test";
    clip.duration = 2.0;
    JointChannel c;
    c.joint = 0;
    c.translationTimes = {0.0, 0.5, 2.0};
    c.translations = {{0, 0, 0}, {1, 2, 3}, {0.1, 0.2, 0.3}};
    c.rotationTimes = {0.0, 1.0};
    c.rotations = {Quat::Identity(), Quat(Eigen::AngleAxisd(1.2, Vec3::UnitY()))};
    c.scaleTimes = {0.25};
    c.scales = {{2, 2, 2}};
    clip.channels.push_back(c);
    return clip;
}

TEST(AnimationClip, EvaluationAtKeysReturnsKeysExactly) {
    Skeleton sk;
    sk.joints.push_back({"root", -1, {}});
    const AnimationClip clip = makeTwoKeyClip();
    ASSERT_TRUE(clip.validate(1).isOk()) << clip.validate(1).message();
    std::vector<Transform> local(1);
    const JointChannel& c = clip.channels[0];
    for (std::size_t k = 0; k < c.translationTimes.size(); ++k) {
        clip.evaluate(sk, c.translationTimes[k], ClipWrap::Clamp, local);
        EXPECT_EQ(local[0].translation, c.translations[k]) << "key " << k;
    }
    for (std::size_t k = 0; k < c.rotationTimes.size(); ++k) {
        clip.evaluate(sk, c.rotationTimes[k], ClipWrap::Clamp, local);
        EXPECT_EQ(local[0].rotation.coeffs(), c.rotations[k].coeffs()) << "key " << k;
    }
    // Between keys: linear translation, slerped rotation, held scale.
    clip.evaluate(sk, 0.25, ClipWrap::Clamp, local);
    EXPECT_LT((local[0].translation - Vec3(0.5, 1.0, 1.5)).norm(), 1e-15);
    EXPECT_LT(local[0].rotation.angularDistance(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))), 1e-12);
    EXPECT_EQ(local[0].scale, Vec3(2, 2, 2));
}

TEST(AnimationClip, LoopWrapsAndClampHolds) {
    Skeleton sk;
    sk.joints.push_back({"root", -1, {}});
    const AnimationClip clip = makeTwoKeyClip();
    std::vector<Transform> a(1), b(1);
    clip.evaluate(sk, 0.3, ClipWrap::Loop, a);
    clip.evaluate(sk, 0.3 + 3 * clip.duration, ClipWrap::Loop, b);
    EXPECT_LT((a[0].translation - b[0].translation).norm(), 1e-12);
    clip.evaluate(sk, 0.3 - clip.duration, ClipWrap::Loop, b);
    EXPECT_LT((a[0].translation - b[0].translation).norm(), 1e-12);
    clip.evaluate(sk, 7.0, ClipWrap::Clamp, b);
    EXPECT_EQ(b[0].translation, clip.channels[0].translations.back());
}

TEST(AnimationClip, ValidateNamesTheBadKey) {
    AnimationClip clip = makeTwoKeyClip();
    clip.channels[0].translationTimes[1] = 0.0;
    Status s = clip.validate(1);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("translation key 1"), std::string::npos) << s.message();
    clip = makeTwoKeyClip();
    clip.channels[0].rotations[1].coeffs() *= 2.0;
    s = clip.validate(1);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("rotation key 1"), std::string::npos) << s.message();
    clip = makeTwoKeyClip();
    clip.channels[0].joint = 3;
    EXPECT_FALSE(clip.validate(1).isOk());
}

TEST(SkinnedMesh, ValidateNamesTheBadVertexOrTriangle) {
    Mannequin man = makeMannequin();
    SkinnedMesh body = man.character.body;
    const std::size_t joints = man.character.skeleton.jointCount();
    body.jointWeights[17] = {0.5, 0.2, 0, 0};
    Status s = body.validate(joints);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("vertex 17"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("sum to 0.7"), std::string::npos) << s.message();

    body = man.character.body;
    body.bindPositions[5].y() = std::nan("");
    s = body.validate(joints);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("vertex 5"), std::string::npos) << s.message();

    body = man.character.body;
    body.triangles[9][2] = static_cast<uint32_t>(body.vertexCount());
    s = body.validate(joints);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("triangle 9"), std::string::npos) << s.message();

    body = man.character.body;
    body.jointIndices[3][0] = static_cast<uint16_t>(joints);
    s = body.validate(joints);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("vertex 3"), std::string::npos) << s.message();
}

TEST(Skeleton, ValidateRejectsParentsOutOfOrder) {
    Skeleton sk;
    sk.joints.push_back({"a", -1, {}});
    sk.joints.push_back({"b", 2, {}});
    sk.joints.push_back({"c", 0, {}});
    const Status s = sk.validate();
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("'b'"), std::string::npos) << s.message();
}

TEST(Character, ChangeBasisMapsEverySkinnedPosition) {
    const Mannequin man = makeMannequin();
    Character moved = man.character;
    Mat3 rot;
    rot << 0, 0, 1, 1, 0, 0, 0, 1, 0; // an axis permutation (x, y, z) -> (z, x, y)
    ASSERT_TRUE(changeBasis(moved, 100.0, rot).isOk());
    ASSERT_TRUE(moved.validate().isOk()) << moved.validate().message();
    const Character& ch = man.character;
    CharacterPose a(ch), b(moved);
    std::vector<Vec3> pa(ch.body.vertexCount()), pb(ch.body.vertexCount());
    for (double t : {0.0, 0.21, 0.55}) {
        ASSERT_TRUE(a.evaluate(ch, ch.findClip("run"), t, ClipWrap::Loop).isOk());
        ASSERT_TRUE(b.evaluate(moved, moved.findClip("run"), t, ClipWrap::Loop).isOk());
        ASSERT_TRUE(skinVertices(ch.body, a.skinMatrices(), pa, {}).isOk());
        ASSERT_TRUE(skinVertices(moved.body, b.skinMatrices(), pb, {}).isOk());
        for (std::size_t v = 0; v < pa.size(); ++v) {
            ASSERT_LT((pb[v] - 100.0 * (rot * pa[v])).norm(), 1e-10) << "vertex " << v;
        }
    }
    EXPECT_FALSE(changeBasis(moved, -1.0, rot).isOk());
    EXPECT_FALSE(changeBasis(moved, 1.0, -Mat3::Identity()).isOk()) << "a reflection is refused";
}

TEST(Skinning, WrongSizesGiveErrorsNotCrashes) {
    const Mannequin man = makeMannequin();
    const Character& ch = man.character;
    CharacterPose pose(ch);
    std::vector<Vec3> p(ch.body.vertexCount() - 1);
    EXPECT_FALSE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    EXPECT_FALSE(pose.evaluate(ch, 7, 0.0, ClipWrap::Loop).isOk());
}

} // namespace
} // namespace cc
