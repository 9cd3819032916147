// A sheet draped on a sphere mesh comes to rest on it, never deeper than the thickness; bad
// contact and proxy input gives clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "collision/BodyMeshes.h"
#include "collision/ContactStepper.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/CapsuleCollider.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::collision;

TEST(Drape, SheetComesToRestOnASphereMeshNoDeeperThanTheThickness) {
    auto device = CollisionDevice::create({}).value();
    const Vec3 center(0, 0.5, 0);
    const test::BodyMesh sphere = test::uvSphere(center, 0.3, 16, 24);
    auto body = BodyCollider::create(*device, sphere.triangles, sphere.positions).value();
    RectanglePanel panel;
    panel.columns = panel.rows = 16;
    panel.origin = Vec3(-0.5, 0.85, 0.5);
    panel.vAxis = Vec3(0, 0, -1);
    cloth::SimulationSettings settings;
    settings.parallel.maxThreads = 1;
    cloth::ClothMaterial material;
    material.damping = 0.01;
    auto sim = cloth::ClothSimulation::create(panel.build().value(), material, settings).value();
    test::ContactStepper stepper;
    stepper.settings.query.parallel.maxThreads = 1;
    stepper.response.friction = {0.4, 0.3};
    const std::vector<const Collider*> colliders{body.get()};
    const double thickness = stepper.settings.query.thickness;
    double deepest = -1e9, lastKinetic = 0;
    for (int i = 1; i <= 180; ++i) {
        ASSERT_TRUE(body->update(sphere.positions, 1.0 / 60).isOk());
        const Status s = stepper.step(*sim, colliders, 1.0 / 60);
        ASSERT_TRUE(s.isOk()) << s.message();
        // Depth below the offset surface, from the mesh itself (brute force over its triangles;
        // the sphere is convex, so the signed distance is the largest plane distance).
        for (const Vec3& p : sim->state().positions) {
            double signedDistance = -1e9;
            for (const auto& t : sphere.triangles) {
                const Vec3 n = (sphere.positions[t[1]] - sphere.positions[t[0]])
                                   .cross(sphere.positions[t[2]] - sphere.positions[t[0]]).normalized();
                signedDistance = std::max(signedDistance, (p - sphere.positions[t[0]]).dot(n));
            }
            if (signedDistance < 0.05) deepest = std::max(deepest, thickness - signedDistance);
        }
        lastKinetic = sim->state().kineticEnergy();
    }
    EXPECT_LE(deepest, thickness) << "a vertex went inside the body";
    EXPECT_LT(deepest, 0.5 * thickness) << "deepest below the offset surface";
    // At rest: the sheet's top sits on the sphere and barely moves.
    double top = -1e9;
    for (const Vec3& p : sim->state().positions) top = std::max(top, p.y());
    EXPECT_NEAR(top, center.y() + 0.3 + thickness, 0.01);
    EXPECT_LT(lastKinetic, 1e-4) << "J; the sheet should have settled";
}

TEST(ContactInput, BadProxiesContactsAndFrictionGiveClearErrors) {
    std::vector<Capsule> capsules{{Vec3::Zero(), Vec3(1, 0, 0), 0.1}};
    EXPECT_FALSE(CapsuleCollider::create(std::vector<Capsule>{}).isOk());
    capsules[0].radius = -1;
    auto bad = CapsuleCollider::create(capsules);
    ASSERT_FALSE(bad.isOk());
    EXPECT_NE(bad.status().message().find("capsule 0 radius"), std::string::npos) << bad.status().message();
    capsules[0].radius = 0.1;
    auto proxies = CapsuleCollider::create(capsules).value();
    capsules[0].b.z() = std::numeric_limits<double>::quiet_NaN();
    const Status s = proxies.update(capsules, 0.1);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("capsule 0"), std::string::npos) << s.message();

    cloth::ContactResponse response;
    response.friction = {0.2, 0.5};  // kinetic above static
    EXPECT_NE(response.validate().message().find("kineticCoefficient"), std::string::npos);
    response.friction = {0.3, 0.2};
    response.thickness = 0.0;
    EXPECT_NE(response.validate().message().find("thickness"), std::string::npos);
    response.thickness = 0.004;
    cloth::ConstraintSet constraints(4);
    Contact c;
    c.vertex = 9;
    c.normal = Vec3::UnitY();
    Status e = cloth::applyContactPlanes(std::vector<Contact>{c}, response, constraints);
    ASSERT_FALSE(e.isOk());
    EXPECT_NE(e.message().find("vertex 9"), std::string::npos) << e.message();
    c.vertex = 2;
    c.point.x() = std::numeric_limits<double>::infinity();
    e = cloth::applyContactPlanes(std::vector<Contact>{c}, response, constraints);
    ASSERT_FALSE(e.isOk());
    EXPECT_NE(e.message().find("not finite"), std::string::npos) << e.message();
    EXPECT_FALSE(constraints.setContactPlane(1, Vec3::Zero(), Vec3::UnitY(), Vec3::Zero(), {-0.1, 0.0}).isOk());
}
