// BodyCollider::traceRays: how many closed parts a point is inside, and where a ray from it enters
// and leaves the body, against spheres' closed forms; open surfaces have no inside unless the
// caller counts them (RayParts::All); bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "collision/BodyMeshes.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/BodyTopology.h"

using namespace cc;
using namespace cc::collision;

namespace {

/// Two overlapping spheres as one body of two parts: A (radius 1 at the origin) and B (radius 0.5
/// at x = 0.8), fine enough that the polygons are within 2 mm of the spheres.
test::BodyMesh twoSpheres() {
    test::BodyMesh body = test::uvSphere(Vec3::Zero(), 1.0, 48, 96);
    const test::BodyMesh b = test::uvSphere(Vec3(0.8, 0.0, 0.0), 0.5, 48, 96);
    const uint32_t offset = uint32_t(body.positions.size());
    body.positions.insert(body.positions.end(), b.positions.begin(), b.positions.end());
    for (auto t : b.triangles) body.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    return body;
}

std::unique_ptr<BodyCollider> colliderOf(CollisionDevice& device, const test::BodyMesh& m) {
    return BodyCollider::create(device, m.triangles, m.positions).value();
}

RayTrace trace(const BodyCollider& body, const Vec3& origin, const Vec3& direction,
               RayParts parts = RayParts::Closed) {
    RayTrace out;
    const Vec3 d = direction.normalized();
    EXPECT_TRUE(body.traceRays(Span<const Vec3>(&origin, 1), Span<const Vec3>(&d, 1), parts,
                               Span<RayTrace>(&out, 1))
                    .isOk());
    return out;
}

constexpr double kPolygonTolerance = 2e-3;  // [m] the spheres' polygons against their closed forms

TEST(RayTrace, CountsThePartsAPointIsInAndWhereTheRayEntersAndLeavesTheBody) {
    auto device = CollisionDevice::create({}).value();
    const auto body = colliderOf(*device, twoSpheres());
    // In A only; the ray enters B at x = 0.3 and leaves A at x = 1 inside B, so the body ends
    // where it leaves B, at x = 1.3.
    RayTrace t = trace(*body, Vec3(0.0, 0.0, 0.0), Vec3::UnitX());
    EXPECT_EQ(t.partsInside, 1);
    EXPECT_NEAR(t.firstExit, 1.3, kPolygonTolerance);
    // The other way it leaves A at x = -1, and meets nothing after.
    t = trace(*body, Vec3(0.0, 0.0, 0.0), -Vec3::UnitX());
    EXPECT_EQ(t.partsInside, 1);
    EXPECT_NEAR(t.firstExit, 1.0, kPolygonTolerance);
    // In both at x = 0.9: up, it leaves A at y = sqrt(1 - 0.81) while still in B, which it
    // leaves at y = sqrt(0.25 - 0.01).
    t = trace(*body, Vec3(0.9, 0.0, 0.0), Vec3::UnitY());
    EXPECT_EQ(t.partsInside, 2);
    EXPECT_NEAR(t.firstExit, std::sqrt(0.24), kPolygonTolerance);
    // Outside, whether the ray passes through the body or away from it: no exit. Where it first
    // enters the body: towards it, B at x = 1.3; away from it, nowhere.
    for (const Vec3& d : {Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(-1.0, 0.1, 0.05)}) {
        t = trace(*body, Vec3(2.0, 0.0, 0.0), d);
        EXPECT_EQ(t.partsInside, 0);
        EXPECT_EQ(t.firstExit, -1.0);
    }
    EXPECT_NEAR(trace(*body, Vec3(2.0, 0.0, 0.0), -Vec3::UnitX()).firstEntry, 0.7,
                kPolygonTolerance);
    EXPECT_EQ(trace(*body, Vec3(2.0, 0.0, 0.0), Vec3::UnitX()).firstEntry, -1.0);
    // A line 0.3 from B's centre enters it at the chord's near end, x = 0.8 + sqrt(0.25 - 0.09)
    // = 1.2.
    EXPECT_NEAR(trace(*body, Vec3(2.0, 0.0, 0.3), -Vec3::UnitX()).firstEntry, 0.8,
                kPolygonTolerance);
    // From inside A it enters B, which it is not in, at x = 0.3.
    EXPECT_NEAR(trace(*body, Vec3::Zero(), Vec3::UnitX()).firstEntry, 0.3, kPolygonTolerance);
    // Through a pole vertex and along ring edges, where a ray meets several triangles at one
    // point: each crossing counts once.
    t = trace(*body, Vec3(0.0, -0.2, 0.0), Vec3::UnitY());
    EXPECT_EQ(t.partsInside, 1);
    EXPECT_NEAR(t.firstExit, 1.2, 1e-6);
}

TEST(RayTrace, AnOpenSurfaceHasNoInside) {
    // A sphere with one triangle missing is not closed (BodyTopology::partClosed): rays pass its
    // surface as if it were not there, and the closed sphere beside it still counts.
    test::BodyMesh open = test::uvSphere(Vec3::Zero(), 1.0, 16, 32);
    open.triangles.pop_back();
    const test::BodyMesh closed = test::uvSphere(Vec3(0.5, 0.0, 0.0), 0.3, 16, 32);
    test::BodyMesh both = open;
    const uint32_t offset = uint32_t(both.positions.size());
    both.positions.insert(both.positions.end(), closed.positions.begin(), closed.positions.end());
    for (auto t : closed.triangles) both.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    auto topology = BodyTopology::build(both.triangles, both.positions).value();
    ASSERT_EQ(topology->partCount, 2u);
    EXPECT_EQ(topology->partClosed[topology->part.front()], 0);
    EXPECT_EQ(topology->partClosed[topology->part.back()], 1);

    auto device = CollisionDevice::create({}).value();
    const auto body = colliderOf(*device, both);
    EXPECT_EQ(trace(*body, Vec3(-0.5, 0.0, 0.0), Vec3::UnitY()).partsInside, 0);
    const RayTrace t = trace(*body, Vec3(0.5, 0.0, 0.0), Vec3::UnitZ());
    EXPECT_EQ(t.partsInside, 1);
    EXPECT_NEAR(t.firstExit, 0.3, 0.3 * (1.0 - std::cos(M_PI / 16.0)) + 1e-6);
}

TEST(RayTrace, WithOpenPartsCountedARayMeetsThemByTheirWinding) {
    // An imported character's open pieces (a plate, a tube without caps) still stand in a cloth
    // edge's way: RayParts::All counts their faces, outside by winding, where Closed passes them.
    test::BodyMesh open = test::uvSphere(Vec3::Zero(), 1.0, 16, 32);
    open.triangles.pop_back(); // at a pole: rays along the equator meet only whole faces
    auto device = CollisionDevice::create({}).value();
    const auto body = colliderOf(*device, open);
    const Vec3 outside(-2.0, 0.0, 0.0);
    EXPECT_EQ(trace(*body, outside, Vec3::UnitX(), RayParts::Closed).firstEntry, -1.0);
    const double chord = 1.0 - std::cos(M_PI / 32.0); // the 32-gon's face inside the circle
    const RayTrace through = trace(*body, outside, Vec3::UnitX(), RayParts::All);
    EXPECT_NEAR(through.firstEntry, 1.0, chord + 1e-6);
    EXPECT_EQ(through.partsInside, 0); // in and out again
    const RayTrace fromInside = trace(*body, Vec3::Zero(), Vec3::UnitX(), RayParts::All);
    EXPECT_EQ(fromInside.partsInside, 1);
    EXPECT_NEAR(fromInside.firstExit, 1.0, chord + 1e-6);
    EXPECT_EQ(fromInside.firstEntry, -1.0);
}

TEST(RayTrace, AFlippedTriangleOpensTheSurface) {
    // Wound against its neighbours, one triangle makes the outward side ambiguous: no inside.
    test::BodyMesh m = test::uvSphere(Vec3::Zero(), 1.0, 8, 16);
    std::swap(m.triangles[5][1], m.triangles[5][2]);
    auto topology = BodyTopology::build(m.triangles, m.positions).value();
    EXPECT_EQ(topology->partClosed[0], 0);
}

TEST(RayTrace, BadInputGivesClearErrors) {
    auto device = CollisionDevice::create({}).value();
    const auto body = colliderOf(*device, test::uvSphere(Vec3::Zero(), 1.0, 8, 16));
    const Vec3 origin = Vec3::Zero(), unit = Vec3::UnitX(), longer(2.0, 0.0, 0.0);
    const Vec3 nan(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
    RayTrace out[2];
    const Status notUnit =
        body->traceRays(Span<const Vec3>(&origin, 1), Span<const Vec3>(&longer, 1),
                        RayParts::Closed, Span<RayTrace>(out, 1));
    EXPECT_NE(notUnit.message().find("direction 0 is not a unit vector"), std::string::npos) << notUnit.message();
    EXPECT_FALSE(body->traceRays(Span<const Vec3>(&nan, 1), Span<const Vec3>(&unit, 1),
                                 RayParts::Closed, Span<RayTrace>(out, 1))
                     .isOk());
    const Status count = body->traceRays(Span<const Vec3>(&origin, 1), Span<const Vec3>(&unit, 1),
                                         RayParts::Closed, Span<RayTrace>(out, 2));
    EXPECT_NE(count.message().find("one direction and one trace per origin"), std::string::npos) << count.message();
}

} // namespace
