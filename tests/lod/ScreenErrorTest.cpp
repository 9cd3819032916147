// The error metric on constructed cases: a rigid shift of k mm reads k mm, and on screen the
// pixels a pinhole camera at a stated distance and field of view gives (TESTPLAN's "error
// metric" point): the numbers the speed/accuracy tables rest on.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/lod/ScreenError.h"
#include "support/Cameras.h"

namespace cc::lod {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A 1 m x 1 m grid of points in the plane z = 0, centred on the origin.
std::vector<float> grid(int n) {
    std::vector<float> p;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            p.push_back(float(-0.5 + double(i) / (n - 1)));
            p.push_back(float(-0.5 + double(j) / (n - 1)));
            p.push_back(0.0f);
        }
    return p;
}

std::vector<float> shifted(std::vector<float> p, const Vec3& by) {
    for (std::size_t v = 0; v < p.size(); v += 3)
        for (int c = 0; c < 3; ++c) p[v + c] = float(double(p[v + c]) + by[c]);
    return p;
}

SchedulerCamera cameraAt(double distance, double fovY, double width, double height) {
    SchedulerCamera c;
    c.viewProjection = test::perspective(fovY, width / height, 0.05, 100.0) *
                       test::lookAt(Vec3(0.0, 0.0, distance), Vec3::Zero());
    c.viewportWidth = width;
    c.viewportHeight = height;
    return c;
}

TEST(ScreenError, ARigidShiftReadsItsLengthInMetresAndItsPixelsAtTheStatedDistance) {
    const std::vector<float> reference = grid(11);
    const double fovY = kPi / 3.0, distance = 2.5, height = 1080.0;
    const SchedulerCamera camera = cameraAt(distance, fovY, 1920.0, height);
    for (double k : {0.001, 0.004, 0.02}) {
        // Across the view (in the image plane): the pinhole's pixels at the stated distance.
        const MeshDeviation across = meshDeviation(shifted(reference, Vec3(0.0, k, 0.0)).data(), reference.data(),
                                                   reference.size() / 3, &camera);
        EXPECT_NEAR(across.rmsMetres, k, 1e-7);
        EXPECT_NEAR(across.maxMetres, k, 1e-7);
        const double expected = pixelsAtDistance(k, distance, fovY, height);
        EXPECT_NEAR(expected, k / (2.0 * distance * std::tan(fovY / 2.0)) * height, 1e-12);
        EXPECT_NEAR(across.maxPixels, expected, 1e-3 * expected + 1e-4) << k << " m";
        // Every vertex moved alike: the RMS is the same pixels (within the grid's perspective).
        EXPECT_NEAR(across.rmsPixels, expected, 1e-3 * expected + 1e-4) << k << " m";
        EXPECT_LE(across.rmsPixels, across.maxPixels);
        // Along the view: the same distance in metres, far fewer pixels (only the corners move
        // outwards or inwards on screen).
        const MeshDeviation along = meshDeviation(shifted(reference, Vec3(0.0, 0.0, k)).data(), reference.data(),
                                                  reference.size() / 3, &camera);
        EXPECT_NEAR(along.maxMetres, k, 1e-7);
        EXPECT_LT(along.maxPixels, 0.5 * expected);
        EXPECT_GT(along.maxPixels, 0.0);
    }
    // Twice as far, half the pixels.
    const SchedulerCamera farther = cameraAt(2.0 * distance, fovY, 1920.0, height);
    const std::vector<float> moved = shifted(reference, Vec3(0.003, 0.0, 0.0));
    const double near = meshDeviation(moved.data(), reference.data(), reference.size() / 3, &camera).maxPixels;
    const double far = meshDeviation(moved.data(), reference.data(), reference.size() / 3, &farther).maxPixels;
    EXPECT_NEAR(far, 0.5 * near, 1e-3 * near);
}

TEST(ScreenError, TheSameMeshReadsZeroAndOneMovedVertexSetsTheMaximum) {
    const std::vector<float> reference = grid(5);
    const SchedulerCamera camera = cameraAt(3.0, kPi / 4.0, 1280.0, 720.0);
    const MeshDeviation same = meshDeviation(reference.data(), reference.data(), reference.size() / 3, &camera);
    EXPECT_EQ(same.rmsMetres, 0.0);
    EXPECT_EQ(same.maxMetres, 0.0);
    EXPECT_EQ(same.maxPixels, 0.0);
    EXPECT_EQ(same.rmsPixels, 0.0);
    std::vector<float> one = reference;
    one[3 * 7 + 1] += 0.05f;
    const MeshDeviation d = meshDeviation(one.data(), reference.data(), reference.size() / 3, &camera);
    EXPECT_NEAR(d.maxMetres, 0.05, 1e-7);
    EXPECT_NEAR(d.rmsMetres, 0.05 / std::sqrt(25.0), 1e-7);
    // One vertex of 25 moved: the RMS on screen is a fifth of its pixels.
    EXPECT_NEAR(d.rmsPixels, d.maxPixels / std::sqrt(25.0), 1e-9 * d.maxPixels);
    EXPECT_GT(d.maxPixels, 0.0);
    // Without a camera: no pixels.
    EXPECT_EQ(meshDeviation(one.data(), reference.data(), reference.size() / 3).maxPixels, 0.0);
}

TEST(ScreenError, VerticesBehindTheCameraAreLeftOutOfThePixels) {
    std::vector<float> reference = grid(3);
    const SchedulerCamera camera = cameraAt(1.0, kPi / 3.0, 1920.0, 1080.0);
    // Move the whole grid behind the camera (z = 2 > the eye's 1): no pixels, the metres still count.
    const std::vector<float> behind = shifted(reference, Vec3(0.0, 0.0, 2.0));
    const std::vector<float> behindMoved = shifted(behind, Vec3(0.0, 0.01, 0.0));
    const MeshDeviation d = meshDeviation(behindMoved.data(), behind.data(), behind.size() / 3, &camera);
    EXPECT_EQ(d.maxPixels, 0.0);
    EXPECT_EQ(d.rmsPixels, 0.0);
    EXPECT_NEAR(d.maxMetres, 0.01, 1e-7);
    EXPECT_TRUE(std::isfinite(d.rmsMetres));
}

} // namespace
} // namespace cc::lod
