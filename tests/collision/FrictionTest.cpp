// Coulomb friction through body contacts (TESTPLAN B7) and cloth carried by a moving body.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/BodyMeshes.h"
#include "collision/ContactStepper.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::collision;

namespace {

constexpr double kG = 9.81;

struct InclineRun {
    double stuckDistance = 0;  // [m] how far the patch moved along the slope
    double acceleration = 0;   // [m/s^2] along the slope, from the velocity between 0.5 s and 1 s
    double maxDepth = 0;       // [m] deepest vertex below the offset surface
};

// A 20 cm patch resting on a plane inclined at `angle` (downhill along +z), for 1 s at 60 Hz.
InclineRun runIncline(double angle, double mu, cloth::IntegratorKind integrator) {
    const Vec3 downhill(0.0, -std::sin(angle), std::cos(angle));
    const Vec3 normal(0.0, std::cos(angle), std::sin(angle));
    const double length = 3.0;
    const test::BodyMesh plane = test::grid(Vec3(-length / 2, 0, 0) + downhill * (length / 2), Vec3(length, 0, 0),
                                            -downhill * length, 6);
    auto device = CollisionDevice::create({}).value();
    auto body = BodyCollider::create(*device, plane.triangles, plane.positions).value();

    test::ContactStepper stepper;
    stepper.settings.query.thickness = 0.004;
    stepper.settings.query.margin = 0.004;
    stepper.response.friction = {mu, mu};
    RectanglePanel panel;
    panel.width = panel.height = 0.2;
    panel.columns = panel.rows = 4;
    panel.vAxis = downhill;
    panel.origin = Vec3(-0.1, 0, 0) - 0.1 * downhill + stepper.settings.query.thickness * normal;
    const ClothMesh mesh = panel.build().value();
    cloth::SimulationSettings settings;
    settings.integrator = integrator;
    auto sim = cloth::ClothSimulation::create(mesh, cloth::ClothMaterial{}, settings).value();

    const std::vector<const Collider*> colliders{body.get()};
    const double dt = 1.0 / 60.0;
    auto meanAlongSlope = [&](const std::vector<Vec3>& values) {
        double sum = 0;
        for (const Vec3& v : values) sum += v.dot(downhill);
        return sum / values.size();
    };
    const double x0 = meanAlongSlope(sim->state().positions);
    InclineRun run;
    double vHalf = 0;
    for (int i = 1; i <= 60; ++i) {
        EXPECT_TRUE(body->update(plane.positions, dt).isOk());
        const Status s = stepper.step(*sim, colliders, dt);
        EXPECT_TRUE(s.isOk()) << s.message();
        if (!s) break;
        if (i == 30) vHalf = meanAlongSlope(sim->state().velocities);
        for (const Vec3& p : sim->state().positions) {
            run.maxDepth = std::max(run.maxDepth, stepper.settings.query.thickness - p.dot(normal));
        }
    }
    run.acceleration = (meanAlongSlope(sim->state().velocities) - vHalf) / 0.5;
    run.stuckDistance = meanAlongSlope(sim->state().positions) - x0;
    return run;
}

} // namespace

TEST(Friction, PatchOnAnInclineSticksBelowTheFrictionAngleAndSlidesAtTheCoulombRateAbove) {
    const double mu = 0.4;
    const double frictionAngle = std::atan(mu);
    for (cloth::IntegratorKind kind : {cloth::IntegratorKind::ImplicitPcg, cloth::IntegratorKind::SymplecticEuler}) {
        const InclineRun stick = runIncline(frictionAngle - 2.0 * kPi / 180.0, mu, kind);
        EXPECT_LT(std::abs(stick.stuckDistance), 1e-6) << "integrator " << int(kind);
        EXPECT_LT(std::abs(stick.acceleration), 1e-6);

        const double slideAngle = frictionAngle + 2.0 * kPi / 180.0;
        const InclineRun slide = runIncline(slideAngle, mu, kind);
        const double expected = kG * (std::sin(slideAngle) - mu * std::cos(slideAngle));
        EXPECT_NEAR(slide.acceleration, expected, 0.02 * expected) << "integrator " << int(kind);
        EXPECT_LT(stick.maxDepth, 1e-6);
        EXPECT_LT(slide.maxDepth, 1e-6);
    }
}

TEST(Friction, FrictionlessPatchSlidesAtGSinA) {
    const double angle = 10.0 * kPi / 180.0;
    const InclineRun slide = runIncline(angle, 0.0, cloth::IntegratorKind::ImplicitPcg);
    EXPECT_NEAR(slide.acceleration, kG * std::sin(angle), 0.02 * kG * std::sin(angle));
}

TEST(Friction, ClothRidesOnAMovingBody) {
    // A patch lying on a horizontal box top that accelerates sideways at 2 m/s^2 (below mu g = 4.9)
    // and rises at 0.3 m/s: with friction it moves with the body, without it stays behind.
    auto device = CollisionDevice::create({}).value();
    test::BodyMesh top = test::grid(Vec3(-1.5, 0, 0.5), Vec3(3, 0, 0), Vec3(0, 0, -1), 30);
    const std::vector<Vec3> rest = top.positions;
    for (double mu : {0.5, 0.0}) {
        auto body = BodyCollider::create(*device, top.triangles, rest).value();
        test::ContactStepper stepper;
        stepper.response.friction = {mu, mu};
        RectanglePanel panel;
        panel.width = panel.height = 0.2;
        panel.columns = panel.rows = 4;
        panel.vAxis = Vec3(0, 0, -1);
        panel.origin = Vec3(-0.1, stepper.settings.query.thickness, 0.1);
        auto sim = cloth::ClothSimulation::create(panel.build().value(), cloth::ClothMaterial{}, {}).value();
        const std::vector<const Collider*> colliders{body.get()};
        const double dt = 1.0 / 60.0;
        Vec3 shift = Vec3::Zero();
        std::vector<Vec3> pose = rest;
        for (int i = 1; i <= 45; ++i) {
            const double t = i * dt;
            shift = Vec3(0.5 * 2.0 * t * t, 0.3 * t, 0.0);
            for (std::size_t k = 0; k < pose.size(); ++k) pose[k] = rest[k] + shift;
            ASSERT_TRUE(body->update(pose, dt).isOk());
            ASSERT_TRUE(stepper.step(*sim, colliders, dt).isOk());
        }
        Vec3 mean = Vec3::Zero();
        double lowest = 1e9;
        for (const Vec3& p : sim->state().positions) mean += p, lowest = std::min(lowest, p.y() - shift.y());
        mean /= double(sim->state().vertexCount());
        EXPECT_GT(lowest, stepper.settings.query.thickness - 1e-6) << "mu " << mu;  // rides on top, rising
        if (mu > 0) {
            EXPECT_NEAR(mean.x(), shift.x(), 0.005) << "the patch should move with the body";
        } else {
            EXPECT_LT(std::abs(mean.x()), 0.005) << "without friction the body slides away underneath";
        }
    }
}
