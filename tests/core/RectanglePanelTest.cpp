#include <gtest/gtest.h>

#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;

TEST(RectanglePanel, BuildsA48GridWithAlternatingDiagonals) {
    RectanglePanel panel{2.0, 1.0, 4, 2};
    auto mesh = panel.build();
    ASSERT_TRUE(mesh.isOk()) << mesh.status().message();
    EXPECT_EQ(mesh.value().vertexCount(), 15u);
    EXPECT_EQ(mesh.value().triangles.size(), 16u);
    EXPECT_TRUE(mesh.value().validate().isOk());
    // Interior vertex valences alternate 8 (odd i+j, where four diagonals meet) and 4 (even i+j).
    std::vector<int> valence(15, 0);
    for (const auto& t : mesh.value().triangles)
        for (uint32_t v : t) ++valence[v];
    EXPECT_EQ(valence[panel.vertexIndex(1, 1)], 8);
    EXPECT_EQ(valence[panel.vertexIndex(2, 1)], 4);
}

TEST(RectanglePanel, AreaSumsToPanelArea) {
    RectanglePanel panel{1.5, 0.5, 7, 3};
    const ClothMesh mesh = panel.build().value();
    double area = 0.0;
    for (const auto& t : mesh.triangles) {
        const Vec2 e1 = mesh.restPositions[t[1]] - mesh.restPositions[t[0]];
        const Vec2 e2 = mesh.restPositions[t[2]] - mesh.restPositions[t[0]];
        area += 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());  // positive: counter-clockwise
    }
    EXPECT_NEAR(area, 0.75, 1e-12);
}

TEST(RectanglePanel, RejectsBadParametersByName) {
    RectanglePanel panel;
    panel.width = -1.0;
    auto mesh = panel.build();
    ASSERT_FALSE(mesh.isOk());
    EXPECT_NE(mesh.status().message().find("width"), std::string::npos);
    panel = RectanglePanel{};
    panel.height = std::nan("");
    EXPECT_NE(panel.build().status().message().find("height"), std::string::npos);
    panel = RectanglePanel{};
    panel.columns = 0;
    EXPECT_FALSE(panel.build().isOk());
    panel = RectanglePanel{};
    panel.columns = panel.rows = 100000;
    EXPECT_NE(panel.build().status().message().find("16M"), std::string::npos);
}
