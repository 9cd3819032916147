// BodyCollider::queryContinuous: Embree-gathered swept candidates against brute force over every
// triangle, across refits and a rebuild.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/BodyMeshes.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/Ccd.h"

using namespace cc;
using namespace cc::collision;

TEST(ContinuousContacts, MatchBruteForceOverEveryTriangleAcrossRefits) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto device = CollisionDevice::create({}).value();
    test::BodyMesh m = test::uvSphere(Vec3(0, 1, 0), 0.2, 8, 12);
    auto body = BodyCollider::create(*device, m.triangles, m.positions).value();
    ContactQuery query;
    query.thickness = 0.01;
    int hits = 0;
    for (int frame = 0; frame < 6; ++frame) {
        // The body moves (a shift plus a wobble); at frame 3 far enough to force a rebuild.
        const std::vector<Vec3> before = m.positions;
        const Vec3 shift = frame == 3 ? Vec3(0.3, 0.1, 0) : Vec3(0.03 * u(rng), 0.03 * u(rng), 0.03 * u(rng));
        for (Vec3& p : m.positions) p += shift + 0.01 * Vec3(u(rng), u(rng), u(rng));
        ASSERT_TRUE(body->update(m.positions, 1.0 / 60).isOk());
        // Points moving through the region the body sweeps.
        std::vector<Vec3> start, end;
        for (int i = 0; i < 400; ++i) {
            const Vec3 c = Vec3(0, 1, 0) + shift + 0.3 * Vec3(u(rng), u(rng), u(rng));
            start.push_back(c);
            end.push_back(c + 0.15 * Vec3(u(rng), u(rng), u(rng)));
        }
        std::vector<Contact> contacts;
        ASSERT_TRUE(body->queryContinuous(start, end, query, contacts).isOk());
        std::size_t next = 0;
        for (uint32_t i = 0; i < start.size(); ++i) {
            // Brute force with the collider's documented rule: first touch within thickness / 4,
            // only from the outer side of a triangle at the start, only ending less than the
            // thickness above its plane.
            CcdSettings ccd;
            ccd.thickness = 0.25 * query.thickness;
            ccd.distanceTolerance = 0.5 * ccd.thickness;
            ccd.timeTolerance = 1e-3;
            double first = 2.0;
            for (const auto& t : m.triangles) {
                const Vec3 &a0 = before[t[0]], &b0 = before[t[1]], &c0 = before[t[2]];
                if ((start[i] - a0).dot((b0 - a0).cross(c0 - a0)) < 0.0) continue;
                const Vec3 &a1 = m.positions[t[0]], &b1 = m.positions[t[1]], &c1 = m.positions[t[2]];
                if ((end[i] - a1).dot((b1 - a1).cross(c1 - a1).normalized()) >= query.thickness) continue;
                CcdHit hit;
                if (vertexTriangleCcd({start[i], a0, b0, c0}, {end[i], m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]},
                                      ccd, hit) == CcdOutcome::Contact) {
                    first = std::min(first, hit.toi);
                }
            }
            const bool reported = next < contacts.size() && contacts[next].vertex == i;
            EXPECT_EQ(reported, first <= 1.0) << "frame " << frame << " point " << i;
            if (!reported) continue;
            EXPECT_EQ(contacts[next].time, first) << "frame " << frame << " point " << i;
            EXPECT_EQ(contacts[next].source, ContactSource::Continuous);
            ++next;
            ++hits;
        }
        EXPECT_EQ(next, contacts.size());
    }
    EXPECT_GE(body->stats().rebuilds, 2u);
    EXPECT_GT(hits, 50);
}
