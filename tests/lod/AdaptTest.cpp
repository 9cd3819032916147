#include <gtest/gtest.h>

#include "crowdcloth/lod/GarmentHierarchy.h"
#include "lod/MeshChecks.h"

namespace cc::lod {
namespace {

/// Folds the sheet about the line x = 0 by `angle` [rad]: the x > 0 half rises out of the XY plane.
void fold(GarmentHierarchy& h, double angle) {
    for (uint32_t v = 0; v < h.vertexCount(); ++v) {
        if (!h.isActive(v)) continue;
        Vec3 p = h.position(v);
        if (p.x() > 0.0) p = Vec3(p.x() * std::cos(angle), p.y(), p.x() * std::sin(angle));
        ASSERT_TRUE(h.setState(v, p, Vec3::Zero()));
    }
}

TEST(Adapt, RefinesAlongAFoldAndCoarsensAfterTheQuietFrames) {
    auto h = GarmentHierarchy::create(GarmentPattern::cape(1.0, 1.0, 0.25).value(), HierarchySettings{}).value();
    RefinementSettings criteria;
    criteria.maxDihedralAngle = 0.3;
    criteria.maxLevel = 6;
    criteria.quietFrames = 5;
    fold(h, 1.0);
    for (int frame = 0; frame < 8; ++frame) ASSERT_TRUE(h.adapt(criteria, {}).isOk());
    // New vertices sit at world midpoints, so the T-junction check still applies after the fold.
    EXPECT_EQ(test::checkConforming(h, {1.0, 4.0, 1}), "");
    // Only triangles touching the fold line x = 0 refine to the finest level.
    uint32_t finest = 0;
    for (uint32_t t : h.activeTriangles()) {
        const auto& tri = h.triangle(t);
        double minX = 1e9, maxX = -1e9;
        for (const Vec2& r : tri.rest) {
            minX = std::min(minX, r.x() - 0.5);
            maxX = std::max(maxX, r.x() - 0.5);
        }
        if (tri.level == 6) {
            ++finest;
            EXPECT_LE(minX, 1e-12);
            EXPECT_GE(maxX, -1e-12);
        }
    }
    EXPECT_GT(finest, 0u);
    const uint32_t refined = h.activeVertexCount();
    EXPECT_LT(refined, 1089u / 2);  // far fewer than uniform level 6
    // Flatten: nothing merges for quietFrames - 1 calls, then the fold region coarsens back.
    for (uint32_t v = 0; v < h.vertexCount(); ++v) {
        if (h.isActive(v)) {
            ASSERT_TRUE(h.setState(v, Vec3(h.position(v).x(), h.position(v).y(), 0.0), Vec3::Zero()));
        }
    }
    for (uint32_t frame = 0; frame + 1 < criteria.quietFrames; ++frame) {
        EXPECT_EQ(h.adapt(criteria, {}).value().coarsened, 0u) << frame;
    }
    uint32_t merged = 0;
    for (int frame = 0; frame < 40; ++frame) merged += h.adapt(criteria, {}).value().coarsened;
    EXPECT_GT(merged, 0u);
    EXPECT_EQ(h.activeVertexCount(), 25u);  // back to the base grid
}

TEST(Adapt, SameInputGivesTheSameMesh) {
    RefinementSettings criteria;
    criteria.maxDihedralAngle = 0.2;
    criteria.vertexBudget = 200;
    std::vector<std::vector<uint32_t>> meshes;
    for (int run = 0; run < 2; ++run) {
        auto h = GarmentHierarchy::create(GarmentPattern::dress(0.6, 0.9, 0.15).value(), HierarchySettings{}).value();
        for (int frame = 0; frame < 6; ++frame) {
            fold(h, 0.3 * frame);
            ASSERT_TRUE(h.adapt(criteria, {}).isOk());
        }
        meshes.push_back(h.activeTriangles());
        EXPECT_LE(h.activeVertexCount(), 200u + 20u);
    }
    EXPECT_EQ(meshes[0], meshes[1]);
}

TEST(Adapt, VertexBudgetAndProximityAndView) {
    auto h = GarmentHierarchy::create(GarmentPattern::cape(1.0, 1.0, 0.25).value(), HierarchySettings{}).value();
    RefinementSettings criteria;
    criteria.maxDihedralAngle = 0.0;
    criteria.proximityDistance = 0.05;
    criteria.maxLevel = 8;
    criteria.vertexBudget = 300;
    // The body touches the left edge (x = -0.5).
    for (int frame = 0; frame < 20; ++frame) {
        const ActiveMesh active = h.activeMesh();
        std::vector<double> distance(active.simToVertex.size());
        for (std::size_t i = 0; i < distance.size(); ++i) distance[i] = active.mesh.positions[i].x() + 0.5;
        AdaptInput input;
        input.bodyDistance = distance;
        auto stats = h.adapt(criteria, input);
        ASSERT_TRUE(stats.isOk()) << stats.status().message();
    }
    // The budget holds to within one forced-split chain, and the detail is by the body.
    EXPECT_LE(h.activeVertexCount(), criteria.vertexBudget + 2 * criteria.maxLevel);
    EXPECT_GT(h.activeVertexCount(), criteria.vertexBudget / 2);
    double leftLevels = 0, rightLevels = 0;
    int left = 0, right = 0;
    for (uint32_t t : h.activeTriangles()) {
        const double u = h.triangle(t).rest[0].x();
        (u < 0.5 ? leftLevels : rightLevels) += h.triangle(t).level;
        ++(u < 0.5 ? left : right);
    }
    EXPECT_GT(leftLevels / left, rightLevels / right + 2.0);

    // View-dependent: a camera 1 m in front of the sheet, 800 px wide, 60 degree field of view.
    auto v = GarmentHierarchy::create(GarmentPattern::cape(1.0, 1.0, 0.25).value(), HierarchySettings{}).value();
    const double f = 1.0 / std::tan(0.5 * 1.047), nearPlane = 0.1, farPlane = 10.0;
    Mat4 proj = Mat4::Zero();
    proj(0, 0) = f;
    proj(1, 1) = f;
    proj(2, 2) = -(farPlane + nearPlane) / (farPlane - nearPlane);
    proj(2, 3) = -2.0 * farPlane * nearPlane / (farPlane - nearPlane);
    proj(3, 2) = -1.0;
    Mat4 viewMatrix = Mat4::Identity();
    viewMatrix(2, 3) = -1.0;  // camera at z = +1 looking down -z
    const Mat4 vp = proj * viewMatrix;
    RefinementSettings pixels;
    pixels.maxDihedralAngle = 0.0;
    pixels.maxEdgePixels = 40.0;
    AdaptInput input;
    input.viewProjection = &vp;
    input.viewportWidth = input.viewportHeight = 800.0;
    for (int frame = 0; frame < 20; ++frame) ASSERT_TRUE(v.adapt(pixels, input).isOk());
    // Closed form: the sheet spans 800 / (2 tan 30deg) px = 693 px across; edges of level L are
    // 0.25 m / 2^(L/2) (axis-aligned, even L) or that times sqrt(2) for the longest edge, so the
    // longest edge is below 40 px from level 6 on (0.25 * sqrt(2) / 8 * 693 = 30.6 px; level 5 is 43 px).
    for (uint32_t t : v.activeTriangles()) EXPECT_GE(v.triangle(t).level, 6u);
    EXPECT_EQ(test::checkConforming(v, {1.0, 4.0, 1}), "");
}

} // namespace
} // namespace cc::lod
