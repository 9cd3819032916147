#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/character/MotionConstraints.h"
#include "crowdcloth/character/SkinBinding.h"

namespace cc {
namespace {


Mannequin build() {
    Result<Mannequin> m = buildMannequin();
    EXPECT_TRUE(m.isOk()) << m.status().message();
    return std::move(m).value();
}

// A skirt-like ring of garment points around the hips, `offset` outside the body surface, plus
// points on the shoulders and upper arms (a cape line): the places garments attach.
std::vector<Vec3> garmentPoints(const Mannequin& m, double offset) {
    std::vector<Vec3> pts;
    const BodyLandmarks& lm = m.landmarks;
    for (int i = 0; i < 48; ++i) {
        const double a = 2.0 * kPi * i / 48;
        for (double dy : {-0.08, 0.0, 0.06}) {
            const Vec3 c = lm.waistCentre + Vec3(0, dy, 0);
            pts.push_back(c + Vec3((lm.waistRadiusX + offset) * std::cos(a), 0, (lm.waistRadiusZ + offset) * std::sin(a)));
        }
    }
    for (int i = 0; i <= 20; ++i) {
        const double f = i / 20.0;
        pts.push_back((1 - f) * lm.leftShoulder + f * lm.rightShoulder + Vec3(0, offset, 0));
    }
    return pts;
}

TEST(SkinBinding, BoundVerticesFollowTheSkinnedBodyOverAWalk) {
    const Mannequin m = build();
    const Character& ch = m.character;
    const SkinnedMesh& body = ch.body;
    // On the surface: project the garment points onto the body first; add the centroids of every
    // fifth body triangle so elbows, knees and shoulders are covered.
    std::vector<Vec3> raw = garmentPoints(m, 0.0);
    for (std::size_t t = 0; t < body.triangles.size(); t += 5) {
        const auto& tri = body.triangles[t];
        raw.push_back((body.bindPositions[tri[0]] + body.bindPositions[tri[1]] + body.bindPositions[tri[2]]) / 3.0);
    }
    Result<SkinBinding> pre = SkinBinding::bind(body, raw);
    ASSERT_TRUE(pre.isOk()) << pre.status().message();
    std::vector<Vec3> onSurface(raw.size());
    CharacterPose rest(ch);
    ASSERT_TRUE(pre.value().evaluate(body, rest.skinMatrices(), {}, onSurface, {}).isOk());

    Result<SkinBinding> binding = SkinBinding::bind(body, onSurface);
    ASSERT_TRUE(binding.isOk()) << binding.status().message();
    const SkinBinding& b = binding.value();
    ASSERT_EQ(b.size(), onSurface.size());
    // At the bind pose the targets are the bind positions.
    std::vector<Vec3> targets(b.size()), points(b.size()), normals(b.size());
    ASSERT_TRUE(b.evaluate(body, rest.skinMatrices(), targets, points, normals).isOk());
    for (std::size_t i = 0; i < b.size(); ++i) ASSERT_LT((targets[i] - onSurface[i]).norm(), 1e-12) << i;

    // Over the walk: each target equals the point of the independently skinned body mesh at the
    // bound triangle's barycentric coordinates.
    const int walk = ch.findClip("walk");
    CharacterPose pose(ch);
    std::vector<Vec3> skinned(body.vertexCount()), skinnedNormals(body.vertexCount());
    double worst = 0.0, worstNaive = 0.0;
    for (int f = 0; f < 60; ++f) {
        const double t = ch.clips[static_cast<std::size_t>(walk)].duration * f / 60.0;
        ASSERT_TRUE(pose.evaluate(ch, walk, t, ClipWrap::Loop).isOk());
        ASSERT_TRUE(skinVertices(body, pose.skinMatrices(), skinned, skinnedNormals).isOk());
        ASSERT_TRUE(b.evaluate(body, pose.skinMatrices(), targets, points, normals).isOk());
        for (std::size_t i = 0; i < b.size(); ++i) {
            const BoundVertex& bv = b.vertices()[i];
            const auto& tri = body.triangles[bv.triangle];
            Vec3 expected = Vec3::Zero();
            for (int k = 0; k < 3; ++k) expected += bv.barycentric[static_cast<std::size_t>(k)] * skinned[tri[static_cast<std::size_t>(k)]];
            worst = std::max(worst, (targets[i] - expected).norm());
            EXPECT_NEAR(normals[i].norm(), 1.0, 1e-12);
            // Skinning the vertex with its interpolated weights alone (the simpler rule) drifts.
            worstNaive = std::max(worstNaive, (skinPoint(onSurface[i], bv.joints, bv.weights, pose.skinMatrices()) - expected).norm());
        }
    }
    std::printf("bound-vertex gap to the skinned surface over a walk: %.3g m (weights-only skinning: %.3g m)\n",
                worst, worstNaive);
    EXPECT_LT(worst, 1e-3);
}

TEST(SkinBinding, OffsetVerticesKeepTheirDistanceFromTheBody) {
    const Mannequin m = build();
    const Character& ch = m.character;
    // 1 cm in front of the body surface along its normal.
    const std::vector<Vec3> raw = garmentPoints(m, 0.0);
    Result<SkinBinding> pre = SkinBinding::bind(ch.body, raw);
    ASSERT_TRUE(pre.isOk()) << pre.status().message();
    std::vector<Vec3> surface(raw.size()), normal(raw.size()), pts(raw.size());
    CharacterPose rest(ch);
    ASSERT_TRUE(pre.value().evaluate(ch.body, rest.skinMatrices(), {}, surface, normal).isOk());
    for (std::size_t i = 0; i < raw.size(); ++i) pts[i] = surface[i] + 0.01 * normal[i];
    Result<SkinBinding> binding = SkinBinding::bind(ch.body, pts);
    ASSERT_TRUE(binding.isOk()) << binding.status().message();
    const SkinBinding& b = binding.value();
    std::vector<double> bindDistance(b.size());
    for (std::size_t i = 0; i < b.size(); ++i) {
        bindDistance[i] = b.vertices()[i].offset.norm();
        ASSERT_GT(bindDistance[i], 0.005) << i;
        ASSERT_LT(bindDistance[i], 0.0101) << i;
    }
    const int walk = ch.findClip("walk");
    CharacterPose pose(ch);
    std::vector<Vec3> targets(b.size()), points(b.size()), normals(b.size());
    double worst = 0.0;
    for (int f = 0; f < 30; ++f) {
        ASSERT_TRUE(pose.evaluate(ch, walk, 0.037 * f, ClipWrap::Loop).isOk());
        ASSERT_TRUE(b.evaluate(ch.body, pose.skinMatrices(), targets, points, normals).isOk());
        for (std::size_t i = 0; i < b.size(); ++i) {
            worst = std::max(worst, std::abs((targets[i] - points[i]).norm() - bindDistance[i]));
            // The target stays in front of the body surface.
            EXPECT_GT((targets[i] - points[i]).dot(normals[i]), 0.0) << i;
        }
    }
    EXPECT_LT(worst, 1e-3) << "offset length changed under skinning";
}

TEST(SkinBinding, EvaluateSkinnedMatchesEvaluateAndFollowsHostSkinnedBodies) {
    const Mannequin m = build();
    const Character& ch = m.character;
    const SkinnedMesh& body = ch.body;
    Result<SkinBinding> binding = SkinBinding::bind(body, garmentPoints(m, 0.01));
    ASSERT_TRUE(binding.isOk()) << binding.status().message();
    const SkinBinding& b = binding.value();
    const std::size_t n = b.size();
    CharacterPose pose(ch);
    ASSERT_TRUE(pose.evaluate(ch, ch.findClip("run"), 0.3, ClipWrap::Loop).isOk());
    std::vector<Vec3> skinned(body.vertexCount()), skinnedNormals(body.vertexCount());
    ASSERT_TRUE(skinVertices(body, pose.skinMatrices(), skinned, skinnedNormals).isOk());
    std::vector<Vec3> t0(n), p0(n), n0(n), t1(n), p1(n), n1(n);
    ASSERT_TRUE(b.evaluate(body, pose.skinMatrices(), t0, p0, n0).isOk());
    ASSERT_TRUE(b.evaluateSkinned(body, skinned, skinnedNormals, pose.skinMatrices(), t1, p1, n1).isOk());
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_LT((t0[i] - t1[i]).norm(), 1e-12) << i;
        ASSERT_LT((p0[i] - p1[i]).norm(), 1e-12) << i;
        ASSERT_LT((n0[i] - n1[i]).norm(), 1e-12) << i;
    }
    // A host moves the whole bind-pose body rigidly (no skin matrices): targets move with it.
    const Quat q(Eigen::AngleAxisd(0.9, Vec3(0.2, 1, 0.1).normalized()));
    const Vec3 shift(3, 0.5, -2);
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        skinned[v] = q * body.bindPositions[v] + shift;
        skinnedNormals[v] = q * body.bindNormals[v];
    }
    ASSERT_TRUE(b.evaluateSkinned(body, skinned, skinnedNormals, {}, t1, p1, n1).isOk());
    CharacterPose rest(ch);
    ASSERT_TRUE(b.evaluate(body, rest.skinMatrices(), t0, p0, n0).isOk());
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_LT((t1[i] - (q * t0[i] + shift)).norm(), 1e-12) << i;
        ASSERT_LT((n1[i] - q * n0[i]).norm(), 1e-12) << i;
    }
    std::vector<Vec3> wrong(3);
    EXPECT_FALSE(b.evaluateSkinned(body, wrong, wrong, {}, t1, p1, n1).isOk());
}

TEST(SkinBinding, GridSearchFindsTheBruteForceClosestPoint) {
    const Mannequin m = build();
    const SkinnedMesh& body = m.character.body;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ux(-0.5, 0.5), uy(0.0, 1.85), uz(-0.3, 0.3);
    std::vector<Vec3> pts;
    while (pts.size() < 200) pts.push_back({ux(rng), uy(rng), uz(rng)});
    SkinBindingSettings settings;
    settings.maxBindDistance = 1.0;
    Result<SkinBinding> binding = SkinBinding::bind(body, pts, settings);
    ASSERT_TRUE(binding.isOk()) << binding.status().message();
    for (std::size_t i = 0; i < pts.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& tri : body.triangles) {
            std::array<double, 3> bary;
            best = std::min(best, (closestPointOnTriangle(pts[i], body.bindPositions[tri[0]], body.bindPositions[tri[1]],
                                                          body.bindPositions[tri[2]], bary) - pts[i]).norm());
        }
        EXPECT_NEAR(binding.value().vertices()[i].offset.norm(), best, 1e-12) << "point " << i;
    }
}

TEST(SkinBinding, ClosestPointOnTriangleBeatsEverySampledPoint) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0), s(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
        const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
        std::array<double, 3> bary;
        const Vec3 q = closestPointOnTriangle(p, a, b, c, bary);
        EXPECT_LT((bary[0] * a + bary[1] * b + bary[2] * c - q).norm(), 1e-12);
        EXPECT_GE(std::min({bary[0], bary[1], bary[2]}), -1e-12);
        const double d = (q - p).norm();
        for (int k = 0; k < 200; ++k) {
            double x = s(rng), y = s(rng);
            if (x + y > 1) { x = 1 - x; y = 1 - y; }
            const Vec3 r = a + x * (b - a) + y * (c - a);
            ASSERT_LE(d, (r - p).norm() + 1e-12);
        }
    }
}

TEST(SkinBinding, BadInputNamesTheVertex) {
    const Mannequin m = build();
    std::vector<Vec3> pts = {{0, 1.0, 0.2}, {0, 1.0, 5.0}};
    Result<SkinBinding> r = SkinBinding::bind(m.character.body, pts);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("garment vertex 1"), std::string::npos) << r.status().message();
    pts[1] = {std::nan(""), 0, 0};
    r = SkinBinding::bind(m.character.body, pts);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("garment vertex 1"), std::string::npos) << r.status().message();
    // Evaluating against another body is refused.
    pts.pop_back();
    r = SkinBinding::bind(m.character.body, pts);
    ASSERT_TRUE(r.isOk());
    MannequinParams other;
    other.height = 1.7;
    Mannequin m2 = buildMannequin(other).value();
    m2.character.body.bindPositions.pop_back();
    std::vector<Mat4> skin(m2.character.skeleton.jointCount(), Mat4::Identity());
    std::vector<Vec3> out(1);
    EXPECT_FALSE(r.value().evaluate(m2.character.body, skin, out, {}, {}).isOk());
}

TEST(MotionConstraints, MaxDistanceClampsOntoTheSphereAndStopsOutwardMotion) {
    const std::vector<Vec3> targets = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}};
    const std::vector<double> radius = {0.1, 0.1, -1.0};
    std::vector<Vec3> x = {{0.3, 0.4, 0}, {1.05, 0, 0}, {9, 9, 9}};
    std::vector<Vec3> v = {{3, 4, 1}, {1, 0, 0}, {1, 1, 1}};
    MotionConstraintStats stats;
    ASSERT_TRUE(applyMotionConstraints(targets, radius, {}, {}, {}, x, v, &stats).isOk());
    EXPECT_LT((x[0] - Vec3(0.06, 0.08, 0)).norm(), 1e-15);
    EXPECT_LT((v[0] - Vec3(0, 0, 1)).norm(), 1e-12) << "radial outward velocity removed, tangential kept";
    EXPECT_EQ(x[1], Vec3(1.05, 0, 0)) << "inside the sphere: untouched";
    EXPECT_EQ(v[1], Vec3(1, 0, 0));
    EXPECT_EQ(x[2], Vec3(9, 9, 9)) << "negative radius = free";
    EXPECT_EQ(stats.maxDistanceClamped, 1u);
    // Inward velocity of a clamped vertex is kept.
    x = {{0.3, 0.4, 0}};
    v = {{-3, -4, 0}};
    ASSERT_TRUE(applyMotionConstraints(Span<const Vec3>(targets.data(), 1), Span<const double>(radius.data(), 1), {}, {}, {}, x, v).isOk());
    EXPECT_EQ(v[0], Vec3(-3, -4, 0));
}

TEST(MotionConstraints, BackstopKeepsVerticesInFrontOfTheSurface) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const std::size_t n = 500;
    std::vector<Vec3> targets(n), points(n), normals(n), x(n), v(n);
    std::vector<double> radius(n);
    for (std::size_t i = 0; i < n; ++i) {
        points[i] = {u(rng), u(rng), u(rng)};
        normals[i] = Vec3(u(rng), u(rng), u(rng)).normalized();
        targets[i] = points[i] + 0.02 * normals[i];
        radius[i] = 0.05 + 0.05 * std::abs(u(rng));
        x[i] = targets[i] + 0.2 * Vec3(u(rng), u(rng), u(rng));
        v[i] = {u(rng), u(rng), u(rng)};
    }
    MotionConstraintSettings settings;
    settings.backstopOffset = 0.005;
    const std::vector<Vec3> v0 = v;
    MotionConstraintStats stats;
    ASSERT_TRUE(applyMotionConstraints(targets, radius, points, normals, settings, x, v, &stats).isOk());
    EXPECT_GT(stats.backstopClamped, 0u);
    EXPECT_GT(stats.maxDistanceClamped, 0u);
    for (std::size_t i = 0; i < n; ++i) {
        // The target is 0.02 in front and the sphere radius >= 0.05, so both constraints can hold.
        EXPECT_GE((x[i] - points[i]).dot(normals[i]), settings.backstopOffset - 1e-12) << i;
        EXPECT_LE((x[i] - targets[i]).norm(), radius[i] + 1e-12) << i;
        EXPECT_TRUE(isFinite(v[i]));
        // Velocities only lose components; they never gain speed.
        EXPECT_LE(v[i].norm(), v0[i].norm() + 1e-12) << i;
    }
    // A vertex exactly on the backstop moving into the body loses that normal component.
    std::vector<Vec3> x1 = {{0, -0.01, 0}}, v1 = {{1, -2, 0}};
    const std::vector<Vec3> p1 = {{0, 0, 0}}, n1 = {{0, 1, 0}};
    ASSERT_TRUE(applyMotionConstraints({}, {}, p1, n1, {}, x1, v1).isOk());
    EXPECT_EQ(x1[0], Vec3(0, 0, 0));
    EXPECT_EQ(v1[0], Vec3(1, 0, 0));
}

TEST(MotionConstraints, MismatchedSpansAreRejected) {
    std::vector<Vec3> x(3), t(2);
    std::vector<double> r(3, 0.1);
    EXPECT_FALSE(applyMotionConstraints(t, r, {}, {}, {}, x, {}).isOk());
}

} // namespace
} // namespace cc
