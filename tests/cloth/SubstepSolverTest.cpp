// The substepped local/global solver (cloth/SubstepSolver.h): closed forms, equilibria, the
// convergence of its iterations, contacts and friction, batches, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "crowdcloth/cloth/ClothTopology.h"
#include "crowdcloth/cloth/MassSpringModel.h"
#include "crowdcloth/cloth/SubstepSimulation.h"
#include "support/SheetScenes.h"
#include "support/SpringChain.h"

using namespace cc;
using namespace cc::cloth;

namespace {

constexpr double kG = 9.81;

std::vector<uint32_t> topEdge(const RectanglePanel& panel) {
    std::vector<uint32_t> top;
    for (uint32_t i = 0; i <= panel.columns; ++i) top.push_back(panel.vertexIndex(i, panel.rows));
    return top;
}

std::vector<uint32_t> farCorners(const RectanglePanel& panel) {
    return {panel.vertexIndex(0, panel.rows), panel.vertexIndex(panel.columns, panel.rows)};
}

// Every vertex in contact with the floor y = 0 below it.
std::vector<Contact> floorContacts(const ClothMesh& mesh) {
    std::vector<Contact> contacts;
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        Contact c;
        c.vertex = v;
        c.point = Vec3(mesh.positions[v].x(), 0.0, mesh.positions[v].z());
        c.normal = Vec3::UnitY();
        contacts.push_back(c);
    }
    return contacts;
}

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

using test::hangingChain;

} // namespace

TEST(SubstepSolver, FreeFallMatchesTheDiscreteClosedForm) {
    // No springs: each substep is v += h g, x += h v, so after n substeps of h (t = n h)
    // x = x0 + v0 t + g t^2 / 2 + g h t / 2 exactly (TESTPLAN A1).
    const double m[] = {0.2};
    ClothLevelDesc desc;
    desc.vertexCount = 1;
    desc.masses = m;
    auto sim = SubstepSimulation::create(desc, {Vec3(0.0, 2.0, 0.0)}).value();
    sim->velocities()[0] = Vec3(1.0, 0.5, 0.0);
    SubstepSettings settings;
    settings.substeps = 7;
    const double dt = 1.0 / 60.0, h = dt / settings.substeps;
    for (int step = 0; step < 30; ++step) ASSERT_TRUE(sim->step(dt, settings).isOk());
    const double t = 30 * dt;
    const Vec3 expected = Vec3(0.0, 2.0, 0.0) + Vec3(1.0, 0.5, 0.0) * t + Vec3(0.0, -kG, 0.0) * (0.5 * t * t + 0.5 * h * t);
    // Roundoff only: each substep's solve multiplies by m / h^2 and its inverse square root twice.
    EXPECT_LT((sim->positions()[0] - expected).norm(), 1e-11 * expected.norm());
}

TEST(SubstepSolver, HangingChainReachesTheExactDiscreteExtensions) {
    // At rest the local/global fixed point is the static equilibrium: spring j (counted from the
    // top, 1-based) of an N-mass chain carries the N - j + 1 masses below it (TESTPLAN B1). Large
    // steps settle it fast (backward Euler's damping); small ones barely damp the slow bounce.
    const int n = 8;
    const double mass = 0.01, k = 50.0, rest = 0.05;
    auto sim = hangingChain(n, mass, k, rest);
    SubstepSettings settings;
    settings.substeps = 1;
    for (int step = 0; step < 1000; ++step) ASSERT_TRUE(sim->step(1.0 / 20.0, settings).isOk());
    for (int j = 1; j <= n; ++j) {
        const double length = (sim->positions()[j - 1] - sim->positions()[j]).norm();
        const double expected = (n - j + 1) * mass * kG / k;
        EXPECT_NEAR(length - rest, expected, 1e-9) << "spring " << j;
    }
}

TEST(SubstepSolver, SheetHungByItsTopEdgeStretchesRhoGHSquaredOverTwoY) {
    // Structural springs only (no shear, no bending): every column is a chain with springs k = Y
    // that carries the cloth below it. Row by row the extensions are rho g L^2 (N - j + 1/2) / Y
    // (the bottom row's lumped masses are half), which sum to the continuum's rho g H^2 / (2 Y)
    // exactly at every resolution.
    ClothMaterial material;
    material.stretchStiffness = 50.0;
    material.shearStiffness = 0.0;
    material.bendStiffness = 0.0;
    const double expected = material.arealDensity * kG * 1.0 / (2.0 * material.stretchStiffness);
    for (uint32_t squares : {4u, 8u, 16u}) {
        const RectanglePanel panel = test::verticalSheet(squares);
        const ClothMesh mesh = panel.build().value();
        auto sim = SubstepSimulation::create(mesh, material, topEdge(panel)).value();
        SubstepSettings settings;
        settings.substeps = 1;
        for (int step = 0; step < 2000; ++step) ASSERT_TRUE(sim->step(1.0 / 10.0, settings).isOk());
        double lowest = 1e300;
        for (const Vec3& p : sim->positions()) lowest = std::min(lowest, p.y());
        EXPECT_NEAR(-lowest, expected, 1e-4 * expected) << squares << " squares";
    }
}

TEST(SubstepSolver, LocalGlobalIterationsConvergeToTheBackwardEulerSubstep) {
    // The local/global iterations of one substep converge to the backward Euler step, where the
    // residual M (x - y) / h^2 - f(x) vanishes (y: the inertial prediction). Measured on a sheet
    // stretched 5% and rumpled, at h = 1/600 s: the residual falls at a steady linear rate.
    const RectanglePanel panel = test::horizontalSheet(8);
    ClothMesh mesh = panel.build().value();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    for (Vec3& p : mesh.positions) p = Vec3(1.05 * p.x(), p.y() + jitter(random), 1.05 * p.z());
    const ClothMaterial material;
    const auto topology = ClothTopology::build(mesh).value();
    const auto model = MassSpringModel::fromMesh(mesh, topology, material).value();
    const std::vector<double> masses = lumpedMasses(mesh, material.arealDensity);
    const double h = 1.0 / 600.0;
    auto residual = [&](const std::vector<Vec3>& x) {
        std::vector<Vec3> f(x.size(), Vec3::Zero());
        ForceEvaluation eval;
        eval.positions = x;
        eval.outForces = f;
        eval.parallel.maxThreads = 1;
        model->evaluate(eval);
        double sum = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i)
            sum += (masses[i] * (x[i] - mesh.positions[i]) / (h * h) - f[i]).squaredNorm();
        return std::sqrt(sum);
    };
    std::vector<double> residuals;
    const int counts[] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
    for (int iterations : counts) {
        auto sim = SubstepSimulation::create(mesh, material, {}).value();
        sim->setAcceleration(Vec3::Zero());
        SubstepSettings settings;
        settings.method = SubstepMethod::LocalGlobal;
        settings.substeps = 1;
        settings.iterations = iterations;
        ASSERT_TRUE(sim->step(h, settings).isOk());
        residuals.push_back(residual(sim->positions()));
    }
    for (std::size_t i = 1; i < residuals.size(); ++i) {
        EXPECT_LT(residuals[i], residuals[i - 1]) << counts[i] << " iterations";
    }
    const double rate = std::pow(residuals[9] / residuals[8], 1.0 / 256.0);
    RecordProperty("rate_per_iteration", std::to_string(rate));
    EXPECT_LT(rate, 0.99);
    EXPECT_LT(residuals[9], 1e-6 * residuals[0]);
}

TEST(SubstepSolver, NewtonIterationsConvergeToTheLinearisedStep) {
    // One Newton step per substep, its linear system solved by CG preconditioned with the shared
    // factor: more iterations converge to the exact Newton step. Measured on a stretched, rumpled
    // sheet at h = 1/240 s: the change from doubling the iterations shrinks steadily (CG on an
    // 81-node system: at 64 iterations the change is 5e-4 of the one at 32).
    const RectanglePanel panel = test::horizontalSheet(8);
    ClothMesh mesh = panel.build().value();
    std::mt19937 random(11);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    for (Vec3& p : mesh.positions) p = Vec3(1.05 * p.x(), p.y() + jitter(random), 1.05 * p.z());
    std::vector<std::vector<Vec3>> results;
    const int counts[] = {2, 4, 8, 16, 32, 64};
    for (int iterations : counts) {
        auto sim = SubstepSimulation::create(mesh, ClothMaterial{}, farCorners(panel)).value();
        SubstepSettings settings;
        settings.method = SubstepMethod::Newton;
        settings.substeps = 1;
        settings.iterations = iterations;
        ASSERT_TRUE(sim->step(1.0 / 240.0, settings).isOk());
        results.push_back(sim->positions());
    }
    auto distance = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
        double sum = 0.0;
        for (std::size_t v = 0; v < a.size(); ++v) sum += (a[v] - b[v]).squaredNorm();
        return std::sqrt(sum);
    };
    std::vector<double> changes;
    for (std::size_t i = 1; i < results.size(); ++i) changes.push_back(distance(results[i], results[i - 1]));
    for (std::size_t i = 1; i < changes.size(); ++i) EXPECT_LT(changes[i], changes[i - 1]) << counts[i + 1] << " iterations";
    RecordProperty("change_per_doubling", std::to_string(changes.back() / changes[changes.size() - 2]));
    EXPECT_LT(changes.back(), 1e-3 * changes.front());
}

TEST(SubstepSolver, StiffBendingJoinsTheFactorAndNewtonConvergesAsWithout) {
    // A plate-like sheet (B = 0.1 N m): at h = 1/60 s its bending springs are stiff enough to join
    // the factor, which then has its own fill-reducing ordering and permutes every solve; at
    // B = 0.02 they stay explicit. CG on a rumpled, stretched sheet's Newton system converges at
    // the same rate either way (measured: within 2 %; the stretch nonlinearity, not bending, sets
    // it), so the ordering and the permutation are right: a wrong one would stall CG.
    const RectanglePanel panel = test::horizontalSheet(8);
    ClothMesh mesh = panel.build().value();
    std::mt19937 random(5);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    for (Vec3& p : mesh.positions) p = Vec3(1.03 * p.x(), p.y() + jitter(random), 1.03 * p.z());
    auto distance = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
        double sum = 0.0;
        for (std::size_t v = 0; v < a.size(); ++v) sum += (a[v] - b[v]).squaredNorm();
        return std::sqrt(sum);
    };
    const int counts[] = {1, 2, 4, 8, 16, 32};
    std::vector<double> changes[2];
    for (int k = 0; k < 2; ++k) {
        ClothMaterial material;
        material.bendStiffness = k == 0 ? 0.1 : 0.02;
        auto level = ClothLevel::cookMesh(mesh, material, farCorners(panel)).value();
        EXPECT_EQ(level->buildFactor(1.0 / 60.0).value()->includesBending(), k == 0);
        std::vector<Vec3> previous;
        for (int iterations : counts) {
            auto sim = SubstepSimulation::create(mesh, material, farCorners(panel)).value();
            SubstepSettings settings;
            settings.method = SubstepMethod::Newton;
            settings.substeps = 1;
            settings.iterations = iterations;
            ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
            if (!previous.empty()) changes[k].push_back(distance(sim->positions(), previous));
            previous = sim->positions();
        }
    }
    for (std::size_t i = 0; i < changes[0].size(); ++i) {
        EXPECT_LT(changes[0][i], 1.25 * changes[1][i]) << counts[i + 1] << " iterations";
    }
    RecordProperty("change_ratio_in_factor", std::to_string(changes[0].back() / changes[0].front()));
    EXPECT_LT(changes[0].back(), 1e-2 * changes[0].front());
}

TEST(SubstepSolver, AttachedVerticesReachTheirTargetsExactly) {
    const RectanglePanel panel = test::horizontalSheet(6);
    const ClothMesh mesh = panel.build().value();
    const auto corners = farCorners(panel);
    auto sim = SubstepSimulation::create(mesh, ClothMaterial{}, corners).value();
    const Vec3 target0 = mesh.positions[corners[0]] + Vec3(0.1, 0.2, -0.05);
    sim->setTarget(0, target0);
    SubstepSettings settings;
    ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
    const uint32_t v0 = sim->level().vertexOfNode()[sim->level().freeNodeCount()];
    EXPECT_EQ(sim->positions()[v0], target0);
}

TEST(SubstepSolver, StrainLimitHoldsProvotsTwoCornerSheet) {
    // Provot's test (TESTPLAN B5): soft springs, two corners, limit 10%: every edge within 10.5%
    // after every step; without the limit the corners stretch far beyond it.
    ClothMaterial soft;
    soft.stretchStiffness = 20.0;
    soft.shearStiffness = 2.0;
    const RectanglePanel panel = test::horizontalSheet(10);
    const ClothMesh mesh = panel.build().value();
    for (double limit : {0.0, 0.1}) {
        auto sim = SubstepSimulation::create(mesh, soft, farCorners(panel)).value();
        SubstepSettings settings;
        settings.strainLimit = limit;
        settings.strainLimitPasses = 50;
        double worst = 0.0;
        for (int step = 0; step < 120; ++step) {
            ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
            worst = std::max(worst, sim->maxEdgeStrain());
        }
        if (limit > 0.0) {
            EXPECT_LE(worst, limit + 0.005);
        } else {
            EXPECT_GT(worst, 0.2);
        }
    }
}

TEST(SubstepSolver, SheetRestsOnAContactPlaneAtItsThickness) {
    // A sheet dropped onto a floor (contacts with the plane y = 0 for every vertex) comes to rest
    // on the offset plane y = thickness, no vertex below it.
    const RectanglePanel panel = test::horizontalSheet(6);
    ClothMesh mesh = panel.build().value();
    for (Vec3& p : mesh.positions) p.y() = 0.05;
    auto sim = SubstepSimulation::create(mesh, ClothMaterial{}, {}).value();
    sim->setContacts(floorContacts(mesh));
    SubstepSettings settings;
    settings.contactThickness = 0.004;
    settings.friction = Friction{0.5, 0.4};
    for (int step = 0; step < 120; ++step) ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
    for (const Vec3& p : sim->positions()) EXPECT_NEAR(p.y(), 0.004, 1e-9);
    EXPECT_LT(sim->kineticEnergy(), 1e-12);
}

TEST(SubstepSolver, FrictionOnAnInclineSticksBelowTheAngleAndSlidesAboveIt) {
    // A particle on a plane at angle a with mu_s = mu_k = mu (TESTPLAN B7): it sticks at
    // atan(mu) - 2 degrees and slides at atan(mu) + 2 degrees with acceleration g (sin a - mu cos a).
    const double mu = 0.4;
    for (double degrees : {-2.0, 2.0}) {
        const double a = std::atan(mu) + degrees * M_PI / 180.0;
        const Vec3 normal(-std::sin(a), std::cos(a), 0.0);  // the plane rises towards -x
        const double m[] = {0.01};
        ClothLevelDesc desc;
        desc.vertexCount = 1;
        desc.masses = m;
        auto sim = SubstepSimulation::create(desc, {Vec3::Zero()}).value();
        Contact c;
        c.point = Vec3::Zero();
        c.normal = normal;
        sim->setContacts({c});
        SubstepSettings settings;
        settings.substeps = 20;
        settings.friction = Friction{mu, mu};
        const double dt = 1.0 / 60.0, seconds = 1.0;
        for (int step = 0; step < int(std::lround(seconds / dt)); ++step) {
            // The plane is tangent at the particle's current point: a long, flat incline.
            c.point = sim->positions()[0] - normal * normal.dot(sim->positions()[0]);
            sim->setContacts({c});
            ASSERT_TRUE(sim->step(dt, settings).isOk());
        }
        const double travelled = sim->positions()[0].norm();
        const double expected = degrees < 0.0 ? 0.0 : 0.5 * kG * (std::sin(a) - mu * std::cos(a)) * seconds * seconds;
        if (degrees < 0.0) {
            EXPECT_LT(travelled, 1e-9);
        } else {
            EXPECT_NEAR(travelled, expected, 0.02 * expected);
        }
    }
}

namespace {

/// `whole` cut along its middle column into two panels side by side, the touching columns welded.
struct CutSheet {
    RectanglePanel left, right;
    ClothMesh mesh;
    uint32_t offset = 0;  ///< the right panel's first vertex in `mesh`
    std::vector<std::array<uint32_t, 2>> welds;
    std::array<uint32_t, 2> corners{};  ///< the far corners of the last row (where both hang)
    Span<const uint32_t> hung() const { return {corners.data(), corners.size()}; }
};

CutSheet cutInHalves(const RectanglePanel& whole) {
    CutSheet c;
    c.left = whole;
    c.left.columns = whole.columns / 2;
    c.left.width = 0.5 * whole.width;
    c.right = c.left;
    c.right.origin.x() += c.left.width;
    const ClothMesh a = c.left.build().value(), b = c.right.build().value();
    c.mesh = a;
    c.offset = uint32_t(a.vertexCount());
    for (std::size_t v = 0; v < b.vertexCount(); ++v) {
        c.mesh.positions.push_back(b.positions[v]);
        c.mesh.restPositions.push_back(b.restPositions[v] + Vec2(c.left.width, 0.0));
    }
    for (const auto& t : b.triangles) c.mesh.triangles.push_back({t[0] + c.offset, t[1] + c.offset, t[2] + c.offset});
    for (uint32_t j = 0; j <= c.left.rows; ++j)
        c.welds.push_back({c.left.vertexIndex(c.left.columns, j), c.offset + c.right.vertexIndex(0, j)});
    c.corners = {c.left.vertexIndex(0, c.left.rows), c.offset + c.right.vertexIndex(c.right.columns, c.right.rows)};
    return c;
}

} // namespace

TEST(SubstepSolver, WeldedCopiesMoveAsOnePoint) {
    // Two panels side by side whose touching columns are welded: the copies end every step at the
    // same position, and the pair hangs as one sheet (no gap opens along the weld).
    const CutSheet cut = cutInHalves(test::horizontalSheet(8));
    auto sim = SubstepSimulation::create(cut.mesh, ClothMaterial{}, cut.hung(), cut.welds).value();
    EXPECT_EQ(sim->level().nodeCount(), cut.mesh.vertexCount() - cut.welds.size());
    for (int step = 0; step < 60; ++step) ASSERT_TRUE(sim->step(1.0 / 60.0, SubstepSettings{}).isOk());
    for (const auto& [p, q] : cut.welds) EXPECT_EQ(sim->positions()[p], sim->positions()[q]);
    EXPECT_LT(sim->maxEdgeStrain(), 0.1);
}

TEST(SubstepSolver, ASeamCarriesStressAndBendingAsTheUncutCloth) {
    // A sheet cut in two along its middle column and welded there against the same sheet uncut,
    // hung by two corners so that it stretches, shears and folds across the seam: stretch, shear
    // and bending act across a weld inside the solve (the copies are one node, the hinges across
    // the seam are the uncut sheet's), so both hang the same (to the solver's rounding: the nodes
    // are numbered differently).
    const RectanglePanel whole = test::horizontalSheet(8);
    const CutSheet cut = cutInHalves(whole);
    const uint32_t wholeAttached[] = {whole.vertexIndex(0, whole.rows), whole.vertexIndex(whole.columns, whole.rows)};
    ClothMaterial material;
    material.bendStiffness = 1e-3;  // folds that bending shapes, across the seam too
    auto cutSim = SubstepSimulation::create(cut.mesh, material, cut.hung(), cut.welds).value();
    auto wholeSim = SubstepSimulation::create(whole.build().value(), material, wholeAttached, {}).value();
    SubstepSettings settings;
    settings.iterations = 40;  // converged enough that the node order's rounding stays small
    for (int step = 0; step < 60; ++step) {
        ASSERT_TRUE(cutSim->step(1.0 / 60.0, settings).isOk());
        ASSERT_TRUE(wholeSim->step(1.0 / 60.0, settings).isOk());
    }
    double worst = 0.0, moved = 0.0;
    for (uint32_t j = 0; j <= whole.rows; ++j)
        for (uint32_t i = 0; i <= whole.columns; ++i) {
            const bool inLeft = i <= cut.left.columns;
            const uint32_t v = inLeft ? cut.left.vertexIndex(i, j) : cut.offset + cut.right.vertexIndex(i - cut.left.columns, j);
            const Vec3& expected = wholeSim->positions()[whole.vertexIndex(i, j)];
            worst = std::max(worst, (cutSim->positions()[v] - expected).norm());
            moved = std::max(moved, (expected - whole.build().value().positions[whole.vertexIndex(i, j)]).norm());
        }
    EXPECT_GT(moved, 0.3) << "the sheet swings down";
    EXPECT_LT(worst, 1e-6) << "largest distance between the cut and the uncut sheet";
}

namespace {

// Eight different instances of one level: different starts, targets, contacts and gravity.
struct Batch {
    std::shared_ptr<const ClothLevel> level;
    std::shared_ptr<const SubstepFactor> factor;
    std::vector<std::vector<Vec3>> positions, velocities, targets;
    std::vector<std::vector<Contact>> contacts;
    std::vector<Vec3> accelerations;

    SubstepSettings settings;

    /// stiffBending: a plate (B = 1 N m) stepped whole, so its bending joins the factor.
    explicit Batch(int lanes, SubstepMethod method = SubstepMethod::Newton, bool stiffBending = false) {
        settings.method = method;
        settings.substeps = stiffBending ? 1 : method == SubstepMethod::Newton ? 4 : 10;
        ClothMaterial material;
        if (stiffBending) material.bendStiffness = 1.0;
        settings.iterations = method == SubstepMethod::Newton ? 4 : 1;
        settings.strainLimit = 0.05;
        settings.contactThickness = 0.004;
        const RectanglePanel panel = test::horizontalSheet(6);
        const ClothMesh mesh = panel.build().value();
        level = ClothLevel::cookMesh(mesh, material, farCorners(panel)).value();
        factor = level->buildFactor(1.0 / 60.0 / settings.substeps).value();
        EXPECT_EQ(factor->includesBending(), stiffBending);
        std::mt19937 random(3);
        std::uniform_real_distribution<double> u(-0.02, 0.02);
        for (int l = 0; l < lanes; ++l) {
            std::vector<Vec3> x = mesh.positions;
            for (Vec3& p : x) p += Vec3(u(random), u(random), u(random));
            positions.push_back(x);
            velocities.push_back(std::vector<Vec3>(x.size(), Vec3(u(random), 0.0, u(random))));
            std::vector<Vec3> t;
            for (uint32_t k = 0; k < level->attachedNodeCount(); ++k)
                t.push_back(x[level->vertexOfNode()[level->freeNodeCount() + k]] + Vec3(0.0, u(random), 0.0));
            targets.push_back(t);
            std::vector<Contact> c;
            for (uint32_t v = l; v < x.size(); v += 5) {
                Contact contact;
                contact.vertex = v;
                contact.point = Vec3(x[v].x(), 0.99, x[v].z());
                contact.normal = Vec3::UnitY();
                contact.surfaceVelocity = Vec3(0.0, 0.1 * l, 0.0);
                c.push_back(contact);
            }
            contacts.push_back(c);
            accelerations.push_back(Vec3(0.1 * l, -kG, 0.0));
        }
    }

    // Steps the lanes `which` together, `steps` times.
    void step(const std::vector<int>& which, int steps, std::vector<SubstepLaneReport>* outReports = nullptr) {
        SubstepWorkspace work;
        std::vector<SubstepLane> lanes;
        for (int l : which) {
            SubstepLane lane;
            lane.positions = positions[l];
            lane.velocities = velocities[l];
            lane.targets = targets[l];
            lane.contacts = contacts[l];
            lane.acceleration = accelerations[l];
            lanes.push_back(lane);
        }
        std::vector<SubstepLaneReport> reports(lanes.size());
        for (int s = 0; s < steps; ++s)
            ASSERT_TRUE(stepSubsteps(*level, *factor, 1.0 / 60.0, settings, lanes, work, reports).isOk());
        if (outReports) *outReports = reports;
    }
};

} // namespace

TEST(SubstepSolver, ALaneGivesTheSameBitsAloneAndInEveryBatch) {
    for (int variant = 0; variant < 4; ++variant) {
        const SubstepMethod method = variant % 2 == 0 ? SubstepMethod::Newton : SubstepMethod::LocalGlobal;
        const bool stiffBending = variant >= 2;
        Batch alone(8, method, stiffBending);
        for (int l = 0; l < 8; ++l) alone.step({l}, 20);
        for (const std::vector<int>& batch :
             std::vector<std::vector<int>>{{0, 1}, {2, 3, 4}, {5, 6, 7, 0}, {0, 1, 2, 3, 4, 5, 6, 7}}) {
            Batch together(8, method, stiffBending);
            together.step(batch, 20);
            for (int l : batch) {
                EXPECT_TRUE(sameBits(together.positions[l], alone.positions[l]))
                    << "lane " << l << " of a batch of " << batch.size() << ", method " << int(method)
                    << (stiffBending ? ", bending in the factor" : "");
                EXPECT_TRUE(sameBits(together.velocities[l], alone.velocities[l])) << "lane " << l;
            }
        }
    }
}

TEST(SubstepSolver, ANonFiniteLaneFailsAloneAndTheOthersAreUntouched) {
    Batch alone(4), together(4);
    for (int l : {0, 1, 3}) alone.step({l}, 5);
    together.positions[2][7].x() = NAN;
    const std::vector<Vec3> before = together.positions[2];
    std::vector<SubstepLaneReport> reports;
    together.step({0, 1, 2, 3}, 5, &reports);
    ASSERT_EQ(reports.size(), 4u);
    EXPECT_EQ(reports[2].status.code(), StatusCode::NumericalFailure);
    EXPECT_NE(reports[2].status.message().find("vertex 7"), std::string::npos) << reports[2].status.message();
    EXPECT_EQ(std::memcmp(before.data(), together.positions[2].data(), before.size() * sizeof(Vec3)), 0);
    for (int l : {0, 1, 3}) {
        EXPECT_TRUE(reports[l].status.isOk());
        EXPECT_TRUE(sameBits(together.positions[l], alone.positions[l])) << "lane " << l;
    }
}

TEST(SubstepSolver, BadInputIsRefusedNamingWhatIsWrong) {
    Batch b(1);
    SubstepWorkspace work;
    SubstepLane lane;
    lane.positions = b.positions[0];
    lane.velocities = b.velocities[0];
    lane.targets = b.targets[0];
    SubstepLaneReport report;
    const Span<const SubstepLane> lanes(&lane, 1);
    const Span<SubstepLaneReport> reports(&report, 1);
    SubstepSettings settings;
    settings.substeps = 0;
    EXPECT_NE(stepSubsteps(*b.level, *b.factor, 1.0 / 60.0, settings, lanes, work, reports).message().find("substeps"),
              std::string::npos);
    settings = SubstepSettings{};
    settings.substeps = 20;  // the factor is for 4 substeps of 1/60 s
    EXPECT_NE(stepSubsteps(*b.level, *b.factor, 1.0 / 60.0, settings, lanes, work, reports).message().find("factor"),
              std::string::npos);
    settings = SubstepSettings{};
    std::vector<Vec3> shortTargets;
    lane.targets = shortTargets;
    EXPECT_NE(stepSubsteps(*b.level, *b.factor, 1.0 / 60.0, settings, lanes, work, reports).message().find("targets"),
              std::string::npos);
    EXPECT_FALSE(b.level->buildFactor(0.0).isOk());
    ClothLevelDesc empty;
    EXPECT_FALSE(ClothLevel::cook(empty).isOk());
    const double badMass[] = {-1.0};
    ClothLevelDesc negative;
    negative.vertexCount = 1;
    negative.masses = badMass;
    EXPECT_NE(ClothLevel::cook(negative).status().message().find("mass"), std::string::npos);
}

TEST(SubstepExtremes, StaysFiniteAndBoundedFromSoftToRigidAndAtHugeSteps) {
    // TESTPLAN D1, D2, D4: stiffness 1e1 to 1e7 N/m, dt 1/1000 to 1/15 s, light and heavy cloth; the
    // energy never exceeds its start by more than 1% of the weight scale.
    struct Case {
        double stretch, density, dt;
    };
    for (SubstepMethod method : {SubstepMethod::Newton, SubstepMethod::LocalGlobal})
    for (const Case& c : {Case{1e1, 0.15, 1.0 / 60.0}, Case{1e7, 0.15, 1.0 / 60.0}, Case{1e7, 0.15, 1.0 / 15.0},
                          Case{5e3, 0.15, 1.0 / 1000.0}, Case{5e3, 1e-3, 1.0 / 30.0}, Case{5e3, 50.0, 1.0 / 30.0}}) {
        SubstepSettings settings;
        settings.method = method;
        settings.iterations = method == SubstepMethod::Newton ? 4 : 1;
        ClothMaterial material;
        material.stretchStiffness = c.stretch;
        material.shearStiffness = 0.1 * c.stretch;
        material.arealDensity = c.density;
        const RectanglePanel panel = test::horizontalSheet(8);
        const ClothMesh mesh = panel.build().value();
        auto sim = SubstepSimulation::create(mesh, material, farCorners(panel)).value();
        const double scale = c.density * kG;  // [J] the sheet's weight times 1 m
        auto energy = [&] {
            double potential = 0.0;
            for (uint32_t k = 0; k < sim->level().freeNodeCount(); ++k)
                potential += sim->level().nodeMasses()[k] * kG * sim->positions()[sim->level().vertexOfNode()[k]].y();
            return potential + sim->kineticEnergy();
        };
        const double e0 = energy();
        for (int step = 0; step < int(0.5 / c.dt) + 1; ++step) {
            ASSERT_TRUE(sim->step(c.dt, settings).isOk()) << c.stretch << " " << c.dt;
            ASSERT_LE(energy(), e0 + 0.01 * scale)
                << "method " << int(method) << " stretch " << c.stretch << " dt " << c.dt << " step " << step;
        }
    }
}

TEST(SubstepExtremes, MassRatioOfAMillionKeepsTheExactEquilibrium) {
    // TESTPLAN D4: a 1 kg bead at the end of a chain of 1 mg beads; at rest every spring carries
    // the bead and the light masses below it.
    const int n = 6;
    const double light = 1e-6, heavy = 1.0, k = 1000.0, rest = 0.05;
    auto sim = hangingChain(n, light, k, rest, heavy);
    SubstepSettings settings;
    settings.substeps = 1;
    for (int step = 0; step < 1000; ++step) ASSERT_TRUE(sim->step(1.0 / 20.0, settings).isOk());
    for (int j = 1; j <= n; ++j) {
        const double length = (sim->positions()[j - 1] - sim->positions()[j]).norm();
        const double expected = (heavy + (n - j) * light) * kG / k;
        EXPECT_NEAR(length - rest, expected, 1e-6 * expected) << "spring " << j;
    }
}

#include "support/AllocationCounter.h"

TEST(SubstepSolver, AWarmWorkspaceAllocatesNothing) {
    // After the first call sizes the workspace, stepping (with contacts, the strain limit and a
    // batch of three) touches no heap: the crowd's hot path.
    for (SubstepMethod method : {SubstepMethod::Newton, SubstepMethod::LocalGlobal}) {
        Batch b(3, method);
        b.step({0, 1, 2}, 2);  // warm-up: sizes the workspace
        SubstepWorkspace work;
        std::vector<SubstepLane> lanes;
        for (int l = 0; l < 3; ++l) {
            SubstepLane lane;
            lane.positions = b.positions[l];
            lane.velocities = b.velocities[l];
            lane.targets = b.targets[l];
            lane.contacts = b.contacts[l];
            lanes.push_back(lane);
        }
        std::vector<SubstepLaneReport> reports(lanes.size());
        ASSERT_TRUE(stepSubsteps(*b.level, *b.factor, 1.0 / 60.0, b.settings, lanes, work, reports).isOk());
        const long before = test::allocationCount();
        for (int s = 0; s < 10; ++s)
            ASSERT_TRUE(stepSubsteps(*b.level, *b.factor, 1.0 / 60.0, b.settings, lanes, work, reports).isOk());
        EXPECT_EQ(test::allocationCount() - before, 0) << "method " << int(method);
    }
}

TEST(SubstepSolver, PushingOutOfAPlaneAddsNoEnergy) {
    // A sheet that starts 2 cm inside a floor is pushed out over the first substep; the push is
    // inelastic, so the sheet does not bounce: no vertex ever rises above the offset plane by more
    // than roundoff, and the kinetic energy after the push is only what gravity gives back.
    const RectanglePanel panel = test::horizontalSheet(6);
    ClothMesh mesh = panel.build().value();
    for (Vec3& p : mesh.positions) p.y() = -0.02;
    auto sim = SubstepSimulation::create(mesh, ClothMaterial{}, {}).value();
    sim->setContacts(floorContacts(mesh));
    SubstepSettings settings;
    settings.contactThickness = 0.004;
    double highest = -1.0;
    for (int step = 0; step < 30; ++step) {
        ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
        for (const Vec3& p : sim->positions()) highest = std::max(highest, p.y());
        EXPECT_LT(sim->kineticEnergy(), 1e-9) << "step " << step;
    }
    EXPECT_LT(highest, 0.004 + 1e-9);
}

namespace {

// One free mass, no springs, no gravity, at `start` with `velocity`.
std::unique_ptr<SubstepSimulation> freeMass(const Vec3& start, const Vec3& velocity) {
    const double m[] = {0.1};
    ClothLevelDesc desc;
    desc.vertexCount = 1;
    desc.masses = m;
    auto sim = SubstepSimulation::create(desc, {start}).value();
    sim->velocities()[0] = velocity;
    sim->setAcceleration(Vec3::Zero());
    return sim;
}

// Distance after 1 s from where a mass at rest in the inertial frame appears in a frame turning
// at w about +Y: it goes round the other way, r(t) = R_y(-w t) r0, with v0 = -w x r0.
double rotatingFrameError(int substeps) {
    const double w = 2.0;
    const Vec3 omega(0.0, w, 0.0), r0(1.0, 0.3, 0.0);
    auto sim = freeMass(r0, -omega.cross(r0));
    sim->setFrameRotation(omega);
    SubstepSettings settings;
    settings.substeps = substeps;
    for (int step = 0; step < 60; ++step) EXPECT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
    const Vec3 expected = Eigen::AngleAxisd(-w * 1.0, Vec3::UnitY()) * r0;
    return (sim->positions()[0] - expected).norm();
}

} // namespace

TEST(SubstepSolver, AMassAtRestSeenFromATurningFrameGoesRoundTheOtherWayConvergingWithSubsteps) {
    // Centrifugal and Coriolis together keep it on its circle (Coriolis alone, or half of it, would
    // spiral it out); explicit in each substep, the error falls as the substep: first order.
    const double coarse = rotatingFrameError(4), fine = rotatingFrameError(16);
    EXPECT_LT(coarse, 0.02) << "[m] on a 1 m circle";
    EXPECT_NEAR(coarse / fine, 4.0, 1.0) << coarse << " " << fine;
}

/// A mass on a spring of stiffness k and rest length `rest` from an attached node at the origin,
/// the mass starting at `start`, both of mass `mass`.
std::unique_ptr<SubstepSimulation> massOnSpring(double k, double mass, double rest, const Vec3& start) {
    std::vector<Spring> springs = {{0, 1, k, rest, SpringKind::Structural}};
    const double m[] = {mass, mass};
    const uint32_t attached[] = {0};
    ClothLevelDesc desc;
    desc.vertexCount = 2;
    desc.springs = springs;
    desc.masses = m;
    desc.attachedVertices = attached;
    return SubstepSimulation::create(desc, {Vec3::Zero(), start}).value();
}

TEST(SubstepSolver, AMassOnASpringInATurningFrameSettlesAtTheCentrifugalRadius) {
    // Spring k, rest length L from an attached node on the axis, no gravity: k (r - L) = m w^2 r,
    // so r = k L / (k - m w^2). Damping settles it.
    const double k = 40.0, mass = 0.1, rest = 0.5, w = 12.0;
    auto sim = massOnSpring(k, mass, rest, Vec3(rest, 0.0, 0.0));
    sim->setAcceleration(Vec3::Zero());
    sim->setFrameRotation(Vec3(0.0, w, 0.0));
    sim->setVelocityDamping(4.0);
    SubstepSettings settings;
    settings.substeps = 8;
    settings.iterations = 20;
    for (int step = 0; step < 600; ++step) ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
    const double expected = k * rest / (k - mass * w * w);
    EXPECT_NEAR(sim->positions()[1].norm(), expected, 1e-6 * expected) << "expected " << expected;
    EXPECT_NEAR(sim->positions()[1].y(), 0.0, 1e-12);
}

TEST(SubstepSolver, VelocityDampingDecaysExactlyPerSubstep) {
    // No forces: each substep keeps exp(-c h) of the velocity, then moves by h v. After n
    // substeps x = x0 + h v0 sum_{j=1..n} q^j with q = exp(-c h), v = q^n v0.
    const Vec3 x0(0.0, 1.0, 0.0), v0(2.0, 0.0, -1.0);
    auto sim = freeMass(x0, v0);
    const double c = 3.0;
    sim->setVelocityDamping(c);
    SubstepSettings settings;
    settings.substeps = 5;
    const double dt = 1.0 / 60.0, h = dt / settings.substeps;
    for (int step = 0; step < 30; ++step) ASSERT_TRUE(sim->step(dt, settings).isOk());
    const int n = 30 * settings.substeps;
    const double q = std::exp(-c * h);
    const double sum = q * (1.0 - std::pow(q, n)) / (1.0 - q);
    EXPECT_LT((sim->positions()[0] - (x0 + h * sum * v0)).norm(), 1e-12);
    EXPECT_LT((sim->velocities()[0] - std::pow(q, n) * v0).norm(), 1e-12);
}

TEST(SubstepSolver, ASpringSoftInCompressionRecoilsToTheStretchItsStoredEnergyAllows) {
    // A mass on a spring from an attached node, no gravity, released at rest compressed by d: it
    // stored compression x k d^2 / 2, all of it kinetic at the rest length and all of it elastic
    // again at the largest stretch s, so k s^2 / 2 = compression x k d^2 / 2 and
    // s = d sqrt(compression). Small substeps keep backward Euler's damping under a percent.
    const double k = 100.0, mass = 1.0, rest = 1.0, d = 0.1;
    for (SubstepMethod method : {SubstepMethod::Newton, SubstepMethod::LocalGlobal}) {
        for (double compression : {1.0, 0.25, 0.04}) {
            auto sim = massOnSpring(k, mass, rest, Vec3(rest - d, 0.0, 0.0));
            sim->setAcceleration(Vec3::Zero());
            SubstepSettings settings;
            settings.method = method;
            settings.substeps = 100;
            settings.iterations = method == SubstepMethod::Newton ? 4 : 20;
            settings.compressionStiffness = compression;
            // A quarter period on each side of the rest length, and some more.
            const double quarters = 0.25 * 2.0 * kPi * (std::sqrt(mass / (compression * k)) + std::sqrt(mass / k));
            double longest = 0.0;
            for (double t = 0.0; t < 1.2 * quarters; t += 1.0 / 60.0) {
                ASSERT_TRUE(sim->step(1.0 / 60.0, settings).isOk());
                longest = std::max(longest, sim->positions()[1].x());
            }
            const double expected = d * std::sqrt(compression);
            EXPECT_NEAR(longest - rest, expected, 0.02 * expected)
                << (method == SubstepMethod::Newton ? "Newton" : "local/global") << ", compression " << compression;
            // No spring pulls sideways: the motion stays on the line.
            EXPECT_EQ(sim->positions()[1].y(), 0.0);
        }
    }
}

TEST(SubstepSolver, CompressionStiffnessOutsideZeroToOneIsRefused) {
    SubstepSettings settings;
    for (double bad : {-0.1, 1.5, std::nan("")}) {
        settings.compressionStiffness = bad;
        const Status s = settings.validate();
        EXPECT_FALSE(s.isOk());
        EXPECT_NE(s.message().find("compressionStiffness"), std::string::npos) << s.message();
    }
}
