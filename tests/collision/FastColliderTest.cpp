// TESTPLAN C4: a collider swept into a hanging sheet at 0.5, 2, 10 and 50 cloth thicknesses per
// step. With continuous collision no vertex ends inside and the sheet is never crossed, checked
// from the geometry alone (not from the solver's contacts). Discrete mode is run too and its
// tunnelling is recorded.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "collision/BodyMeshes.h"
#include "collision/ContactStepper.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/CapsuleCollider.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::collision;

namespace {

constexpr double kThickness = 0.005;
constexpr double kSpeeds[] = {0.5, 2.0, 10.0, 50.0};  // thicknesses per step

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double s = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - a - s * d).norm();
}

struct SweepResult {
    int insideVertices = 0;  // worst step
    int crossedVertices = 0; // worst step: vertices whose path went through the bar
    int crossingEdges = 0;   // worst step
};

// A sheet hanging in the XY plane (pinned along its top edge) and a horizontal bar along X at
// mid-height moving +Z from z = -0.1 to z = 0.3, then holding still for 10 steps. Either a capsule
// proxy or a mesh body: `body` receives the bar's centre z each step and returns the collider.
// `core(q)` measures a point q given in the bar's own frame (bar centred at y = 0.5, z = 0): < 1
// inside the bar, 1 on its surface.
template <typename Core, typename MakeCollider>
SweepResult sweep(double speed, bool continuous, Core&& core, MakeCollider&& colliderAt) {
    RectanglePanel panel;
    panel.columns = panel.rows = 16;
    panel.origin = Vec3(-0.5, 0.0, 0.0);
    const ClothMesh mesh = panel.build().value();
    cloth::SimulationSettings settings;
    settings.parallel.maxThreads = 1;  // a small sheet: OpenMP fork/join would dominate on 2 cores
    auto sim = cloth::ClothSimulation::create(mesh, cloth::ClothMaterial{}, settings).value();
    for (uint32_t i = 0; i <= panel.columns; ++i) {
        const uint32_t v = panel.vertexIndex(i, panel.rows);
        EXPECT_TRUE(sim->constraints().pin(v, mesh.positions[v]).isOk());
    }
    test::ContactStepper stepper;
    stepper.settings.query.thickness = kThickness;
    stepper.settings.query.margin = kThickness;
    stepper.settings.continuous = continuous;
    stepper.settings.query.parallel.maxThreads = 1;
    stepper.response.friction = {0.3, 0.3};
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) edges.push_back({t[k], t[(k + 1) % 3]});
    }

    const double dt = 1.0 / 60.0;
    const double step = speed * kThickness;
    const int moving = int(std::ceil(0.4 / step));
    SweepResult result;
    double z = -0.1, previousZ = z;
    for (int i = 1; i <= moving + 10; ++i) {
        z = std::min(0.3, z + step);
        const Collider* collider = colliderAt(z, dt);
        const std::vector<const Collider*> colliders{collider};
        const Status s = stepper.step(*sim, colliders, dt);
        EXPECT_TRUE(s.isOk()) << s.message();
        if (!s) break;
        int inside = 0, crossed = 0, crossing = 0;
        for (std::size_t v = 0; v < sim->state().positions.size(); ++v) {
            const Vec3& p = sim->state().positions[v];
            EXPECT_TRUE(isFinite(p));
            inside += core(p - Vec3(0, 0, z)) < 1.0;
            // The bar only translates, so in its frame the vertex moved on the straight segment
            // from (x0 - bar0) to (x1 - bar1): if that passes through the bar, the vertex crossed it
            // within the step (sampled every 1/400 of the step).
            const Vec3 from = stepper.start[v] - Vec3(0, 0, previousZ), to = p - Vec3(0, 0, z);
            bool through = false;
            for (int k = 0; k <= 400 && !through; ++k) {
                through = core(from + (k / 400.0) * (to - from)) < 0.9;
            }
            crossed += through;
        }
        previousZ = z;
        for (const auto& [u, w] : edges) {
            // An edge through the bar's core joins vertices on both sides of it.
            bool through = false;
            for (int k = 0; k <= 20 && !through; ++k) {
                const Vec3 q = sim->state().positions[u] + (k / 20.0) * (sim->state().positions[w] - sim->state().positions[u]);
                through = core(q - Vec3(0, 0, z)) < 0.5;
            }
            crossing += through;
        }
        result.insideVertices = std::max(result.insideVertices, inside);
        result.crossedVertices = std::max(result.crossedVertices, crossed);
        result.crossingEdges = std::max(result.crossingEdges, crossing);
    }
    return result;
}

} // namespace

TEST(FastCollider, CapsuleSweptIntoASheetNeverPassesThroughWithContinuousCollision) {
    const double radius = 0.08;
    for (double speed : kSpeeds) {
        for (bool continuous : {true, false}) {
            CapsuleCollider capsule = CapsuleCollider::create(std::vector<Capsule>{{Vec3(-0.8, 0.5, -0.1), Vec3(0.8, 0.5, -0.1), radius}}).value();
            const auto core = [&](const Vec3& q) {
                return distanceToSegment(q, Vec3(-0.8, 0.5, 0), Vec3(0.8, 0.5, 0)) / radius;
            };
            const SweepResult r = sweep(speed, continuous, core, [&](double z, double dt) {
                EXPECT_TRUE(capsule.update(std::vector<Capsule>{{Vec3(-0.8, 0.5, z), Vec3(0.8, 0.5, z), radius}}, dt).isOk());
                return &capsule;
            });
            std::cout << "capsule, " << speed << " thicknesses/step, " << (continuous ? "continuous" : "discrete")
                      << ": worst step had " << r.insideVertices << " vertices inside, " << r.crossedVertices
                      << " through the bar within a step, " << r.crossingEdges << " edges through its core\n";
            if (continuous) {
                EXPECT_EQ(r.insideVertices, 0) << speed;
                EXPECT_EQ(r.crossedVertices, 0) << speed;
                EXPECT_EQ(r.crossingEdges, 0) << speed;
            }
        }
    }
}

TEST(FastCollider, MeshBodySweptIntoASheetNeverPassesThroughWithContinuousCollision) {
    // A bar as a closed triangle mesh (a UV sphere stretched into an ellipsoid with semi-axes
    // 0.9, r, r) in an Embree scene, refit every step. Inside is tested in the unit-sphere frame
    // against the convex mesh's inscribed radius there.
    const double radius = 0.08;
    test::BodyMesh bar = test::uvSphere(Vec3::Zero(), 1.0, 10, 16);
    double inscribed = 1.0;
    for (const auto& t : bar.triangles) {
        const Vec3 n = (bar.positions[t[1]] - bar.positions[t[0]]).cross(bar.positions[t[2]] - bar.positions[t[0]]);
        inscribed = std::min(inscribed, std::abs(n.dot(bar.positions[t[0]])) / n.norm());
    }
    for (Vec3& p : bar.positions) p = Vec3(0.9 * p.x(), 0.5 + radius * p.y(), radius * p.z());
    const auto core = [&](const Vec3& q) {
        return Vec3(q.x() / 0.9, (q.y() - 0.5) / radius, q.z() / radius).norm() / inscribed;
    };
    auto device = CollisionDevice::create({}).value();
    for (double speed : kSpeeds) {
        for (bool continuous : {true, false}) {
            if (!continuous && speed < 50.0) continue;  // discrete mode is documented by the capsule run
            std::vector<Vec3> pose = bar.positions;
            for (Vec3& p : pose) p.z() += -0.1;
            auto body = BodyCollider::create(*device, bar.triangles, pose).value();
            const SweepResult r = sweep(speed, continuous, core, [&](double z, double dt) {
                for (std::size_t k = 0; k < pose.size(); ++k) pose[k] = bar.positions[k] + Vec3(0, 0, z);
                EXPECT_TRUE(body->update(pose, dt).isOk());
                return body.get();
            });
            std::cout << "mesh bar, " << speed << " thicknesses/step, " << (continuous ? "continuous" : "discrete")
                      << ": worst step had " << r.insideVertices << " vertices inside, " << r.crossedVertices
                      << " through the bar within a step, " << r.crossingEdges << " edges through its core\n";
            if (continuous) {
                EXPECT_EQ(r.insideVertices, 0) << speed;
                EXPECT_EQ(r.crossedVertices, 0) << speed;
                EXPECT_EQ(r.crossingEdges, 0) << speed;
            }
        }
    }
}
