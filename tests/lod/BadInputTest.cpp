#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "crowdcloth/lod/GarmentHierarchy.h"

namespace cc::lod {
namespace {

bool mentions(const Status& s, const char* what) { return !s && s.message().find(what) != std::string::npos; }

TEST(LodBadInput, DegeneratePanelSizesAreRejected) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(mentions(GarmentPattern::cape(0.0, 1.0, 0.25).status(), "width"));
    EXPECT_TRUE(mentions(GarmentPattern::cape(1.0, nan, 0.25).status(), "height"));
    EXPECT_TRUE(mentions(GarmentPattern::cape(1.0, 1.0, -0.1).status(), "cellSize"));
    EXPECT_TRUE(mentions(GarmentPattern::skirt(std::numeric_limits<double>::infinity(), 1.0, 0.1).status(), "circumference"));
    EXPECT_TRUE(mentions(GarmentPattern::poncho(1.0, 1.0, 0.0, 0.25).status(), "depth"));
    GarmentPattern pattern = GarmentPattern::cape(1.0, 1.0, 0.25).value();
    pattern.panels[0].rows = 0;
    EXPECT_TRUE(mentions(pattern.validate(), "panels[0].columns and .rows"));
    pattern.panels[0].rows = 4;
    pattern.panels[0].height = 1e-6;  // sliver squares
    EXPECT_TRUE(mentions(pattern.validate(), "aspect"));
    pattern.panels[0].height = 1.0;
    pattern.panels[0].vAxis = Vec3(1.0, 0.0, 0.0);
    EXPECT_TRUE(mentions(pattern.validate(), "vAxis"));
    GarmentPattern tube = GarmentPattern::skirt(1.0, 1.0, 0.25).value();
    tube.panels[0].columns = 2;
    EXPECT_TRUE(mentions(tube.validate(), "tube"));
    EXPECT_TRUE(mentions(GarmentPattern{}.validate(), "empty"));
}

TEST(LodBadInput, BadSeamsAreRejected) {
    GarmentPattern dress = GarmentPattern::dress(0.6, 0.9, 0.3).value();
    GarmentPattern flipped = dress;
    flipped.seams[0].reversed = true;
    EXPECT_TRUE(mentions(flipped.validate(), "flip"));
    GarmentPattern uneven = dress;
    uneven.panels[1].rows = 5;
    uneven.panels[1].height = 1.5;
    EXPECT_TRUE(mentions(uneven.validate(), "base segments"));
    GarmentPattern twice = dress;
    twice.seams.push_back(twice.seams[0]);
    EXPECT_TRUE(mentions(twice.validate(), "already in a seam"));
    GarmentPattern outOfRange = dress;
    outOfRange.seams[0].panelB = 7;
    EXPECT_TRUE(mentions(outOfRange.validate(), "out of range"));
    // A one-square-wide dress glues both sides of each panel onto the same two vertices.
    EXPECT_FALSE(GarmentHierarchy::create(GarmentPattern::dress(0.3, 0.9, 0.3).value(), HierarchySettings{}).isOk());
}

TEST(LodBadInput, AbsurdLevelsAndBudgetsAreRejected) {
    const GarmentPattern cape = GarmentPattern::cape(1.0, 1.0, 0.25).value();
    HierarchySettings settings;
    settings.maxLevel = 40;
    EXPECT_TRUE(mentions(GarmentHierarchy::create(cape, settings).status(), "maxLevel"));
    settings.maxLevel = 8;
    settings.renderLevel = 9;
    EXPECT_TRUE(mentions(GarmentHierarchy::create(cape, settings).status(), "renderLevel"));
    settings.maxLevel = 20;
    settings.renderLevel = 20;
    EXPECT_TRUE(mentions(GarmentHierarchy::create(cape, settings).status(), "maxRenderVertices"));
    settings = HierarchySettings{};
    settings.arealDensity = 0.0;
    EXPECT_TRUE(mentions(GarmentHierarchy::create(cape, settings).status(), "arealDensity"));

    auto h = GarmentHierarchy::create(cape, HierarchySettings{}).value();
    EXPECT_TRUE(mentions(h.setUniformLevel(11), "maxLevel"));
    RefinementSettings criteria;
    criteria.coarsenFraction = 1.5;
    EXPECT_TRUE(mentions(h.adapt(criteria, {}).status(), "coarsenFraction"));
    criteria = RefinementSettings{};
    criteria.maxDihedralAngle = -1.0;
    EXPECT_TRUE(mentions(h.adapt(criteria, {}).status(), "maxDihedralAngle"));
    criteria = RefinementSettings{};
    criteria.minLevel = 12;
    EXPECT_TRUE(mentions(h.adapt(criteria, {}).status(), "minLevel"));
    criteria = RefinementSettings{};
    const Mat4 view = Mat4::Identity();
    AdaptInput input;
    input.viewProjection = &view;
    EXPECT_TRUE(mentions(h.adapt(criteria, input).status(), "viewport"));
    criteria.proximityDistance = 0.1;
    std::vector<double> distances(3, 0.0);
    AdaptInput near;
    near.bodyDistance = distances;
    EXPECT_TRUE(mentions(h.adapt(criteria, near).status(), "bodyDistance"));
}

TEST(LodBadInput, InvalidOperationsAndStaleStateAreRejected) {
    auto h = GarmentHierarchy::create(GarmentPattern::cape(1.0, 1.0, 0.25).value(), HierarchySettings{}).value();
    EXPECT_TRUE(mentions(h.coarsen(0), "base vertex"));
    EXPECT_TRUE(mentions(h.coarsen(1u << 30), "does not exist"));
    EXPECT_TRUE(mentions(h.refine(1u << 30), "not active"));
    ActiveMesh stale = h.activeMesh();
    ASSERT_TRUE(h.refine(0));
    EXPECT_TRUE(mentions(h.refine(0), "not active"));
    EXPECT_TRUE(mentions(h.readState(stale, stale.mesh.positions, stale.velocities), "stale"));
    ActiveMesh active = h.activeMesh();
    std::vector<Vec3> positions = active.mesh.positions;
    positions[3].x() = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(mentions(h.readState(active, positions, active.velocities), "simulation vertex 3"));
    EXPECT_TRUE(mentions(h.readState(active, positions, {}), "expected"));
    EXPECT_TRUE(mentions(h.setState(0, Vec3::Constant(std::nan("")), Vec3::Zero()), "non-finite"));
    const uint32_t missing[] = {1u << 30};
    EXPECT_TRUE(mentions(h.interpolation(active, Span<const uint32_t>(missing, 1)).status(), "row 0"));
}

} // namespace
} // namespace cc::lod
