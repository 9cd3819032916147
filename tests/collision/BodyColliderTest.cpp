// BodyCollider: closest-point contacts against brute force, refits, signs, degenerate triangles,
// bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "collision/BodyMeshes.h"
#include "crowdcloth/collision/BodyCollider.h"

using namespace cc;
using namespace cc::collision;

namespace {

struct Brute {
    double distance = 1e300;
    Vec3 point;
};

Brute bruteClosest(const test::BodyMesh& m, const Vec3& p) {
    Brute best;
    for (const auto& t : m.triangles) {
        const Vec3 c = test::bruteClosestOnTriangle(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
        const double d = (c - p).norm();
        if (d < best.distance) best = {d, c};
    }
    return best;
}

std::unique_ptr<CollisionDevice> makeDevice() { return CollisionDevice::create({}).value(); }

// Random points in a shell around the sphere, plus every body vertex and edge midpoint (points
// exactly on vertices and edges).
std::vector<Vec3> probePoints(const test::BodyMesh& m, std::mt19937& rng, int count, double spread) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> points;
    for (int i = 0; i < count; ++i) {
        const Vec3& anchor = m.positions[rng() % m.positions.size()];
        points.push_back(anchor + spread * Vec3(u(rng), u(rng), u(rng)));
    }
    for (const Vec3& p : m.positions) points.push_back(p);
    for (const auto& t : m.triangles) points.push_back(0.5 * (m.positions[t[0]] + m.positions[t[1]]));
    return points;
}

void expectMatchesBruteForce(const BodyCollider& body, const test::BodyMesh& m, const std::vector<Vec3>& points,
                             const ContactQuery& query) {
    std::vector<Contact> contacts;
    ASSERT_TRUE(body.queryProximity(points, query, contacts).isOk());
    std::size_t next = 0;
    int expected = 0;
    for (uint32_t i = 0; i < points.size(); ++i) {
        const Brute b = bruteClosest(m, points[i]);
        const bool within = b.distance <= query.reach(i);
        const bool borderline = std::abs(b.distance - query.reach(i)) < 1e-9;
        const bool reported = next < contacts.size() && contacts[next].vertex == i;
        if (!borderline) {
            EXPECT_EQ(within, reported) << "point " << i << " at distance " << b.distance;
        }
        expected += within;
        if (!reported) continue;
        const Contact& c = contacts[next++];
        const double signedDistance = (points[i] - c.point).dot(c.normal);
        EXPECT_NEAR(std::abs(signedDistance), b.distance, 1e-9) << "point " << i;
        EXPECT_NEAR((c.point - points[i]).norm(), b.distance, 1e-9) << "point " << i;
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
        EXPECT_NEAR(c.depth, query.thickness - signedDistance, 1e-12);
    }
    EXPECT_EQ(next, contacts.size()) << "contacts not sorted by vertex or duplicated";
    EXPECT_GT(expected, 10) << "the probe set should produce contacts";
}

} // namespace

TEST(BodyCollider, ProximityMatchesBruteForceOnRandomMeshesAndAfterRefits) {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.01);
    auto device = makeDevice();
    test::BodyMesh m = test::uvSphere(Vec3(0.1, 1.0, -0.2), 0.15, 12, 18);
    for (Vec3& p : m.positions) p += Vec3(noise(rng), noise(rng), noise(rng));  // a lumpy, random body
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    ContactQuery query;
    query.thickness = 0.01;
    query.margin = 0.02;
    expectMatchesBruteForce(*body, m, probePoints(m, rng, 3000, 0.05), query);

    // Animate: every vertex moves by a smooth field plus noise; refits keep the answers exact.
    for (int frame = 1; frame <= 8; ++frame) {
        for (Vec3& p : m.positions) {
            p += Vec3(0.02 * std::sin(3 * p.y() + frame), 0.01 * frame * 0.1, 0.02 * std::cos(5 * p.x())) +
                 Vec3(noise(rng), noise(rng), noise(rng)) * 0.3;
        }
        ASSERT_TRUE(body->update(m.positions, 1.0 / 60).isOk());
        expectMatchesBruteForce(*body, m, probePoints(m, rng, 600, 0.05), query);
    }
    EXPECT_GE(body->stats().refits, 1u);

    // A large displacement forces a full rebuild; answers stay exact.
    const uint64_t rebuilds = body->stats().rebuilds;
    for (Vec3& p : m.positions) p = Vec3(1.3 * p.x(), 0.7 * p.y() + 2.0, p.z() - 1.0);
    ASSERT_TRUE(body->update(m.positions, 1.0 / 60).isOk());
    EXPECT_EQ(body->stats().rebuilds, rebuilds + 1);
    expectMatchesBruteForce(*body, m, probePoints(m, rng, 600, 0.05), query);
}

TEST(BodyCollider, ASharedTopologyAndAResetToAnotherPoseAnswerAsAFreshCollider) {
    // A World builds a body's topology once and hands idle colliders to other characters of the
    // body: a collider on the shared topology, reset from another pose, must answer exactly.
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> noise(-0.002, 0.002);
    auto device = makeDevice();
    test::BodyMesh m = test::uvSphere(Vec3(0.0, 1.0, 0.0), 0.15, 12, 18);
    auto shape = BodyTopology::build(m.triangles, m.positions);
    ASSERT_TRUE(shape.isOk()) << shape.status().message();
    EXPECT_EQ(shape.value()->partCount, 1u);
    auto spare = BodyCollider::create(*device, shape.value(), m.positions).value();
    auto other = BodyCollider::create(*device, shape.value(), m.positions).value();
    ContactQuery query;
    query.thickness = 0.01;
    query.margin = 0.04;
    expectMatchesBruteForce(*spare, m, probePoints(m, rng, 400, 0.05), query);

    // Another character's pose (a smooth bend plus noise), then the collider handed over.
    for (Vec3& p : m.positions)
        p += Vec3(0.03 * std::sin(4 * p.y()), 0.0, 0.02 * std::cos(6 * p.x())) + Vec3(noise(rng), noise(rng), noise(rng));
    ASSERT_TRUE(spare->reset(m.positions).isOk());
    for (const Vec3& v : spare->previousPositions()) ASSERT_TRUE(std::isfinite(v.x()));
    EXPECT_EQ(spare->currentPositions()[7], m.positions[7]);
    EXPECT_EQ(spare->previousPositions()[7], m.positions[7]) << "a reset body does not move";
    expectMatchesBruteForce(*spare, m, probePoints(m, rng, 600, 0.05), query);

    // And the same contacts as a collider made at that pose, bit for bit.
    auto fresh = BodyCollider::create(*device, m.triangles, m.positions).value();
    const std::vector<Vec3> points = probePoints(m, rng, 600, 0.05);
    std::vector<Contact> a, b;
    ASSERT_TRUE(spare->queryProximity(points, query, a).isOk());
    ASSERT_TRUE(fresh->queryProximity(points, query, b).isOk());
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].vertex, b[k].vertex);
        EXPECT_EQ(a[k].point, b[k].point);
        EXPECT_EQ(a[k].normal, b[k].normal);
    }
    EXPECT_EQ(other->triangleCount(), fresh->triangleCount());

    EXPECT_FALSE(BodyCollider::create(*device, std::shared_ptr<const BodyTopology>(), m.positions).isOk());
    std::vector<Vec3> tooFew(m.positions.begin(), m.positions.end() - 1);
    EXPECT_FALSE(BodyCollider::create(*device, shape.value(), tooFew).isOk()) << "a pose must fit the topology";
}

TEST(BodyCollider, PerPointMarginsMatchBruteForce) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto device = makeDevice();
    const test::BodyMesh m = test::uvSphere(Vec3(0.0, 1.0, 0.0), 0.15, 12, 18);
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    const std::vector<Vec3> points = probePoints(m, rng, 3000, 0.12);
    std::vector<double> margins(points.size());
    for (double& x : margins) x = 0.1 * unit(rng) * unit(rng);  // most small, a few wide
    ContactQuery query;
    query.thickness = 0.01;
    query.margin = 1.0;  // ignored while pointMargins is given
    query.pointMargins = margins;
    expectMatchesBruteForce(*body, m, points, query);

    margins.pop_back();
    query.pointMargins = margins;
    std::vector<Contact> contacts;
    Status s = body->queryProximity(points, query, contacts);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("pointMargins"), std::string::npos) << s.message();
    margins.push_back(-0.5);
    query.pointMargins = margins;
    s = body->queryProximity(points, query, contacts);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("pointMargins[" + std::to_string(points.size() - 1) + "]"), std::string::npos)
        << s.message();
}

TEST(BodyCollider, ManyPartsNearAPointGiveItsNearestPartsExactly) {
    // Seven overlapping spheres (a body's limbs, each its own part) around probes that reach all
    // of them: each point gets one contact per part for its 4 nearest parts within reach, each at
    // that part's closest point (the search may shrink once 4 parts are held, never lose one).
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto device = makeDevice();
    test::BodyMesh all;
    std::vector<test::BodyMesh> parts;
    for (int k = 0; k < 7; ++k) {
        const Vec3 centre(0.12 * std::cos(0.9 * k), 1.0 + 0.05 * k, 0.12 * std::sin(0.9 * k));
        parts.push_back(test::uvSphere(centre, 0.07 + 0.01 * k, 8, 12));
        const uint32_t base = uint32_t(all.positions.size());
        for (const Vec3& p : parts.back().positions) all.positions.push_back(p);
        for (const auto& t : parts.back().triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    auto body = BodyCollider::create(*device, all.triangles, all.positions).value();
    std::vector<Vec3> points;
    points.reserve(800);
    for (int i = 0; i < 800; ++i) points.push_back(Vec3(0.0, 1.15, 0.0) + 0.3 * Vec3(u(rng), u(rng), u(rng)));
    ContactQuery query;
    query.thickness = 0.01;
    query.margin = 0.3;
    std::vector<Contact> contacts;
    ASSERT_TRUE(body->queryProximity(points, query, contacts).isOk());
    std::size_t next = 0;
    int withFour = 0;
    for (uint32_t i = 0; i < points.size(); ++i) {
        std::vector<double> distance;
        distance.reserve(parts.size());
        for (const test::BodyMesh& part : parts) distance.push_back(bruteClosest(part, points[i]).distance);
        std::vector<double> within;
        for (double d : distance)
            if (d <= query.reach()) within.push_back(d);
        std::sort(within.begin(), within.end());
        if (within.size() > 4) within.resize(4);
        withFour += within.size() == 4;
        std::vector<double> reported;
        for (; next < contacts.size() && contacts[next].vertex == i; ++next)
            reported.push_back((contacts[next].point - points[i]).norm());
        std::sort(reported.begin(), reported.end());
        ASSERT_EQ(reported.size(), within.size()) << "point " << i;
        for (std::size_t k = 0; k < within.size(); ++k) EXPECT_NEAR(reported[k], within[k], 1e-9) << "point " << i;
    }
    EXPECT_EQ(next, contacts.size());
    EXPECT_GT(withFour, 100) << "the probes should be near more parts than a point keeps";
}

namespace {

/// Probes just outside and inside the sphere's vertices, edges and faces; `m` is that sphere as
/// given (welded or split into pieces), probed at the points of `probe`.
void expectSidesOfSphere(const test::BodyMesh& m, const test::BodyMesh& probe, const Vec3& center) {
    auto device = makeDevice();
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    ContactQuery query;
    query.thickness = 0.01;
    query.margin = 0.05;
    std::vector<Vec3> points;
    std::vector<double> sides;  // +1 outside, -1 inside
    for (const Vec3& p : probe.positions) {
        const Vec3 radial = (p - center).normalized();
        points.push_back(p + 0.02 * radial), sides.push_back(1);   // off a vertex, outside
        points.push_back(p - 0.02 * radial), sides.push_back(-1);  // and inside
    }
    for (const auto& t : probe.triangles) {
        const Vec3 mid = 0.5 * (probe.positions[t[0]] + probe.positions[t[1]]);
        const Vec3 centroid = (probe.positions[t[0]] + probe.positions[t[1]] + probe.positions[t[2]]) / 3.0;
        for (const Vec3& q : {mid, centroid}) {
            const Vec3 radial = (q - center).normalized();
            points.push_back(q + 0.01 * radial), sides.push_back(1);
            points.push_back(q - 0.01 * radial), sides.push_back(-1);
        }
    }
    std::vector<Contact> contacts;
    ASSERT_TRUE(body->queryProximity(points, query, contacts).isOk());
    ASSERT_EQ(contacts.size(), points.size());
    for (const Contact& c : contacts) {
        const Vec3 radial = (points[c.vertex] - center).normalized();
        EXPECT_GT(c.normal.dot(radial), 0.5) << "normal of point " << c.vertex << " does not point outwards";
        const double signedDistance = (points[c.vertex] - c.point).dot(c.normal);
        EXPECT_EQ(signedDistance > 0, sides[c.vertex] > 0) << "point " << c.vertex << " on the wrong side";
    }
}

} // namespace

TEST(BodyCollider, InsideAndOutsideAreToldApartAtFacesEdgesAndVertices) {
    const Vec3 center(0.0, 1.0, 0.0);
    const test::BodyMesh m = test::uvSphere(center, 0.2, 10, 16);
    expectSidesOfSphere(m, m, center);
}

TEST(BodyCollider, ABodySplitAtSeamsIsOneClosedSurface) {
    // Exported skins split vertices at UV and normal seams; split here at every triangle (a
    // flat-shaded export), the sphere must still be one closed part with an inside, not 288
    // open patches each reporting its own contact and side.
    const Vec3 center(0.0, 1.0, 0.0);
    const test::BodyMesh m = test::uvSphere(center, 0.2, 10, 16);
    test::BodyMesh split;
    for (const auto& t : m.triangles) {
        const uint32_t first = uint32_t(split.positions.size());
        for (uint32_t v : t) split.positions.push_back(m.positions[v]);
        split.triangles.push_back({first, first + 1, first + 2});
    }
    expectSidesOfSphere(split, m, center);
}

TEST(BodyCollider, PointsOnTheSurfaceHaveZeroDistanceAndAUnitNormal) {
    auto device = makeDevice();
    const test::BodyMesh m = test::uvSphere(Vec3::Zero(), 0.3, 8, 12);
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    std::vector<Vec3> points = m.positions;  // exactly on vertices
    for (const auto& t : m.triangles) points.push_back(0.25 * m.positions[t[1]] + 0.75 * m.positions[t[2]]);  // on edges
    std::vector<Contact> contacts;
    const ContactQuery query;
    ASSERT_TRUE(body->queryProximity(points, query, contacts).isOk());
    ASSERT_EQ(contacts.size(), points.size());
    for (const Contact& c : contacts) {
        EXPECT_LT((c.point - points[c.vertex]).norm(), 1e-12);
        EXPECT_NEAR(c.depth, query.thickness, 1e-12);
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-9);
        EXPECT_GT(c.normal.dot(points[c.vertex].normalized()), 0.8);
    }
}

TEST(BodyCollider, DegenerateTrianglesAreSkippedAndCounted) {
    // The rule: a triangle with (near) zero area in the current pose is skipped by every query and
    // counted in stats(); its edges are still covered by the neighbours of a closed mesh.
    auto device = makeDevice();
    test::BodyMesh m = test::grid(Vec3(-0.5, 0, 0.5), Vec3(1, 0, 0), Vec3(0, 0, -1), 4);
    const uint32_t a = 0, b = 1;
    m.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));  // collinear: zero area
    m.triangles.push_back({a, b, uint32_t(m.positions.size() - 1)});
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    EXPECT_EQ(body->stats().degenerateTriangles, 1u);
    std::vector<Vec3> points{m.positions.back() + Vec3(0, 0.001, 0), Vec3(0.1, 0.002, 0.1)};
    std::vector<Contact> contacts;
    ASSERT_TRUE(body->queryProximity(points, ContactQuery{}, contacts).isOk());
    ASSERT_EQ(contacts.size(), 2u);
    for (const Contact& c : contacts) {
        EXPECT_NE(c.primitive, m.triangles.size() - 1);
        EXPECT_TRUE(isFinite(c.normal));
        EXPECT_NEAR(c.normal.y(), 1.0, 1e-12);
    }
    // Moving the extra vertex off the line makes the triangle regular again.
    m.positions.back() += Vec3(0, 0, -0.1);
    ASSERT_TRUE(body->update(m.positions, 0.1).isOk());
    EXPECT_EQ(body->stats().degenerateTriangles, 0u);
}

TEST(BodyCollider, BadInputGivesClearErrors) {
    auto device = makeDevice();
    test::BodyMesh m = test::uvSphere(Vec3::Zero(), 0.3, 6, 8);
    {
        auto r = BodyCollider::create(*device, Span<const std::array<uint32_t, 3>>(), m.positions);
        ASSERT_FALSE(r.isOk());
        EXPECT_NE(r.status().message().find("zero triangles"), std::string::npos) << r.status().message();
    }
    {
        auto tris = m.triangles;
        tris[5][2] = 999;
        auto r = BodyCollider::create(*device, tris, m.positions);
        ASSERT_FALSE(r.isOk());
        EXPECT_NE(r.status().message().find("triangle 5"), std::string::npos) << r.status().message();
        EXPECT_NE(r.status().message().find("999"), std::string::npos) << r.status().message();
    }
    {
        auto pos = m.positions;
        pos[3].y() = std::numeric_limits<double>::quiet_NaN();
        auto r = BodyCollider::create(*device, m.triangles, pos);
        ASSERT_FALSE(r.isOk());
        EXPECT_NE(r.status().message().find("body vertex 3"), std::string::npos) << r.status().message();
    }
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    auto pos = m.positions;
    pos[7].x() = std::numeric_limits<double>::infinity();
    Status s = body->update(pos, 1.0 / 60);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("body vertex 7"), std::string::npos) << s.message();
    EXPECT_FALSE(body->update(m.positions, 0.0).isOk());
    EXPECT_FALSE(body->update(std::vector<Vec3>(3, Vec3::Zero()), 0.1).isOk());
    // A rejected update leaves the body as it was.
    EXPECT_EQ((body->currentPositions()[7] - m.positions[7]).norm(), 0.0);

    std::vector<Contact> contacts;
    ContactQuery q;
    q.thickness = -0.01;
    s = body->queryProximity(m.positions, q, contacts);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("thickness"), std::string::npos) << s.message();
    q = ContactQuery{};
    q.margin = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(body->queryProximity(m.positions, q, contacts).isOk());
    std::vector<Vec3> cloth{Vec3::Zero(), Vec3(0, std::nan(""), 0)};
    s = body->queryProximity(cloth, ContactQuery{}, contacts);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("cloth vertex 1"), std::string::npos) << s.message();

    BodyColliderSettings bad;
    bad.rebuildFraction = 0.0;
    auto r = BodyCollider::create(*device, m.triangles, m.positions, bad);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("rebuildFraction"), std::string::npos);
    CollisionDeviceSettings badDevice;
    badDevice.threads = 0;
    EXPECT_FALSE(CollisionDevice::create(badDevice).isOk());
}
