// Stability at the extremes (TESTPLAN D1-D4): every run must stay finite with bounded energy; the
// explicit integrator either substeps or refuses with a clear error.
#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/cloth/ContinuumModel.h"
#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

struct Extreme {
    double stretch = 5e3, shear = 5e2, bend = 1e-5, density = 0.15, dt = 1.0 / 60.0;
};

// Runs a corner-pinned sheet for `seconds`; asserts finiteness and that the total energy never
// exceeds its initial value by more than 1% of the gravitational energy scale (a falling sheet
// only converts potential energy into motion, heat and strain).
void expectStableImplicit(const Extreme& e, ForceModelKind model, double seconds, const std::string& label) {
    ClothMaterial material;
    material.stretchStiffness = e.stretch;
    material.shearStiffness = e.shear;
    material.bendStiffness = e.bend;
    material.arealDensity = e.density;
    SimulationSettings settings;
    settings.forceModel = model;
    settings.implicit.pcg.maxIterations = 400;  // capped: report non-convergence, never hang
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(8), material, settings);
    ASSERT_TRUE(sim) << label;
    const double e0 = sim->totalEnergy();
    const double scale = e.density * 9.81 * 1.0;  // [J] weight of the 1 m^2 sheet times 1 m
    const int steps = std::max(1, static_cast<int>(seconds / e.dt));
    for (int i = 0; i < steps; ++i) {
        const Status s = sim->step(e.dt);
        ASSERT_TRUE(s.isOk()) << label << ": " << s.message();
        const double energy = sim->totalEnergy();
        ASSERT_TRUE(std::isfinite(energy)) << label << " step " << i;
        ASSERT_LE(energy, e0 + 0.01 * scale) << label << " step " << i;
    }
    EXPECT_EQ(sim->state().firstNonFinite(), sim->state().vertexCount()) << label;
}

} // namespace

TEST(Extremes, ImplicitStaysBoundedFromSoftToRigidStretch) {
    for (double stretch : {1e1, 1e3, 1e5, 1e7}) {
        for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
            Extreme e;
            e.stretch = stretch;
            e.shear = 0.1 * stretch;
            expectStableImplicit(e, model, 1.0, "stretch " + std::to_string(stretch));
        }
    }
}

TEST(Extremes, ImplicitStaysBoundedAtTheStiffestClothWithHugeSteps) {
    for (double dt : {1.0 / 1000.0, 1.0 / 30.0, 1.0 / 15.0}) {
        Extreme e;
        e.stretch = 1e7;
        e.shear = 1e6;
        e.dt = dt;
        expectStableImplicit(e, ForceModelKind::Continuum, dt < 0.01 ? 0.1 : 2.0, "dt " + std::to_string(dt));
    }
}

TEST(Extremes, ImplicitStaysBoundedAtExtremeBendToStretchRatios) {
    Extreme limp;  // stretch / bend = 1e12 m^-2: membrane only
    limp.stretch = 1e4;
    limp.bend = 1e-8;
    expectStableImplicit(limp, ForceModelKind::Continuum, 1.0, "limp");
    Extreme plate;  // bend / stretch = 1 m^2: a stiff plate on a soft membrane
    plate.stretch = 10.0;
    plate.shear = 1.0;
    plate.bend = 10.0;
    expectStableImplicit(plate, ForceModelKind::Continuum, 1.0, "plate");
}

TEST(Extremes, ImplicitStaysBoundedAcrossArealDensities) {
    for (double density : {0.01, 0.15, 2.0}) {
        Extreme e;
        e.density = density;
        expectStableImplicit(e, ForceModelKind::Continuum, 1.0, "density " + std::to_string(density));
    }
}

TEST(Extremes, NeighbourMassRatioOfAMillionStaysFinite) {
    // Alternate vertex masses by 1e6 on a continuum sheet: heavy and light neighbours.
    RectanglePanel panel = test::horizontalSheet(8);
    const ClothMesh mesh = panel.build().value();
    auto topology = ClothTopology::build(mesh).value();
    auto model = ContinuumModel::fromMesh(mesh, topology, ClothMaterial{}).value();
    std::vector<double> masses = lumpedMasses(mesh, 0.15);
    for (std::size_t i = 0; i < masses.size(); i += 2) masses[i] *= 1e6;
    for (IntegratorKind kind : {IntegratorKind::ImplicitPcg, IntegratorKind::ImplicitCholmod}) {
        SimulationSettings settings;
        settings.integrator = kind;
        auto sim = ClothSimulation::create(std::move(ContinuumModel::fromMesh(mesh, topology, ClothMaterial{}).value()),
                                           mesh.positions, masses, 0.01, settings).value();
        const uint32_t a = panel.vertexIndex(0, 8), b = panel.vertexIndex(8, 8);
        ASSERT_TRUE(sim->constraints().pin(a, mesh.positions[a]).isOk());
        ASSERT_TRUE(sim->constraints().pin(b, mesh.positions[b]).isOk());
        const double e0 = sim->totalEnergy();
        for (int i = 0; i < 60; ++i) {
            const Status s = sim->step(1.0 / 60.0);
            ASSERT_TRUE(s.isOk()) << s.message();
            ASSERT_LE(sim->totalEnergy(), e0 + 1e-6 * std::abs(e0) + 1e-9);
        }
        EXPECT_EQ(sim->state().firstNonFinite(), sim->state().vertexCount());
    }
    (void)model;
}

TEST(Extremes, ExplicitSubstepsOrRefusesClearly) {
    for (double stretch : {1e1, 1e3, 1e5, 1e7}) {
        ClothMaterial material;
        material.stretchStiffness = stretch;
        material.shearStiffness = 0.1 * stretch;
        SimulationSettings settings;
        settings.forceModel = ForceModelKind::MassSpring;
        settings.integrator = IntegratorKind::SymplecticEuler;
        settings.explicitEuler.maxSubsteps = 500;
        auto sim = test::cornerPinnedSheet(test::horizontalSheet(8), material, settings);
        const double e0 = sim->totalEnergy();
        for (int i = 0; i < 60; ++i) {
            const Status s = sim->step(1.0 / 60.0);
            if (!s.isOk()) {
                EXPECT_EQ(s.code(), StatusCode::InvalidArgument) << s.message();
                EXPECT_NE(s.message().find("substeps"), std::string::npos) << s.message();
                EXPECT_GE(stretch, 1e5) << "refused a soft cloth: " << s.message();
                break;
            }
            ASSERT_LE(sim->totalEnergy(), e0 + 0.01 * 0.15 * 9.81) << "stretch " << stretch << " step " << i;
            EXPECT_GE(sim->lastStats().substeps, 1);
        }
        EXPECT_EQ(sim->state().firstNonFinite(), sim->state().vertexCount());
    }
}
