#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "crowdcloth/cloth/SubstepSimulation.h"
#include "crowdcloth/collision/SelfCollision.h"
#include "crowdcloth/core/RectanglePanel.h"
#include "self_collision/TriangleIntersections.h"

namespace cc::collision {
namespace {

using Triangles = std::vector<std::array<uint32_t, 3>>;

/// The signed distance of x from a contact's plane as the substep solver places it at the step's
/// end (offset: SubstepSettings::contactThickness).
double planeDistance(const Contact& c, const Vec3& x, double offset) { return c.normal.dot(x - c.point) - offset; }

// Triangle (0, 1, 2) in z = 0, vertex 3 above its middle at height `gap`.
struct VertexOverTriangle {
    Triangles tris{{0, 1, 2}};
    std::vector<Vec3> x0;
    explicit VertexOverTriangle(double gap)
        : x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.25, 0.25, gap)} {}
};

SelfCollision makeSelf(const Triangles& tris, uint32_t vertexCount) {
    auto self = SelfCollision::create(tris, vertexCount, {});
    EXPECT_TRUE(self.isOk()) << self.status().message();
    return std::move(self.value());
}

TEST(SeparatingPlanes, AnApproachingPairGetsTheMidplaneOffsetByHalfTheThickness) {
    VertexOverTriangle s(0.01);
    SelfCollision self = makeSelf(s.tris, 4);
    std::vector<Vec3> v(4, Vec3::Zero());
    v[3] = Vec3(0, 0, -0.6);  // 1 cm in 1/60 s: twice that reaches the triangle
    SeparatingPlaneSettings settings;
    settings.thickness = 2e-3;
    settings.solverOffset = 1e-3;
    const double dt = 1.0 / 60;
    std::vector<Contact> planes;
    ASSERT_TRUE(self.separatingPlanes(s.x0, v, dt, settings, planes).isOk());
    ASSERT_EQ(planes.size(), 4u);
    // The plane moves at the pair's mean velocity: the midpoint of the closest points (z = 5 mm)
    // moving at the mean of the vertex's and the triangle point's velocities (-0.3 m/s).
    const Vec3 meanVelocity(0, 0, -0.3);
    for (const Contact& c : planes) {
        EXPECT_EQ(c.surfaceVelocity, meanVelocity);
        const Vec3 midAtEnd(0.25, 0.25, 0.005 - 0.3 * dt);
        const double side = c.vertex == 3 ? 1.0 : -1.0;
        EXPECT_NEAR(c.normal.z(), side, 1e-12);
        // The solver's plane lies half the thickness from the moving midplane, on the vertex's side.
        EXPECT_NEAR(planeDistance(c, midAtEnd, settings.solverOffset), -0.5 * settings.thickness, 1e-12);
    }
}

TEST(SeparatingPlanes, NoVertexStartsBehindItsPlaneWhenThePairIsFartherThanTheThickness) {
    // The closest points of two disjoint convex primitives span a separating plane: a tilted
    // triangle's far corners are on their side of it too, so no plane pushes a vertex it has not
    // reached. Random pairs, each side checked at x0 against the plane at the step's start.
    std::srand(3);
    auto unit = [] { return double(std::rand()) / RAND_MAX - 0.5; };
    int planesChecked = 0;
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Vec3> x0(6);
        for (int i = 0; i < 3; ++i) x0[i] = 0.05 * Vec3(unit(), unit(), 0.3 * unit());
        for (int i = 3; i < 6; ++i) x0[i] = 0.05 * Vec3(unit(), unit(), 0.3 * unit()) + Vec3(0, 0, 0.012);
        SelfCollision self = makeSelf(Triangles{{0, 1, 2}, {3, 4, 5}}, 6);
        std::vector<Vec3> v(6, Vec3::Zero());
        for (int i = 3; i < 6; ++i) v[i] = Vec3(unit(), unit(), -1.0);
        SeparatingPlaneSettings settings;
        settings.thickness = 2e-3;
        std::vector<Contact> planes;
        const double dt = 1.0 / 60;
        ASSERT_TRUE(self.separatingPlanes(x0, v, dt, settings, planes).isOk());
        for (const Contact& c : planes) {
            const Vec3 planeAtStart = c.point - dt * c.surfaceVelocity;
            const double distance = c.normal.dot(x0[c.vertex] - planeAtStart);
            const double gapAtStart = 2.0 * (distance + 0.5 * settings.thickness);  // >= the pair's gap
            if (gapAtStart < settings.thickness) continue;  // a pair closer than the thickness is pushed apart
            EXPECT_GE(distance, -1e-12) << "trial " << trial << " vertex " << c.vertex;
            ++planesChecked;
        }
    }
    EXPECT_GT(planesChecked, 200);
}

TEST(SeparatingPlanes, PairsMovingTogetherOrFarApartGetNone) {
    VertexOverTriangle s(0.01);
    SelfCollision self = makeSelf(s.tris, 4);
    std::vector<Contact> planes;
    const std::vector<Vec3> together(4, Vec3(0.3, -2.0, -1.0));  // a falling sheet: the pair keeps its gap
    ASSERT_TRUE(self.separatingPlanes(s.x0, together, 1.0 / 60, {}, planes).isOk());
    EXPECT_TRUE(planes.empty());
    std::vector<Vec3> apart(4, Vec3::Zero());
    apart[3] = Vec3(0, 0, 1.0);
    ASSERT_TRUE(self.separatingPlanes(s.x0, apart, 1.0 / 60, {}, planes).isOk());
    EXPECT_TRUE(planes.empty());
}

TEST(SeparatingPlanes, BadInputNamesTheProblem) {
    VertexOverTriangle s(0.01);
    SelfCollision self = makeSelf(s.tris, 4);
    std::vector<Contact> planes;
    std::vector<Vec3> v(4, Vec3::Zero());
    v[2].x() = std::nan("");
    Status status = self.separatingPlanes(s.x0, v, 1.0 / 60, {}, planes);
    EXPECT_NE(status.message().find("vertex 2"), std::string::npos) << status.message();
    EXPECT_TRUE(planes.empty());
    v[2] = Vec3::Zero();
    EXPECT_FALSE(self.separatingPlanes(s.x0, v, 0.0, {}, planes).isOk());
    EXPECT_FALSE(self.separatingPlanes(s.x0, std::vector<Vec3>(3), 1.0 / 60, {}, planes).isOk());
    SeparatingPlaneSettings bad;
    bad.lookahead = -1.0;
    EXPECT_NE(self.separatingPlanes(s.x0, v, 1.0 / 60, bad, planes).message().find("lookahead"), std::string::npos);
}

// ---- The fold: half a sheet falling onto the other half (issue 10's blow-up) ----

struct FoldRun {
    int steps = 0;
    int intersecting = 0;          ///< intersecting triangle pairs after the last step
    int firstIntersectingStep = -1;
    double fastestStep = 0.0;      ///< [m] largest distance a vertex moved in one step
    double maxStrain = 0.0;
    double topHeight = 0.0;        ///< [m] highest vertex at the end
    double solveSeconds = 0.0, resolveSeconds = 0.0, planeSeconds = 0.0;
    uint32_t failSafes = 0, stopped = 0;
    std::size_t maxPlanes = 0;
};

/// A 0.6 m sheet of (cells + 1)^2 vertices on the floor with its far half standing up, leaning
/// 10 degrees over the near half, stepped by the substep solver at 60 Hz as the World steps a
/// garment: floor contacts and (with `planes`) the self-contacts' separating planes in the solve,
/// then SelfCollision::resolve as the fail-safe after it.
FoldRun runFold(uint32_t cells, bool planes, int steps) {
    const double size = 0.6, thickness = 4e-3, dt = 1.0 / 60;
    RectanglePanel panel;
    panel.width = panel.height = size;
    panel.columns = panel.rows = cells;
    panel.origin = Vec3(-0.5 * size, 0.0, 0.0);
    panel.vAxis = Vec3(0.0, 0.0, 1.0);  // lying in the floor plane, v along +Z
    ClothMesh mesh = panel.build().value();
    const double lean = 10.0 * M_PI / 180.0;
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        const double along = mesh.restPositions[v].y();
        if (along <= 0.5 * size) {
            mesh.positions[v] = Vec3(mesh.positions[v].x(), thickness, along);
        } else {
            const double up = along - 0.5 * size;  // the standing half, leaning back over the floor half
            mesh.positions[v] = Vec3(mesh.positions[v].x(), thickness + up * std::cos(lean),
                                     0.5 * size - up * std::sin(lean));
        }
    }
    EXPECT_EQ(test::countIntersectingPairs(mesh.positions, mesh.triangles), 0);
    cloth::ClothMaterial material;
    material.bendStiffness = 1e-6;
    auto sim = cloth::SubstepSimulation::create(mesh, material, {}).value();
    cloth::SubstepSettings settings;
    settings.substeps = 4;
    settings.iterations = 4;
    settings.strainLimit = 0.1;
    settings.contactThickness = thickness;
    settings.friction = cloth::Friction{0.3, 0.24};
    std::vector<Contact> floor(mesh.vertexCount());
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        floor[v].vertex = v;
        floor[v].point = Vec3(mesh.positions[v].x(), 0.0, mesh.positions[v].z());
        floor[v].normal = Vec3::UnitY();
    }
    SelfCollisionSettings selfSettings;
    selfSettings.thickness = 0.5 * thickness;  // as the World's garments
    selfSettings.ccdGap = std::min(selfSettings.ccdGap, selfSettings.thickness);
    selfSettings.parallel.maxThreads = 1;  // as the World's garments: they run in parallel already
    selfSettings.proximityPass = !planes;  // the planes repel inside the solve
    auto self = SelfCollision::create(mesh.triangles, uint32_t(mesh.vertexCount()), selfSettings).value();
    SeparatingPlaneSettings planeSettings;
    planeSettings.thickness = selfSettings.thickness;
    planeSettings.solverOffset = thickness;
    const std::vector<double> masses(mesh.vertexCount(), 1.0);
    FoldRun run;
    using Clock = std::chrono::steady_clock;
    auto seconds = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
    for (int step = 0; step < steps; ++step) {
        std::size_t planeCount = 0;
        const std::vector<Vec3> x0 = sim->positions();
        std::vector<Contact> contacts = floor;
        auto t = Clock::now();
        if (planes) {
            EXPECT_TRUE(self.separatingPlanes(x0, sim->velocities(), dt, planeSettings, contacts).isOk());
            run.maxPlanes = std::max(run.maxPlanes, contacts.size() - floor.size());
            planeCount = contacts.size() - floor.size();
        }
        run.planeSeconds += seconds(t);
        // Floor planes point at the vertex's floor point wherever it slid to: the floor is flat.
        for (uint32_t v = 0; v < mesh.vertexCount(); ++v) contacts[v].point = Vec3(x0[v].x(), 0.0, x0[v].z());
        sim->setContacts(std::move(contacts));
        t = Clock::now();
        const Status stepped = sim->step(dt, settings);
        run.solveSeconds += seconds(t);
        EXPECT_TRUE(stepped.isOk()) << stepped.message();
        if (!stepped.isOk()) break;
        std::vector<Vec3> x1 = sim->positions();
        SelfCollisionStats stats;
        t = Clock::now();
        EXPECT_TRUE(self.resolve(x0, x1, masses, stats).isOk());
        run.resolveSeconds += seconds(t);
        run.failSafes += stats.failSafeActivations;
        run.stopped += stats.stoppedVertices;
        for (std::size_t v = 0; v < x1.size(); ++v) {
            run.fastestStep = std::max(run.fastestStep, (x1[v] - x0[v]).norm());
            sim->positions()[v] = x1[v];
            sim->velocities()[v] = (x1[v] - x0[v]) / dt;
        }
        run.maxStrain = std::max(run.maxStrain, sim->maxEdgeStrain());
        ++run.steps;
        if (std::getenv("CC_FOLD_TRACE"))
            std::printf("step %d: fastest %.1f mm, strain %.1f %%, planes %zu, fail-safe %u, ccd tests %u, "
                        "collisions %u; mean solve %.1f ms, resolve %.1f ms\n",
                        step, 1e3 * run.fastestStep, 100 * sim->maxEdgeStrain(), planeCount, stats.failSafeActivations,
                        stats.ccdTests, stats.firstPassCollisions, 1e3 * run.solveSeconds / run.steps,
                        1e3 * run.resolveSeconds / run.steps);
        if (run.firstIntersectingStep < 0 && test::countIntersectingPairs(sim->positions(), mesh.triangles) > 0)
            run.firstIntersectingStep = step;
    }
    run.intersecting = test::countIntersectingPairs(sim->positions(), mesh.triangles);
    for (const Vec3& p : sim->positions()) run.topHeight = std::max(run.topHeight, p.y());
    return run;
}

void printFold(const char* name, const FoldRun& run) {
    std::printf("[ fold %s ] %d steps: fastest vertex %.1f mm per step, max strain %.1f %%, top %.0f mm, "
                "intersecting pairs %d (first at step %d); fail-safe steps %u, stopped vertices %u, most planes %zu; "
                "per step: solve %.2f ms, planes %.2f ms, resolve %.2f ms\n",
                name, run.steps, 1e3 * run.fastestStep, 100 * run.maxStrain, 1e3 * run.topHeight, run.intersecting,
                run.firstIntersectingStep, run.failSafes, run.stopped, run.maxPlanes,
                1e3 * run.solveSeconds / std::max(1, run.steps), 1e3 * run.planeSeconds / std::max(1, run.steps),
                1e3 * run.resolveSeconds / std::max(1, run.steps));
}

TEST(SeparatingPlanesFold, HalfASheetFallsOntoTheOtherHalfWithoutBlowingUp) {
    const FoldRun run = runFold(32, true, 90);
    printFold("33^2 with planes", run);
    EXPECT_EQ(run.steps, 90);
    EXPECT_EQ(run.intersecting, 0);
    EXPECT_EQ(run.firstIntersectingStep, -1);
    // Free fall of the 0.3 m half from the vertical reaches ~3.4 m/s at the tip: 57 mm per step.
    // The blow-up moved vertices 0.5-1.2 m per step.
    EXPECT_LT(run.fastestStep, 0.1);
    EXPECT_LT(run.maxStrain, 0.2);
    EXPECT_LT(run.topHeight, 0.05) << "the standing half must have fallen";
}

// The measurement the planes answer: the same fold with only the resolve after the solve (issue
// 10: vertices moving ~0.5 m per step from step 6, then seconds per step). Run by hand.
TEST(SeparatingPlanesFold, DISABLED_WithoutPlanesForComparison) {
    printFold("33^2 without planes", runFold(32, false, 90));
}

} // namespace
} // namespace cc::collision
