// Flared (annular sector) panels: the rest shape, its inverse, placement, and every 4-8 level of
// flared skirts, capes and two-panel dresses laid out edge to edge.
#include <cmath>

#include <gtest/gtest.h>

#include "crowdcloth/lod/GarmentHierarchy.h"
#include "lod/MeshChecks.h"

namespace cc::lod {
namespace {


PanelDesc flared(PanelShape shape, double top, double hem, double height, uint32_t columns, uint32_t rows) {
    PanelDesc d;
    d.shape = shape;
    d.width = top;
    d.hemWidth = hem;
    d.height = height;
    d.columns = columns;
    d.rows = rows;
    return d;
}

/// Area and open border of the base grid's rest polygon (what every level's triangles cover).
test::GarmentExpectation expectationOf(const GarmentPattern& p, int euler) {
    test::GarmentExpectation e;
    e.eulerCharacteristic = euler;
    for (std::size_t panel = 0; panel < p.panels.size(); ++panel) {
        const PanelDesc& d = p.panels[panel];
        for (uint32_t j = 0; j < d.rows; ++j)
            for (uint32_t i = 0; i < d.columns; ++i) {
                const Vec2 a = d.rest(double(i) / d.columns, double(j) / d.rows), b = d.rest(double(i + 1) / d.columns, double(j) / d.rows);
                const Vec2 c = d.rest(double(i + 1) / d.columns, double(j + 1) / d.rows), f = d.rest(double(i) / d.columns, double(j + 1) / d.rows);
                const auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
                e.area += 0.5 * (cross(b - a, c - a) + cross(c - a, f - a));
            }
        for (uint32_t i = 0; i < d.columns; ++i)
            for (double t : {0.0, 1.0}) e.boundaryLength += (d.rest(double(i + 1) / d.columns, t) - d.rest(double(i) / d.columns, t)).norm();
        if (d.shape == PanelShape::Tube) continue;
        for (PanelSide side : {PanelSide::Left, PanelSide::Right}) {
            bool sewn = false;
            for (const Seam& seam : p.seams)
                sewn = sewn || (seam.panelA == panel && seam.sideA == side) || (seam.panelB == panel && seam.sideB == side);
            if (!sewn) e.boundaryLength += d.height;
        }
    }
    return e;
}

TEST(FlaredPanel, RestShapeIsAnAnnularSectorAndGridOfInvertsIt) {
    PanelDesc d = flared(PanelShape::Rectangle, 0.4, 1.0, 0.6, 6, 3);
    d.chartOrigin = Vec2(0.3, -0.2);
    d.chartAngle = 0.7;
    // Top and hem arcs have the asked lengths, the sides are radii of the panel's height.
    double top = 0.0, hem = 0.0;
    for (int k = 0; k < 1000; ++k) {
        top += (d.rest((k + 1) / 1000.0, 1.0) - d.rest(k / 1000.0, 1.0)).norm();
        hem += (d.rest((k + 1) / 1000.0, 0.0) - d.rest(k / 1000.0, 0.0)).norm();
    }
    EXPECT_NEAR(top, 0.4, 1e-6);
    EXPECT_NEAR(hem, 1.0, 1e-6);
    EXPECT_NEAR((d.rest(0.0, 1.0) - d.rest(0.0, 0.0)).norm(), 0.6, 1e-12);
    for (double s : {0.0, 0.13, 0.5, 0.99})
        for (double t : {0.0, 0.4, 1.0}) {
            const Vec2 st = d.gridOf(d.rest(s, t));
            EXPECT_NEAR(st.x(), s, 1e-12);
            EXPECT_NEAR(st.y(), t, 1e-12);
        }
    // Rows stay square to columns: the sector's radii meet its arcs at right angles.
    const Vec2 alongRow = d.rest(0.51, 0.5) - d.rest(0.49, 0.5), alongColumn = d.rest(0.5, 0.51) - d.rest(0.5, 0.49);
    EXPECT_NEAR(alongRow.normalized().dot(alongColumn.normalized()), 0.0, 1e-9);
}

TEST(FlaredPanel, TubesPlaceAsConesWithTheirRestLengths) {
    const PanelDesc d = flared(PanelShape::Tube, 0.8, 1.6, 0.5, 32, 8);
    for (double t : {0.0, 0.5, 1.0}) {
        double ring = 0.0;
        for (int k = 0; k < 32; ++k) ring += (d.place((k + 1) / 32.0, t) - d.place(k / 32.0, t)).norm();
        const double rest = 0.8 + (1.0 - t) * 0.8;
        EXPECT_NEAR(ring, rest * std::sin(kPi / 32) / (kPi / 32), 1e-9) << "a ring's chords, t = " << t;
    }
    EXPECT_NEAR((d.place(0.3, 1.0) - d.place(0.3, 0.0)).norm(), 0.5, 1e-9) << "the slant is the panel's height";
}

TEST(FlaredPanel, BadFlaresAreRefusedNamingTheField) {
    GarmentPattern p;
    p.panels.push_back(flared(PanelShape::Tube, 0.8, 0.5, 0.5, 8, 2));
    EXPECT_NE(p.validate().message().find("hemWidth"), std::string::npos);
    p.panels[0].hemWidth = 0.8 + 2.0 * kPi * 0.5 + 0.1;  // more than a full circle
    EXPECT_NE(p.validate().message().find("hemWidth"), std::string::npos);
    p.panels[0].hemWidth = 0.8 + 2.0 * kPi * 0.5;  // exactly a circle skirt
    EXPECT_TRUE(p.validate().isOk()) << p.validate().message();
}

TEST(FlaredPanel, EveryLevelOfFlaredGarmentsIsConforming) {
    std::vector<std::pair<GarmentPattern, int>> patterns;
    patterns.push_back({GarmentPattern::skirt(0.8, 0.5, 0.15, 1.6).value(), 0});
    patterns.push_back({GarmentPattern::skirt(0.8, 0.5, 0.15, 0.8 + 2.0 * kPi * 0.5).value(), 0});  // circle skirt
    {
        GarmentPattern cape;
        cape.panels.push_back(flared(PanelShape::Rectangle, 0.5, 1.1, 0.9, 6, 4));
        patterns.push_back({cape, 1});
    }
    {
        // A dress: front and back sewn at both sides, the back drafted beside the front.
        GarmentPattern dress;
        PanelDesc front = flared(PanelShape::Rectangle, 0.45, 0.8, 0.8, 4, 4);
        PanelDesc back = front;
        const double flare = back.flareAngle();
        const Vec2 apex(0.5 * back.width, back.height + back.width / flare);
        back.chartAngle = flare;
        back.chartOrigin = apex - Eigen::Rotation2Dd(flare) * apex;
        dress.panels = {front, back};
        dress.seams.push_back({0, PanelSide::Right, 1, PanelSide::Left, false});
        dress.seams.push_back({0, PanelSide::Left, 1, PanelSide::Right, false});
        patterns.push_back({dress, 0});
        EXPECT_LT((back.rest(0.0, 0.5) - front.rest(1.0, 0.5)).norm(), 1e-12) << "the sewn sides meet in the pattern plane";
    }
    for (const auto& [pattern, euler] : patterns) {
        auto h = GarmentHierarchy::create(pattern, HierarchySettings{});
        ASSERT_TRUE(h.isOk()) << h.status().message();
        const test::GarmentExpectation expect = expectationOf(pattern, euler);
        for (uint32_t level : {0u, 1u, 3u, 5u}) {
            ASSERT_TRUE(h.value().setUniformLevel(level));
            EXPECT_EQ(test::checkConforming(h.value(), expect), "") << "level " << level;
            EXPECT_NEAR(h.value().totalMass(), 0.15 * expect.area, 1e-12) << "mass from the sector's rest area";
        }
    }
}

} // namespace
} // namespace cc::lod
