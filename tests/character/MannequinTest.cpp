#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/Mannequin.h"

namespace cc {
namespace {


Mannequin build(const MannequinParams& params = {}) {
    Result<Mannequin> m = buildMannequin(params);
    EXPECT_TRUE(m.isOk()) << m.status().message();
    return std::move(m).value();
}

// Solid angle of triangle (a, b, c) seen from p (Van Oosterom & Strackee 1983), over 4 pi: the
// generalized winding number contribution (Jacobson et al. 2013).
double windingNumber(const SkinnedMesh& body, const Vec3& p) {
    double sum = 0.0;
    for (const auto& t : body.triangles) {
        const Vec3 a = body.bindPositions[t[0]] - p, b = body.bindPositions[t[1]] - p, c = body.bindPositions[t[2]] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double num = a.dot(b.cross(c));
        const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        sum += 2.0 * std::atan2(num, den);
    }
    return sum / (4.0 * kPi);
}

TEST(Mannequin, HeightMatchesTheParameterWithinOnePercent) {
    for (double h : {1.55, 1.8, 2.05}) {
        MannequinParams p;
        p.height = h;
        const Mannequin m = build(p);
        double lo = 1e9, hi = -1e9;
        for (const Vec3& q : m.character.body.bindPositions) {
            lo = std::min(lo, q.y());
            hi = std::max(hi, q.y());
        }
        EXPECT_NEAR(hi - lo, h, 0.01 * h) << "height " << h;
        EXPECT_NEAR(lo, 0.0, 1e-9) << "the soles rest on y = 0";
    }
}

TEST(Mannequin, HasAFewThousandTrianglesAndTheNamedSkeleton) {
    const Mannequin m = build();
    const Character& ch = m.character;
    EXPECT_GE(ch.body.triangles.size(), 2000u);
    EXPECT_LE(ch.body.triangles.size(), 8000u);
    EXPECT_EQ(ch.skeleton.jointCount(), static_cast<std::size_t>(MannequinJoint::Count));
    for (const char* name : {"hips", "spine", "chest", "neck", "head", "upper_arm_l", "forearm_r", "hand_l",
                             "thigh_r", "shin_l", "foot_r", "shoulder_l"}) {
        EXPECT_GE(ch.skeleton.findJoint(name), 0) << name;
    }
    for (const char* clip : {"idle", "walk", "run"}) EXPECT_GE(ch.findClip(clip), 0) << clip;
    std::printf("mannequin: %zu vertices, %zu triangles, %zu parts\n", ch.body.vertexCount(),
                ch.body.triangles.size(), m.parts.size());
}

// Every part: each directed edge appears once and its reverse once (closed, 2-manifold,
// consistently oriented), Euler characteristic 2 (sphere), and positive signed volume (outward).
TEST(Mannequin, PartsAreWatertightManifoldAndOutward) {
    const Mannequin m = build();
    const SkinnedMesh& body = m.character.body;
    std::size_t covered = 0;
    for (const BodyPart& part : m.parts) {
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        double volume = 0.0;
        for (uint32_t t = part.firstTriangle; t < part.firstTriangle + part.triangleCount; ++t) {
            const auto& tri = body.triangles[t];
            for (int e = 0; e < 3; ++e) {
                const uint32_t a = tri[static_cast<std::size_t>(e)], b = tri[static_cast<std::size_t>((e + 1) % 3)];
                ASSERT_GE(a, part.firstVertex) << part.name;
                ASSERT_LT(a, part.firstVertex + part.vertexCount) << part.name;
                ++directed[{a, b}];
            }
            volume += body.bindPositions[tri[0]].dot(body.bindPositions[tri[1]].cross(body.bindPositions[tri[2]])) / 6.0;
        }
        for (const auto& [edge, count] : directed) {
            ASSERT_EQ(count, 1) << part.name << ": directed edge repeated (inconsistent orientation)";
            ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << part.name << ": boundary edge (not closed)";
        }
        const long euler = static_cast<long>(part.vertexCount) - static_cast<long>(directed.size() / 2) +
                           static_cast<long>(part.triangleCount);
        EXPECT_EQ(euler, 2) << part.name;
        EXPECT_GT(volume, 0.0) << part.name << " faces inwards";
        covered += part.triangleCount;
    }
    EXPECT_EQ(covered, body.triangles.size());
}

TEST(Mannequin, WindingNumberFindsJointsInsideAndFarPointsOutside) {
    const Mannequin m = build();
    const Character& ch = m.character;
    std::vector<Mat4> global(ch.skeleton.jointCount());
    std::vector<Transform> local(ch.skeleton.jointCount());
    ch.skeleton.restPose(local);
    ch.skeleton.computeGlobalTransforms(local, global);
    for (std::size_t j = 0; j < global.size(); ++j) {
        const Vec3 p = global[j].topRightCorner<3, 1>();
        EXPECT_GE(windingNumber(ch.body, p), 0.5) << ch.skeleton.joints[j].name << " lies outside the body";
    }
    for (const Vec3& p : {Vec3(0, 1.0, 0.5), Vec3(0.6, 1.0, 0), Vec3(0, 2.5, 0), Vec3(0, 0.3, 0)}) {
        EXPECT_LT(std::abs(windingNumber(ch.body, p)), 1e-6) << p.transpose();
    }
}

TEST(Mannequin, DifferentParametersGiveDifferentBodies) {
    const Mannequin a = build();
    MannequinParams p;
    p.shoulderWidth = 0.46;
    p.hipWidth = 0.38;
    p.limbGirth = 1.2;
    const Mannequin b = build(p);
    ASSERT_EQ(a.character.body.vertexCount(), b.character.body.vertexCount());
    double maxDiff = 0.0;
    for (std::size_t v = 0; v < a.character.body.vertexCount(); ++v) {
        maxDiff = std::max(maxDiff, (a.character.body.bindPositions[v] - b.character.body.bindPositions[v]).norm());
    }
    EXPECT_GT(maxDiff, 0.02);
    EXPECT_GT(b.landmarks.hipRadiusX, a.landmarks.hipRadiusX);
    EXPECT_GT(b.landmarks.leftShoulder.x(), a.landmarks.leftShoulder.x());
}

TEST(Mannequin, InvalidParametersNameTheField) {
    MannequinParams p;
    p.hipWidth = 3.0;
    Result<Mannequin> m = buildMannequin(p);
    ASSERT_FALSE(m.isOk());
    EXPECT_NE(m.status().message().find("hipWidth"), std::string::npos) << m.status().message();
    p = {};
    p.height = std::nan("");
    EXPECT_FALSE(buildMannequin(p).isOk());
}

// World-space peak speed of the centroid of a part's vertices over one cycle, with the clip's
// root velocity added (the clips are in place).
double peakSpeed(const Mannequin& m, const char* clipName, const char* partName) {
    const Character& ch = m.character;
    const int clip = ch.findClip(clipName);
    const AnimationClip& c = ch.clips[static_cast<std::size_t>(clip)];
    const BodyPart* part = nullptr;
    for (const BodyPart& bp : m.parts) {
        if (bp.name == partName) part = &bp;
    }
    CharacterPose pose(ch);
    std::vector<Vec3> p(ch.body.vertexCount());
    const auto centroid = [&](double t) {
        EXPECT_TRUE(pose.evaluate(ch, clip, t, ClipWrap::Loop).isOk());
        EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
        Vec3 s = Vec3::Zero();
        for (uint32_t v = part->firstVertex; v < part->firstVertex + part->vertexCount; ++v) s += p[v];
        return Vec3(s / part->vertexCount + c.rootVelocity * t);
    };
    const int steps = 400;
    const double dt = c.duration / steps;
    double peak = 0.0;
    Vec3 prev = centroid(0.0);
    for (int i = 1; i <= steps; ++i) {
        const Vec3 cur = centroid(i * dt);
        peak = std::max(peak, (cur - prev).norm() / dt);
        prev = cur;
    }
    return peak;
}

TEST(Mannequin, RunReachesAboutTenMetresPerSecondAndWalkStaysSlow) {
    const Mannequin m = build();
    for (const char* part : {"hand_l", "hand_r", "foot_l", "foot_r"}) {
        const double run = peakSpeed(m, "run", part);
        const double walk = peakSpeed(m, "walk", part);
        std::printf("%s peak speed: run %.2f m/s, walk %.2f m/s\n", part, run, walk);
        EXPECT_GE(run, 7.0) << part;
        EXPECT_LE(run, 13.0) << part;
        EXPECT_GE(walk, 1.0) << part;
        EXPECT_LE(walk, 4.0) << part;
    }
}

TEST(Mannequin, ClipsLoopContinuously) {
    const Mannequin m = build();
    const Character& ch = m.character;
    CharacterPose a(ch), b(ch);
    std::vector<Vec3> pa(ch.body.vertexCount()), pb(ch.body.vertexCount());
    for (std::size_t c = 0; c < ch.clips.size(); ++c) {
        const double T = ch.clips[c].duration;
        ASSERT_GT(T, 0.0);
        ASSERT_TRUE(a.evaluate(ch, static_cast<int>(c), 0.0, ClipWrap::Clamp).isOk());
        ASSERT_TRUE(b.evaluate(ch, static_cast<int>(c), T, ClipWrap::Clamp).isOk());
        ASSERT_TRUE(skinVertices(ch.body, a.skinMatrices(), pa, {}).isOk());
        ASSERT_TRUE(skinVertices(ch.body, b.skinMatrices(), pb, {}).isOk());
        double gap = 0.0;
        for (std::size_t v = 0; v < pa.size(); ++v) gap = std::max(gap, (pa[v] - pb[v]).norm());
        EXPECT_LT(gap, 1e-12) << ch.clips[c].name << ": pose at 0 differs from pose at the cycle length";
        // Just before the end the pose is close to the start (no jump across the seam).
        ASSERT_TRUE(b.evaluate(ch, static_cast<int>(c), T - 1e-4, ClipWrap::Loop).isOk());
        ASSERT_TRUE(skinVertices(ch.body, b.skinMatrices(), pb, {}).isOk());
        gap = 0.0;
        for (std::size_t v = 0; v < pa.size(); ++v) gap = std::max(gap, (pa[v] - pb[v]).norm());
        EXPECT_LT(gap, 1e-4 * 15.0) << ch.clips[c].name << ": jump at the loop seam";
        EXPECT_GT(gap, 0.0) << ch.clips[c].name << " does not move";
    }
}

TEST(Mannequin, CapsulesHugTheirParts) {
    const Mannequin m = build();
    const SkinnedMesh& body = m.character.body;
    ASSERT_EQ(m.capsules.size(), m.parts.size() - 1 + 3);
    for (const BodyCapsule& c : m.capsules) {
        ASSERT_GE(c.joint, 0);
        ASSERT_LT(static_cast<std::size_t>(c.joint), m.character.skeleton.jointCount());
        EXPECT_GT(c.radius, 0.01);
        EXPECT_LT(c.radius, 0.2);
    }
    // Each limb capsule: at least 80% of its part's vertices lie within 2 cm of its surface.
    for (std::size_t i = 0; i < m.parts.size(); ++i) {
        const BodyPart& part = m.parts[i];
        if (part.name == "torso") continue;
        const BodyCapsule* cap = nullptr;
        for (const BodyCapsule& c : m.capsules) {
            if (c.joint == part.joint) cap = &c;
        }
        ASSERT_NE(cap, nullptr) << part.name;
        std::size_t near = 0;
        for (uint32_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v) {
            const Vec3& q = body.bindPositions[v];
            const Vec3 ab = cap->b - cap->a;
            const double t = ab.squaredNorm() > 0 ? std::clamp((q - cap->a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
            if (std::abs((q - (cap->a + t * ab)).norm() - cap->radius) < 0.02) ++near;
        }
        EXPECT_GE(near, part.vertexCount * 8 / 10) << part.name;
    }
}

TEST(Mannequin, LandmarksLieOnTheBody) {
    const Mannequin m = build();
    const BodyLandmarks& lm = m.landmarks;
    const auto& joints = m.character.skeleton.joints;
    EXPECT_EQ(joints[static_cast<std::size_t>(lm.waistJoint)].name, "spine");
    EXPECT_GT(lm.waistCentre.y(), 0.55 * 1.8);
    EXPECT_LT(lm.waistCentre.y(), 0.68 * 1.8);
    EXPECT_GT(lm.hipRadiusX, lm.waistRadiusX);
    EXPECT_GT(lm.leftShoulder.x(), 0.1);
    EXPECT_LT(lm.rightShoulder.x(), -0.1);
    EXPECT_NEAR(lm.leftShoulder.y(), 0.8 * 1.8 + 0.05, 0.05);
    // Waist ring points are on the surface: the winding number changes across them.
    const Vec3 front = lm.waistCentre + Vec3(0, 0, lm.waistRadiusZ);
    EXPECT_GE(windingNumber(m.character.body, front - Vec3(0, 0, 0.01)), 0.5);
    EXPECT_LT(windingNumber(m.character.body, front + Vec3(0, 0, 0.01)), 0.5);
    const Vec3 side = lm.waistCentre + Vec3(lm.waistRadiusX, 0, 0);
    EXPECT_GE(windingNumber(m.character.body, side - Vec3(0.01, 0, 0)), 0.5);
    EXPECT_LT(windingNumber(m.character.body, side + Vec3(0.01, 0, 0)), 0.5);
    EXPECT_GE(windingNumber(m.character.body, lm.leftShoulder - Vec3(0, 0.01, 0)), 0.5);
    EXPECT_LT(windingNumber(m.character.body, lm.leftShoulder + Vec3(0, 0.01, 0)), 0.5);
}

} // namespace
} // namespace cc
