// Bad input is rejected with a message naming what and where; nothing is left half-built and a
// failed step leaves the state as it was.
#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/cloth/MassSpringModel.h"
#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

void expectRejected(const ClothMesh& mesh, const ClothMaterial& material, const SimulationSettings& settings,
                    const char* fragment) {
    auto sim = ClothSimulation::create(mesh, material, settings);
    ASSERT_FALSE(sim.isOk()) << "accepted input that should name: " << fragment;
    EXPECT_EQ(sim.status().code(), StatusCode::InvalidArgument);
    EXPECT_NE(sim.status().message().find(fragment), std::string::npos) << sim.status().message();
    EXPECT_EQ(sim.value(), nullptr);  // nothing half-built
}

ClothMesh smallSheet() { return RectanglePanel{1.0, 1.0, 3, 3}.build().value(); }

} // namespace

TEST(BadInput, DegenerateMeshesAreRejectedNamingTheElement) {
    ClothMesh mesh = smallSheet();
    mesh.restPositions[5] = mesh.restPositions[6];  // zero-length edge 5-6
    expectRejected(mesh, ClothMaterial{}, SimulationSettings{}, "zero-length rest edge");

    mesh = smallSheet();
    // Triangle 0 is (0, 1, 5); moving vertex 5 onto the edge 0-1 flattens it.
    mesh.restPositions[5] = 0.5 * (mesh.restPositions[0] + mesh.restPositions[1]) + Vec2(0, 1e-12);
    expectRejected(mesh, ClothMaterial{}, SimulationSettings{}, "triangle 0 (vertices 0, 1, 5) has zero rest area");

    mesh = smallSheet();
    mesh.positions[7].z() = std::nan("");
    expectRejected(mesh, ClothMaterial{}, SimulationSettings{}, "vertex 7");

    mesh = smallSheet();
    mesh.triangles.push_back({0, 1, 4});  // a third triangle on edge 0-1... and 1-4
    mesh.triangles.push_back({0, 1, 5});
    auto nonManifold = ClothSimulation::create(mesh, ClothMaterial{}, SimulationSettings{});
    ASSERT_FALSE(nonManifold.isOk());
    EXPECT_NE(nonManifold.status().message().find("triangle"), std::string::npos) << nonManifold.status().message();
}

TEST(BadInput, NonManifoldEdgeIsRejected) {
    // Three triangles on the edge 0-1, all counter-clockwise in pattern space.
    ClothMesh mesh;
    mesh.restPositions = {{0, 0}, {1, 0}, {0.5, 1}, {0.2, 2}, {0.9, 3}};
    for (const Vec2& r : mesh.restPositions) mesh.positions.push_back(Vec3(r.x(), r.y(), 0));
    mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
    expectRejected(mesh, ClothMaterial{}, SimulationSettings{}, "non-manifold");
}

TEST(BadInput, AbsurdMaterialParametersAreRejectedByName) {
    const ClothMesh mesh = smallSheet();
    struct Case {
        double ClothMaterial::*field;
        double value;
        const char* name;
    };
    const Case cases[] = {
        {&ClothMaterial::arealDensity, 0.0, "arealDensity"},
        {&ClothMaterial::arealDensity, std::nan(""), "arealDensity"},
        {&ClothMaterial::stretchStiffness, -5.0, "stretchStiffness"},
        {&ClothMaterial::stretchStiffness, INFINITY, "stretchStiffness"},
        {&ClothMaterial::shearStiffness, -1.0, "shearStiffness"},
        {&ClothMaterial::bendStiffness, std::nan(""), "bendStiffness"},
        {&ClothMaterial::damping, -0.1, "damping"},
    };
    for (const Case& c : cases) {
        ClothMaterial material;
        material.*c.field = c.value;
        expectRejected(mesh, material, SimulationSettings{}, c.name);
    }
}

TEST(BadInput, AbsurdSettingsAreRejectedByName) {
    const ClothMesh mesh = smallSheet();
    SimulationSettings s;
    s.gravity.y() = std::nan("");
    expectRejected(mesh, ClothMaterial{}, s, "gravity");
    s = SimulationSettings{};
    s.implicit.pcg.relativeTolerance = 0.0;
    expectRejected(mesh, ClothMaterial{}, s, "relativeTolerance");
    s = SimulationSettings{};
    s.strainLimit = -0.1;
    expectRejected(mesh, ClothMaterial{}, s, "strainLimit");
    s = SimulationSettings{};
    s.explicitEuler.maxSubsteps = 0;
    expectRejected(mesh, ClothMaterial{}, s, "maxSubsteps");
}

TEST(BadInput, BadSpringsAndMassesAreRejected) {
    auto negative = MassSpringModel::fromSprings(2, {{0, 1, -3.0, 1.0, SpringKind::Structural}});
    ASSERT_FALSE(negative.isOk());
    EXPECT_NE(negative.status().message().find("spring 0"), std::string::npos);
    EXPECT_FALSE(MassSpringModel::fromSprings(2, {{0, 2, 1.0, 1.0, SpringKind::Structural}}).isOk());
    EXPECT_FALSE(MassSpringModel::fromSprings(2, {{0, 1, 1.0, 0.0, SpringKind::Structural}}).isOk());

    auto model = MassSpringModel::fromSprings(2, {{0, 1, 1.0, 1.0, SpringKind::Structural}});
    auto sim = ClothSimulation::create(std::move(model.value()), {Vec3::Zero(), Vec3(1, 0, 0)}, {1.0, 0.0}, 0.0,
                                       SimulationSettings{});
    ASSERT_FALSE(sim.isOk());
    EXPECT_NE(sim.status().message().find("vertex 1 has mass"), std::string::npos) << sim.status().message();
}

TEST(BadInput, BadStepsAndConstraintsLeaveTheStateUntouched) {
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(4), ClothMaterial{}, SimulationSettings{});
    ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
    const uint64_t before = sim->stateHash();
    for (double dt : {0.0, -1.0 / 60.0, double(NAN), double(INFINITY), 5.0}) {
        const Status s = sim->step(dt);
        EXPECT_EQ(s.code(), StatusCode::InvalidArgument) << dt;
        EXPECT_NE(s.message().find("dt"), std::string::npos) << s.message();
    }
    EXPECT_FALSE(sim->constraints().pin(1000, Vec3::Zero()).isOk());
    EXPECT_FALSE(sim->constraints().setTarget(3, Vec3(0, std::nan(""), 0)).isOk());
    EXPECT_FALSE(sim->constraints().setContactPlane(3, Vec3::Zero(), Vec3(0, 2, 0)).isOk());  // not unit
    EXPECT_EQ(sim->stateHash(), before);
}

TEST(BadInput, NonFiniteStateWrittenByTheHostIsRefusedNamingTheVertex) {
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(4), ClothMaterial{}, SimulationSettings{});
    sim->state().velocities[9].x() = std::nan("");
    const Status s = sim->step(1.0 / 60.0);
    EXPECT_EQ(s.code(), StatusCode::InvalidArgument);
    EXPECT_NE(s.message().find("vertex 9"), std::string::npos) << s.message();
}

TEST(BadInput, AStepThatBlowsUpIsUndoneAndReported) {
    // Forcing one substep far beyond the stability limit makes symplectic Euler overflow to
    // infinity; the step that first produces a non-finite value must be undone and reported.
    SimulationSettings settings;
    settings.forceModel = ForceModelKind::MassSpring;
    settings.integrator = IntegratorKind::SymplecticEuler;
    settings.explicitEuler.fixedSubsteps = 1;
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(6), ClothMaterial{}, settings);
    Status status;
    uint64_t lastGood = sim->stateHash();
    for (int i = 0; i < 2000 && status.isOk(); ++i) {
        lastGood = sim->stateHash();
        status = sim->step(1.0 / 60.0);
    }
    ASSERT_EQ(status.code(), StatusCode::NumericalFailure) << status.message();
    EXPECT_NE(status.message().find("non-finite state at vertex"), std::string::npos) << status.message();
    EXPECT_EQ(sim->stateHash(), lastGood);
    EXPECT_EQ(sim->state().firstNonFinite(), sim->state().vertexCount());
}
