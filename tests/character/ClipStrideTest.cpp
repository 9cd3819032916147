// The widest stride of a character's clips (the A-line cut's allowance), against clips whose thigh
// angles are known.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/character/BodyRegions.h"
#include "crowdcloth/character/ClipStride.h"
#include "crowdcloth/character/Mannequin.h"
#include "support/RestPose.h"

namespace cc {
namespace {

/// A one-second clip: the left thigh swung forward by `angle` [rad] and the right back, about the
/// body's left axis, at half a second; at rest at both ends. The mannequin's thighs hang from a
/// pelvis at rest orientation, so a rotation about the world's left axis is one about theirs.
AnimationClip strideClip(const Character& ch, const BodyRegions& regions, double angle) {
    AnimationClip clip;
    clip.name = "stride";
    clip.duration = 1.0;
    for (int leg = 0; leg < 2; ++leg) {
        JointChannel c;
        c.joint = regions.thigh[std::size_t(leg)];
        const Quat rest = ch.skeleton.joints[std::size_t(c.joint)].restLocal.rotation;
        const Quat swung = Quat(Eigen::AngleAxisd(leg == 0 ? -angle : angle, regions.left)) * rest;
        c.rotationTimes = {0.0, 0.5, 1.0};
        c.rotations = {rest, swung, rest};
        clip.channels.push_back(c);
    }
    return clip;
}

TEST(ClipStride, TheWidestHalfAngleBetweenTheThighs) {
    Character ch = buildMannequin().value().character;
    const BodyRegions regions = findBodyRegions(ch, test::restPositionsOf(ch)).value();
    // The pelvis above the thighs is at rest orientation: a swing about the world's left axis.
    std::vector<Transform> local(ch.skeleton.jointCount());
    std::vector<Mat4> global(ch.skeleton.jointCount());
    ch.skeleton.restPose(local);
    ch.skeleton.computeGlobalTransforms(local, global);
    const int32_t pelvis = ch.skeleton.joints[std::size_t(regions.thigh[0])].parent;
    ASSERT_GE(pelvis, 0);
    const Mat3 pelvisRotation = global[std::size_t(pelvis)].topLeftCorner<3, 3>();
    EXPECT_TRUE(pelvisRotation.isIdentity(1e-9));

    // The mannequin's own clips: standing still, walking, running.
    EXPECT_NEAR(widestClipStride(ch, regions), 30.0 * M_PI / 180.0, 3.0 * M_PI / 180.0)
        << "its run";
    for (double degrees : {10.0, 25.0, 47.0}) {
        Character swinging = ch;
        swinging.clips = {strideClip(ch, regions, degrees * M_PI / 180.0)};
        ASSERT_TRUE(swinging.validate().isOk());
        EXPECT_NEAR(widestClipStride(swinging, regions) * 180.0 / M_PI, degrees, 0.5) << degrees;
    }
    Character still = ch;
    still.clips.clear();
    EXPECT_EQ(widestClipStride(still, regions), 0.0) << "no clips";
    BodyRegions legless = regions;
    legless.thigh = {-1, -1};
    EXPECT_EQ(widestClipStride(ch, legless), 0.0) << "no legs";
}

/// `ch` with a helper leaf (a twist joint at the hip) inserted as each thigh's first child, before
/// the shin, and `regions` and its clips renumbered to match (the body is left alone: the stride
/// reads the skeleton and the clips only).
Character withTwistJoints(const Character& ch, BodyRegions& regions) {
    Character out = ch;
    for (int leg = 0; leg < 2; ++leg) {
        const int32_t thigh = regions.thigh[std::size_t(leg)];
        const int32_t at = thigh + 1;
        auto shift = [&](int32_t& j) {
            if (j >= at) ++j;
        };
        for (Joint& j : out.skeleton.joints) shift(j.parent);
        Joint twist;
        twist.name = "thigh_twist_" + std::to_string(leg);
        twist.parent = thigh;
        out.skeleton.joints.insert(out.skeleton.joints.begin() + at, twist);
        for (AnimationClip& clip : out.clips)
            for (JointChannel& c : clip.channels) shift(c.joint);
        for (int32_t& j : regions.thigh) shift(j);
        for (int32_t& j : regions.upperArm) shift(j);
    }
    return out;
}

TEST(ClipStride, TwistJointsBesideTheShinArePassedOver) {
    const Character ch = buildMannequin().value().character;
    const BodyRegions plain = findBodyRegions(ch, test::restPositionsOf(ch)).value();
    BodyRegions regions = plain;
    Character twisted = withTwistJoints(ch, regions);
    twisted.clips = {strideClip(twisted, regions, 0.5)};
    // The helper is each thigh's first child; the first-child chain would stop at it, at the hip.
    for (int32_t thigh : regions.thigh)
        ASSERT_EQ(twisted.skeleton.joints[std::size_t(thigh) + 1].parent, thigh);
    EXPECT_NEAR(widestClipStride(twisted, regions), 0.5, 0.01);
}

TEST(ClipStride, AnAbsurdDurationIsSampledBoundedly) {
    Character ch = buildMannequin().value().character;
    const BodyRegions regions = findBodyRegions(ch, test::restPositionsOf(ch)).value();
    AnimationClip clip = strideClip(ch, regions, 0.4);
    clip.duration = 1e12; // keys stay in the first second; sampled 3,601 times, not 3e13
    for (JointChannel& c : clip.channels) c.rotationTimes = {0.0, 0.5e12, 1e12};
    ch.clips = {clip};
    ASSERT_TRUE(ch.validate().isOk());
    EXPECT_NEAR(widestClipStride(ch, regions), 0.4, 0.01);
}

} // namespace
} // namespace cc
