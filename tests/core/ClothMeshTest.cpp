#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;

namespace {
ClothMesh twoTriangles() {
    ClothMesh m;
    m.restPositions = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    for (const Vec2& r : m.restPositions) m.positions.push_back(Vec3(r.x(), r.y(), 0));
    m.triangles = {{0, 1, 3}, {0, 3, 2}};
    return m;
}
void expectError(const ClothMesh& m, const char* fragment) {
    const Status s = m.validate();
    ASSERT_FALSE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::InvalidArgument);
    EXPECT_NE(s.message().find(fragment), std::string::npos) << s.message();
}
} // namespace

TEST(ClothMesh, AcceptsAValidMesh) { EXPECT_TRUE(twoTriangles().validate().isOk()); }

TEST(ClothMesh, RejectsZeroAreaTriangleNamingIt) {
    ClothMesh m = twoTriangles();
    m.restPositions[2] = Vec2(0.5, 0.5);  // triangle 1 (0, 3, 2) becomes collinear
    expectError(m, "triangle 1");
    expectError(m, "zero rest area");
}

TEST(ClothMesh, RejectsZeroLengthEdge) {
    ClothMesh m = twoTriangles();
    m.restPositions[3] = m.restPositions[1];
    expectError(m, "zero-length rest edge");
}

TEST(ClothMesh, RejectsNonFinitePositionNamingVertex) {
    ClothMesh m = twoTriangles();
    m.positions[2].y() = std::nan("");
    expectError(m, "vertex 2");
    m = twoTriangles();
    m.restPositions[1].x() = INFINITY;
    expectError(m, "vertex 1");
}

TEST(ClothMesh, RejectsOutOfRangeIndexAndRepeatedVertex) {
    ClothMesh m = twoTriangles();
    m.triangles[1][2] = 7;
    expectError(m, "indexes vertex 7");
    m = twoTriangles();
    m.triangles[0] = {0, 0, 3};
    expectError(m, "repeats a vertex");
}

TEST(ClothMesh, RejectsInvertedTriangleAndEmptyMesh) {
    ClothMesh m = twoTriangles();
    std::swap(m.triangles[0][1], m.triangles[0][2]);
    expectError(m, "clockwise");
    expectError(ClothMesh{}, "no vertices");
}
