// The multigrid-preconditioned filtered PCG: its answer is CHOLMOD's, its preconditioner is a
// symmetric V-cycle, its iterations do not grow with the resolution, and it is deterministic.
#include <gtest/gtest.h>

#include <random>

#include "crowdcloth/cloth/CholmodSolver.h"
#include "crowdcloth/cloth/MultigridPcg.h"
#include "support/AllocationCounter.h"
#include "support/GridProlongations.h"
#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

/// The bench's sheet (1 m, flat at 1 m, pinned at its two far corners) with `vertices` per side.
std::unique_ptr<ClothSimulation> benchSheet(int vertices, IntegratorKind integrator,
                                            SimulationSettings settings = {}) {
    ClothMaterial material;
    material.damping = 0.01;
    settings.integrator = integrator;
    return test::cornerPinnedSheet(test::horizontalSheet(uint32_t(vertices - 1)), material,
                                   settings);
}

const ImplicitEulerIntegrator& implicitOf(const ClothSimulation& sim) {
    return static_cast<const ImplicitEulerIntegrator&>(sim.integrator());
}

/// A moving sheet's system matrix with pins, a moving target and contact planes: a patch against
/// one plane (so coarse vertices lose its normal) and a row against tilted planes.
struct ConstrainedSystem {
    std::unique_ptr<ClothSimulation> sim;
    std::vector<VertexFilter> filters;
    std::vector<Vec3> b, z;

    explicit ConstrainedSystem(int vertices) : sim(benchSheet(vertices, IntegratorKind::ImplicitMultigrid)) {
        for (int i = 0; i < 12; ++i) EXPECT_TRUE(sim->step(1.0 / 60.0).isOk());
        const uint32_t n = sim->state().vertexCount();
        filters.assign(n, VertexFilter{});
        z.assign(n, Vec3::Zero());
        b.resize(n);
        std::mt19937 random(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (uint32_t i = 0; i < n; ++i) b[i] = 1e-3 * Vec3(u(random), u(random), u(random));
        const RectanglePanel panel = test::horizontalSheet(uint32_t(vertices - 1));
        for (uint32_t corner :
             {panel.vertexIndex(0, panel.rows), panel.vertexIndex(panel.columns, panel.rows)}) {
            filters[corner].kind = ConstraintKind::Target;
            z[corner] = Vec3(0.0, 0.01, 0.0);
        }
        const uint32_t mid = panel.columns / 2;
        filters[panel.vertexIndex(mid, panel.rows)].kind = ConstraintKind::Target;
        z[panel.vertexIndex(mid, panel.rows)] = Vec3(0.02, 0.0, -0.01);
        for (uint32_t j = 0; j < panel.rows / 3; ++j) {
            for (uint32_t i = 0; i < panel.columns / 3; ++i) {
                const uint32_t v = panel.vertexIndex(i, j);
                filters[v].kind = ConstraintKind::ContactPlane;
                filters[v].normal = Vec3::UnitY();
                z[v] = Vec3(0.0, 0.005, 0.0);
            }
        }
        for (uint32_t i = 0; i <= panel.columns; ++i) {
            const uint32_t v = panel.vertexIndex(i, panel.rows / 2);
            filters[v].kind = ConstraintKind::ContactPlane;
            filters[v].normal = Vec3(0.1 * std::sin(double(i)), 1.0, 0.3).normalized();
        }
    }
    const BlockSparseMatrix& matrix() const { return implicitOf(*sim).systemMatrix(); }
};

double relativeDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double diff = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        diff += (a[i] - b[i]).squaredNorm();
        norm += b[i].squaredNorm();
    }
    return std::sqrt(diff / norm);
}

// Iterations per step after `warmUp` steps, averaged over `steps` steps.
double iterationsPerStep(int vertices, int warmUp, int steps) {
    auto sim = benchSheet(vertices, IntegratorKind::ImplicitMultigrid);
    for (int i = 0; i < warmUp; ++i) EXPECT_TRUE(sim->step(1.0 / 60.0).isOk());
    int iterations = 0;
    for (int i = 0; i < steps; ++i) {
        EXPECT_TRUE(sim->step(1.0 / 60.0).isOk());
        iterations += sim->lastStats().iterations;
    }
    return double(iterations) / steps;
}

} // namespace

TEST(MultigridPcg, IterationsDoNotGrowFrom17To65) {
    // The 129^2 case and the bench's 30-step warm-up are in MultigridPcgSlowTest.cpp; block
    // Jacobi needs 64 / 174 / 423 iterations here.
    const double it17 = iterationsPerStep(17, 6, 2);
    const double it33 = iterationsPerStep(33, 6, 2);
    const double it65 = iterationsPerStep(65, 6, 2);
    EXPECT_LE(it65, 2.0 * it17) << it17 << " " << it33 << " " << it65;
    EXPECT_LE(it65, 20.0) << it17 << " " << it33 << " " << it65;
}

TEST(MultigridPcg, AnswerEqualsCholmodWithPinsAndContactPlanes) {
    for (CoarseningKind coarsening :
         {CoarseningKind::IndependentSet, CoarseningKind::SmoothedAggregation}) {
        ConstrainedSystem system(33);
        MultigridSettings settings;
        settings.coarsening = coarsening;
        settings.coarsestVertices = 16;  // several levels even at this size
        MultigridPcg mg(settings);
        PcgSettings pcg;
        pcg.relativeTolerance = 1e-10;
        std::vector<Vec3> dv(system.z.size(), Vec3::Zero()), exact(system.z.size());
        PcgResult result;
        ASSERT_TRUE(
            mg.solve(system.matrix(), system.filters, system.b, system.z, dv, pcg, {}, result)
                .isOk());
        EXPECT_TRUE(result.converged);
        EXPECT_GE(mg.hierarchy()->levelCount(), 3);
        CholmodSolver cholmod;
        ASSERT_TRUE(
            cholmod.solve(system.matrix(), system.filters, system.b, system.z, exact).isOk());
        EXPECT_LT(relativeDifference(dv, exact), 1e-7) << "coarsening " << int(coarsening);
        for (std::size_t i = 0; i < dv.size(); ++i) {
            const VertexFilter& f = system.filters[i];
            // The constrained part of dv is exactly z.
            EXPECT_LT((dv[i] - f.project(dv[i]) - (system.z[i] - f.project(system.z[i]))).norm(),
                      1e-15)
                << i;
        }
    }
}

TEST(MultigridPcg, SheetOnOnePlaneWithFewFreeVerticesGivesCholmodsAnswer) {
    // Nearly every vertex slides on one plane, so the coarse levels keep the plane's normal only
    // where a free vertex supports it, and together they span less than they keep: the coarse
    // operators are singular in some normal directions (a null space the prolongation maps to
    // zero), which the coarsest Cholesky must pass over.
    ConstrainedSystem system(33);
    for (std::size_t i = 0; i < system.filters.size(); ++i) {
        if (system.filters[i].kind == ConstraintKind::Target || i % 97 == 5) continue;
        system.filters[i].kind = ConstraintKind::ContactPlane;
        system.filters[i].normal = Vec3::UnitY();
    }
    MultigridPcg mg;
    PcgSettings pcg;
    pcg.relativeTolerance = 1e-10;
    std::vector<Vec3> dv(system.z.size(), Vec3::Zero()), exact(system.z.size());
    PcgResult result;
    const Status s =
        mg.solve(system.matrix(), system.filters, system.b, system.z, dv, pcg, {}, result);
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_TRUE(result.converged);
    CholmodSolver cholmod;
    ASSERT_TRUE(cholmod.solve(system.matrix(), system.filters, system.b, system.z, exact).isOk());
    EXPECT_LT(relativeDifference(dv, exact), 1e-7);
}

TEST(MultigridPcg, HandedInProlongationsGiveCholmodsAnswer) {
    for (bool pairs : {false, true}) {
        ConstrainedSystem system(17);
        MultigridSettings settings;
        settings.prolongations = test::gridProlongations(test::horizontalSheet(16));
        if (!pairs) settings.minCoarsening = 1.0;  // every 4-8 level as given
        settings.coarsestVertices = 4;
        MultigridPcg mg(settings);
        PcgSettings pcg;
        pcg.relativeTolerance = 1e-10;
        std::vector<Vec3> dv(system.z.size(), Vec3::Zero()), exact(system.z.size());
        PcgResult result;
        ASSERT_TRUE(
            mg.solve(system.matrix(), system.filters, system.b, system.z, dv, pcg, {}, result)
                .isOk());
        // Paired (the default): 289, 81, 25, 9, 4 vertices.
        EXPECT_EQ(mg.hierarchy()->levelCount(), pairs ? 5 : 9);
        EXPECT_LE(result.iterations, 30);
        CholmodSolver cholmod;
        ASSERT_TRUE(
            cholmod.solve(system.matrix(), system.filters, system.b, system.z, exact).isOk());
        EXPECT_LT(relativeDifference(dv, exact), 1e-7) << "pairs " << pairs;
    }
}

TEST(MultigridPcg, StepAgreesWithCholmodStep) {
    // Through ClothSimulation, with a moving target and contact planes, as SolverAgreement does
    // for block-Jacobi PCG.
    auto source = benchSheet(17, IntegratorKind::ImplicitPcg);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(source->step(1.0 / 60.0).isOk());
    std::vector<Vec3> positions[2];
    int kind = 0;
    for (IntegratorKind integrator :
         {IntegratorKind::ImplicitMultigrid, IntegratorKind::ImplicitCholmod}) {
        SimulationSettings settings;
        settings.implicit.pcg.relativeTolerance = 1e-8;
        auto sim = benchSheet(17, integrator, settings);
        sim->state() = source->state();
        ASSERT_TRUE(sim->constraints()
                        .setTarget(6, source->state().positions[6] + Vec3(0.01, 0.0, 0.0))
                        .isOk());
        for (uint32_t v = 20; v < 40; ++v) {
            ASSERT_TRUE(sim->constraints()
                            .setContactPlane(v, source->state().positions[v], Vec3(0, 1, 0))
                            .isOk());
        }
        ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
        positions[kind++] = sim->state().positions;
    }
    double worst = 0.0, motion = 0.0;
    for (std::size_t i = 0; i < positions[0].size(); ++i) {
        worst = std::max(worst, (positions[0][i] - positions[1][i]).norm());
        motion = std::max(motion, (positions[1][i] - source->state().positions[i]).norm());
    }
    EXPECT_LT(worst, 100.0 * 1e-8 * motion);
}

TEST(MultigridPcg, PreconditionerIsSymmetricPositiveDefinite) {
    ConstrainedSystem system(33);
    MultigridSettings settings;
    settings.coarsestVertices = 16;
    MultigridPcg mg(settings);
    ASSERT_TRUE(mg.setUp(system.matrix(), system.filters, {}).isOk());
    std::mt19937 random(11);
    std::normal_distribution<double> g;
    const std::size_t n = system.z.size();
    for (int trial = 0; trial < 4; ++trial) {
        std::vector<Vec3> x(n), y(n), mx, my;
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = system.filters[i].project(Vec3(g(random), g(random), g(random)));
            y[i] = system.filters[i].project(Vec3(g(random), g(random), g(random)));
        }
        mg.applyPreconditioner(x, mx, {});
        mg.applyPreconditioner(y, my, {});
        double xmy = 0.0, ymx = 0.0, xmx = 0.0, scale = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            xmy += x[i].dot(my[i]);
            ymx += y[i].dot(mx[i]);
            xmx += x[i].dot(mx[i]);
            scale += x[i].norm() * my[i].norm();
        }
        EXPECT_LT(std::abs(xmy - ymx), 1e-12 * scale) << xmy << " vs " << ymx;
        EXPECT_GT(xmx, 0.0);
    }
}

TEST(MultigridPcg, BitIdenticalForOneAndTwoThreads) {
    const auto hashes = [](int threads) {
        SimulationSettings settings;
        settings.parallel.maxThreads = threads;
        settings.parallel.minParallel = 1;  // run every loop, even short colours, in parallel
        settings.implicit.multigrid.coarsestVertices = 16;  // three levels
        auto sim = benchSheet(17, IntegratorKind::ImplicitMultigrid, settings);
        std::vector<uint64_t> out;
        for (int i = 0; i < 6; ++i) {
            if (i == 3) {
                for (uint32_t v = 0; v < 17; ++v) {
                    EXPECT_TRUE(sim->constraints()
                                    .setContactPlane(v, sim->state().positions[v], Vec3::UnitY(),
                                                     Vec3::Zero(), Friction{0.5, 0.3})
                                    .isOk());
                }
            }
            EXPECT_TRUE(sim->step(1.0 / 60.0).isOk());
            out.push_back(sim->stateHash());
        }
        return out;
    };
    EXPECT_EQ(hashes(1), hashes(2));
}

TEST(MultigridPcg, HierarchyIsBuiltOnceAndSolvesAllocateNothing) {
    auto sim = benchSheet(17, IntegratorKind::ImplicitMultigrid);
    ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
    const MultigridPcg& mg = implicitOf(*sim).multigrid();
    ConstrainedSystem system(17);
    MultigridPcg solver;
    std::vector<Vec3> dv(system.z.size(), Vec3::Zero());
    PcgResult result;
    ASSERT_TRUE(
        solver.solve(system.matrix(), system.filters, system.b, system.z, dv, {}, {}, result)
            .isOk());
    const long probe = test::allocationCount();
    int* heap = new int[64];
    volatile int* touched = heap;
    touched[0] = 1;
    delete[] heap;
    ASSERT_GT(test::allocationCount(), probe);  // the counter sees allocations
    const long before = test::allocationCount();
    for (int i = 0; i < 3; ++i) {
        system.filters[40].kind =
            i % 2 ? ConstraintKind::Target : ConstraintKind::Free;  // filters change
        ASSERT_TRUE(
            solver.solve(system.matrix(), system.filters, system.b, system.z, dv, {}, {}, result)
                .isOk());
    }
    EXPECT_EQ(test::allocationCount() - before, 0);
    EXPECT_EQ(solver.hierarchyBuilds(), 1);

    for (int i = 0; i < 10; ++i) {
        sim->constraints().clearContactPlanes();
        if (i % 2) {
            ASSERT_TRUE(
                sim->constraints().setContactPlane(10, Vec3(0, 0.5, 0), Vec3::UnitY()).isOk());
        }
        ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
    }
    EXPECT_EQ(mg.hierarchyBuilds(), 1);
    EXPECT_STREQ(sim->integrator().name(), "implicit-euler-multigrid");
    EXPECT_STREQ(integratorKindName(IntegratorKind::ImplicitMultigrid), "implicit-multigrid");
}

TEST(MultigridPcg, BadInputGivesAClearStatus) {
    const RectanglePanel panel = test::horizontalSheet(8);
    const ClothMesh mesh = panel.build().value();
    const auto rejected = [&](const SimulationSettings& settings, const std::string& fragment) {
        auto sim = ClothSimulation::create(mesh, ClothMaterial{}, settings);
        ASSERT_FALSE(sim.isOk()) << fragment;
        EXPECT_EQ(sim.status().code(), StatusCode::InvalidArgument);
        EXPECT_NE(sim.status().message().find(fragment), std::string::npos)
            << sim.status().message();
    };
    SimulationSettings good;
    good.integrator = IntegratorKind::ImplicitMultigrid;
    good.implicit.multigrid.prolongations = test::gridProlongations(panel);
    ASSERT_TRUE(ClothSimulation::create(mesh, ClothMaterial{}, good).isOk());

    SimulationSettings s = good;
    s.implicit.multigrid.prolongations = test::gridProlongations(test::horizontalSheet(4));
    rejected(s, "MultigridSettings.prolongations[0] has 25 rows; its finer level has 81 vertices");
    s = good;
    s.implicit.multigrid.prolongations[1].terms[3].source = 1000;
    rejected(s, "MultigridSettings.prolongations[1] row 3 refers to coarse vertex 1000 of 25");
    s = good;
    s.implicit.multigrid.prolongations[0].terms[5].weight = std::nan("");
    rejected(s, "MultigridSettings.prolongations[0] row 3 has a non-finite weight");
    s = good;
    s.implicit.multigrid.prolongations.erase(s.implicit.multigrid.prolongations.begin());
    rejected(s, "prolongations[0] has 41 rows");
    s = good;
    s.implicit.multigrid.smoothingSweeps = 0;
    rejected(s, "SimulationSettings.implicit.multigrid: MultigridSettings.smoothingSweeps = 0");
    s = good;
    s.implicit.multigrid.coarsestVertices = 0;
    rejected(s, "MultigridSettings.coarsestVertices");
    s = good;
    s.implicit.multigrid.strengthThreshold = 1.5;
    rejected(s, "MultigridSettings.strengthThreshold");
    s = good;
    s.implicit.multigrid.maxLevels = 1;
    rejected(s, "MultigridSettings.maxLevels");
    s = good;
    s.implicit.multigrid.minCoarsening = 0.5;
    rejected(s, "MultigridSettings.minCoarsening");
    s = good;
    s.integrator = static_cast<IntegratorKind>(17);
    rejected(s, "SimulationSettings.integrator = 17");

    // Straight to the solver: sizes that do not match, and a matrix that is not positive definite.
    ConstrainedSystem system(9);
    MultigridPcg mg;
    std::vector<Vec3> dv(system.z.size(), Vec3::Zero());
    PcgResult result;
    std::vector<VertexFilter> fewer(system.filters.begin(), system.filters.end() - 1);
    Status st = mg.solve(system.matrix(), fewer, system.b, system.z, dv, {}, {}, result);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("filters for a matrix of 81 rows"), std::string::npos)
        << st.message();
    std::vector<Vec3> shortB(system.b.begin(), system.b.end() - 1);
    st = mg.solve(system.matrix(), system.filters, shortB, system.z, dv, {}, {}, result);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    BlockSparseMatrix indefinite = system.matrix();
    indefinite.block(indefinite.diagonalSlot(30)) *= -1.0;
    st = mg.solve(indefinite, system.filters, system.b, system.z, dv, {}, {}, result);
    EXPECT_EQ(st.code(), StatusCode::NumericalFailure);
    EXPECT_NE(st.message().find("vertex 30 on level 0 is not positive definite"), std::string::npos)
        << st.message();
}
