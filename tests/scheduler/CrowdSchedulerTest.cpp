#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "crowdcloth/lod/CrowdScheduler.h"
#include "support/Cameras.h"

namespace cc::lod {
namespace {

constexpr double kFov = 1.0;        // [rad]
constexpr double kHeight = 1080.0;  // [px]

SchedulerCamera cameraAtOrigin() {
    SchedulerCamera camera;
    camera.viewProjection = test::perspective(kFov, 16.0 / 9.0, 0.1, 1000.0) *
                            test::lookAt(Vec3::Zero(), Vec3(0, 0, -1));
    camera.viewportWidth = 1920.0;
    camera.viewportHeight = kHeight;
    return camera;
}

/// Five levels; each coarser one is 4x cheaper and twice as wrong (second-order geometry would
/// be 4x, the hanging-sheet sag converges at about that).
GarmentProfile fiveLevels() {
    GarmentProfile profile;
    for (int l = 0; l < 5; ++l) {
        LevelProfile level;
        level.errorMetres = l == 4 ? 0.0 : 0.04 / std::pow(2.0, l);
        level.costMs[int(SolverChoice::SubstepNewton)] = 0.01 * std::pow(4.0, l);
        profile.levels.push_back(level);
    }
    return profile;
}

GarmentRequest garmentAt(uint64_t id, double distance, double speed = 1.0) {
    GarmentRequest r;
    r.id = id;
    r.center = Vec3(0.0, 0.0, -distance);
    r.radius = 0.5;
    r.speed = speed;
    return r;
}

std::vector<GarmentSchedule> schedule(const SchedulerSettings& settings, const std::vector<GarmentRequest>& requests,
                                      const GarmentProfile& profile = fiveLevels()) {
    const SchedulerCamera camera = cameraAtOrigin();
    std::vector<GarmentSchedule> out(requests.size());
    const Status status = scheduleGarments(settings, Span<const SchedulerCamera>(&camera, 1),
                                           Span<const GarmentProfile>(&profile, 1), requests, out);
    EXPECT_TRUE(status.isOk()) << status.message();
    return out;
}

SchedulerSettings unlimited() {
    SchedulerSettings s;
    s.budgetMs = 1e9;
    s.refineWithSlack = false;
    return s;
}

TEST(ProjectSphere, PixelsPerMetreMatchesPinhole) {
    const SchedulerCamera camera = cameraAtOrigin();
    for (double d : {2.0, 10.0, 100.0}) {
        const ScreenProjection p = projectSphere(camera, Vec3(0, 0, -d), 1e-6);
        EXPECT_TRUE(p.visible);
        EXPECT_NEAR(p.pixelsPerMetre, 0.5 * kHeight / (d * std::tan(0.5 * kFov)), 1e-6 * p.pixelsPerMetre);
    }
    EXPECT_FALSE(projectSphere(camera, Vec3(0, 0, 10), 1.0).visible) << "behind the camera";
    EXPECT_FALSE(projectSphere(camera, Vec3(100, 0, -10), 1.0).visible) << "far to the right";
    EXPECT_TRUE(projectSphere(camera, Vec3(0, 0, 0.5), 1.0).visible) << "sphere around the camera";
}

TEST(ProjectSphere, ASphereAroundTheEyeIsSeenAtTheNearPlanesScale) {
    // The camera inside a garment's bounds (a close-up, or a skirt around the eye): nothing is drawn
    // nearer than the near plane (0.1 m), so that is the largest scale the garment can have.
    const double nearPlaneScale = 0.5 * kHeight / (0.1 * std::tan(0.5 * kFov));
    const SchedulerCamera camera = cameraAtOrigin();
    for (const Vec3& center : {Vec3(0, 0, 0.5), Vec3(0, 0, -0.5), Vec3(0.3, -0.2, 0)}) {
        const ScreenProjection p = projectSphere(camera, center, 1.0);
        EXPECT_TRUE(p.visible);
        EXPECT_NEAR(p.pixelsPerMetre, nearPlaneScale, 1e-9 * nearPlaneScale) << center.transpose();
    }
    // Moved away, the same camera (translated and turned) sees the same near-plane limit.
    SchedulerCamera moved = camera;
    moved.viewProjection = test::perspective(kFov, 16.0 / 9.0, 0.1, 1000.0) *
                           test::lookAt(Vec3(40, 2, -7), Vec3(41, 2, -6));
    EXPECT_NEAR(projectSphere(moved, Vec3(40, 2, -7), 0.8).pixelsPerMetre, nearPlaneScale, 1e-6 * nearPlaneScale);
    // Just beyond the near plane the pinhole scale holds again.
    const ScreenProjection justBeyond = projectSphere(camera, Vec3(0, 0, -1.2), 1.0);
    EXPECT_NEAR(justBeyond.pixelsPerMetre, 0.5 * kHeight / (0.2 * std::tan(0.5 * kFov)), 1e-6 * nearPlaneScale);

    // And the scheduler's predicted error stays a screen-sized figure, not a million pixels.
    GarmentRequest around = garmentAt(0, 0.2);
    around.radius = 1.0;
    const auto out = schedule(unlimited(), {around});
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(std::isfinite(out[0].predictedErrorPx));
    EXPECT_LE(out[0].predictedErrorPx, 0.04 * nearPlaneScale);
}

TEST(CrowdScheduler, LevelFallsAndIntervalGrowsWithDistance) {
    std::vector<GarmentRequest> requests;
    requests.reserve(60);
    for (int i = 0; i < 60; ++i) requests.push_back(garmentAt(i, 1.0 + 4.0 * i));
    const auto out = schedule(unlimited(), requests);
    for (std::size_t i = 1; i < out.size(); ++i) {
        EXPECT_LE(out[i].level, out[i - 1].level) << "garment " << i;
        EXPECT_GE(out[i].updateInterval, out[i - 1].updateInterval) << "garment " << i;
        EXPECT_LE(out[i].predictedErrorPx, 1.0);
    }
    EXPECT_EQ(out.front().level, 4);
    EXPECT_EQ(out.front().updateInterval, 1);
    EXPECT_EQ(out.back().level, 0);
    EXPECT_GT(out.back().updateInterval, 1);
}

TEST(CrowdScheduler, PicksTheCheapestOfferedSolver) {
    GarmentProfile profile = fiveLevels();
    profile.levels[0].costMs[int(SolverChoice::SubstepLocalGlobal)] = 0.001;
    profile.levels[0].substeps = 16;
    profile.levels[0].iterations = 1;
    const auto out = schedule(unlimited(), {garmentAt(1, 900.0)}, profile);
    EXPECT_EQ(out[0].level, 0);
    EXPECT_EQ(out[0].solver, SolverChoice::SubstepLocalGlobal);
    EXPECT_EQ(out[0].substeps, 16);
    EXPECT_EQ(out[0].iterations, 1);
    const auto near = schedule(unlimited(), {garmentAt(1, 1.0)}, profile);
    EXPECT_EQ(near[0].solver, SolverChoice::SubstepNewton);
    EXPECT_EQ(near[0].substeps, 4);
}

TEST(CrowdScheduler, StaysWithinBudgetWithTheFixedCostModel) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> distance(1.0, 60.0);
    std::vector<GarmentRequest> requests;
    requests.reserve(300);
    for (int i = 0; i < 300; ++i) requests.push_back(garmentAt(i, distance(rng), 1.4));
    const auto free = schedule(unlimited(), requests);
    double freeCost = 0.0, freeError = 0.0;
    for (const auto& s : free) freeCost += s.predictedCostMs, freeError += s.predictedErrorPx;

    for (double budget : {0.5 * freeCost, 0.1 * freeCost, 0.02 * freeCost}) {
        SchedulerSettings settings = unlimited();
        settings.budgetMs = budget;
        const auto out = schedule(settings, requests);
        double cost = 0.0, error = 0.0;
        for (const auto& s : out) cost += s.predictedCostMs, error += s.predictedErrorPx;
        EXPECT_LE(cost, budget * (1 + 1e-12)) << "budget " << budget;
        EXPECT_GT(error, freeError) << "a tighter budget must cost accuracy";
    }
}

TEST(CrowdScheduler, DegradesTheLeastImportantAndFarthestFirst) {
    std::vector<GarmentRequest> requests = {garmentAt(1, 3.0), garmentAt(2, 3.0), garmentAt(3, 30.0)};
    requests[1].importance = 10.0;
    const auto free = schedule(unlimited(), requests);
    SchedulerSettings settings = unlimited();
    settings.budgetMs = 0.7 * (free[0].predictedCostMs + free[1].predictedCostMs + free[2].predictedCostMs);
    const auto out = schedule(settings, requests);
    EXPECT_EQ(out[1].level, free[1].level) << "the important garment keeps its level";
    EXPECT_LT(out[0].level * 1.0 / out[0].updateInterval, free[0].level * 1.0 / free[0].updateInterval);
}

TEST(CrowdScheduler, SpendsSlackOnTheLargestGains) {
    std::vector<GarmentRequest> requests;
    requests.reserve(20);
    for (int i = 0; i < 20; ++i) requests.push_back(garmentAt(i, 5.0 + 5.0 * i));
    SchedulerSettings settings;
    settings.refineWithSlack = false;
    settings.budgetMs = 1000.0;
    const auto base = schedule(settings, requests);
    settings.refineWithSlack = true;
    const auto out = schedule(settings, requests);
    double cost = 0.0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_GE(out[i].level, base[i].level);
        EXPECT_LE(out[i].predictedErrorPx, base[i].predictedErrorPx);
        cost += out[i].predictedCostMs;
    }
    EXPECT_LE(cost, settings.budgetMs * (1.0 - settings.slackHeadroom));
    EXPECT_EQ(out.back().level, 4) << "plenty of budget: even the farthest garment is finest";
}

/// Distance at which a garment approaching the camera first refines past `level`, or a receding
/// one first coarsens to `level`.
double switchDistance(const SchedulerSettings& settings, bool approaching, int level) {
    GarmentSchedule previous;
    double lastD = 0.0;
    for (int i = 0; i <= 4000; ++i) {
        const double d = approaching ? 200.0 - 0.05 * i : 0.5 + 0.05 * i;
        GarmentRequest r = garmentAt(1, d);
        r.speed = 0.0;
        r.previous = previous;
        previous = schedule(settings, {r})[0];
        if (approaching ? previous.level > level : previous.level <= level) return d;
        lastD = d;
    }
    return lastD;
}

TEST(CrowdScheduler, HysteresisSeparatesRefineAndCoarsenDistances) {
    const SchedulerSettings settings = unlimited();
    const double refineAt = switchDistance(settings, true, 1);
    const double coarsenAt = switchDistance(settings, false, 1);
    // Refining happens where level 1's error reaches the tolerance, coarsening back only where it
    // is (1 - hysteresis) of it: 1 / 0.75 = 1.33x farther (less the sphere radius).
    EXPECT_GT(coarsenAt, refineAt * (1.0 + 0.5 * settings.hysteresis))
        << "coarsening must wait until the coarse level is clearly within tolerance";

    // A still camera at the threshold: the decision never changes, whichever side it came from.
    for (double d : {refineAt, coarsenAt, 0.5 * (refineAt + coarsenAt)}) {
        GarmentRequest r = garmentAt(1, d, 0.0);
        r.previous = schedule(settings, {r})[0];
        const int first = r.previous.level;
        for (int frame = 0; frame < 50; ++frame) {
            r.previous = schedule(settings, {r})[0];
            ASSERT_EQ(r.previous.level, first) << "flicker at " << d << " m, frame " << frame;
        }
    }
}

TEST(CrowdScheduler, ResultDoesNotDependOnInputOrder) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> distance(1.0, 80.0);
    std::vector<GarmentRequest> requests;
    requests.reserve(100);
    for (int i = 0; i < 100; ++i) requests.push_back(garmentAt(1000 - i, distance(rng)));
    requests[10].center = requests[11].center; // an exact tie: decided by id
    SchedulerSettings settings;
    settings.budgetMs = 3.0;
    const auto out = schedule(settings, requests);
    std::vector<GarmentRequest> shuffled = requests;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const auto outShuffled = schedule(settings, shuffled);
    for (std::size_t i = 0; i < shuffled.size(); ++i) {
        const auto j = std::find_if(requests.begin(), requests.end(),
                                    [&](const GarmentRequest& r) { return r.id == shuffled[i].id; }) - requests.begin();
        EXPECT_EQ(outShuffled[i].level, out[j].level);
        EXPECT_EQ(outShuffled[i].updateInterval, out[j].updateInterval);
        EXPECT_EQ(outShuffled[i].predictedCostMs, out[j].predictedCostMs);
    }
}

TEST(CrowdScheduler, UnseenGarmentsSleepAtRestAndIdleOtherwise) {
    GarmentRequest behind = garmentAt(1, -5.0, 0.0);
    behind.atRest = true;
    GarmentRequest moving = garmentAt(2, -5.0, 1.0);
    const auto out = schedule(unlimited(), {behind, moving});
    EXPECT_FALSE(out[0].visible);
    EXPECT_EQ(out[0].updateInterval, 0);
    EXPECT_EQ(out[0].collision, CollisionDetail::None);
    EXPECT_EQ(out[0].predictedCostMs, 0.0);
    EXPECT_EQ(out[1].level, 0);
    EXPECT_EQ(out[1].updateInterval, SchedulerSettings{}.maxUpdateInterval);
    EXPECT_EQ(out[1].collision, CollisionDetail::Proxies);
}

TEST(CrowdScheduler, CollisionDetailFollowsScreenSizeAndSpeed) {
    const auto out = schedule(unlimited(), {garmentAt(1, 1.5, 3.0), garmentAt(2, 1.5, 0.5), garmentAt(3, 80.0, 3.0)});
    EXPECT_EQ(out[0].collision, CollisionDetail::MeshContinuous);
    EXPECT_TRUE(out[0].selfCollision);
    EXPECT_EQ(out[1].collision, CollisionDetail::Mesh);
    EXPECT_EQ(out[2].collision, CollisionDetail::Proxies);
    EXPECT_FALSE(out[2].selfCollision);
}

TEST(CrowdScheduler, CountsSelfCollisionsCostWhereItIsOn) {
    // Self-collision is taken by a garment seen large at one of its finest two levels: its cost
    // joins that garment's prediction there, nowhere else, and a budget that fits the garment only
    // without it is kept (the crowd pays for it with accuracy where it costs least).
    GarmentProfile selfCosts = fiveLevels();
    for (LevelProfile& level : selfCosts.levels) level.selfCollisionCostMs = 2.0;
    const std::vector<GarmentRequest> requests = {garmentAt(0, 0.6, 3.0), garmentAt(1, 80.0, 3.0)};
    SchedulerSettings settings = unlimited();
    settings.pixelTolerance = 1e-6;  // the finest level, every frame, everywhere
    const auto plain = schedule(settings, requests), costly = schedule(settings, requests, selfCosts);
    ASSERT_EQ(costly[0].level, 4);
    ASSERT_EQ(costly[0].updateInterval, 1);
    ASSERT_TRUE(costly[0].selfCollision);
    EXPECT_DOUBLE_EQ(costly[0].predictedCostMs, plain[0].predictedCostMs + 2.0);
    EXPECT_FALSE(costly[1].selfCollision);
    EXPECT_DOUBLE_EQ(costly[1].predictedCostMs, plain[1].predictedCostMs) << "small on screen: no self-collision";

    settings.budgetMs = plain[0].predictedCostMs + plain[1].predictedCostMs + 1.0;  // short of the 2 ms
    const auto tight = schedule(settings, requests, selfCosts);
    EXPECT_LE(tight[0].predictedCostMs + tight[1].predictedCostMs, settings.budgetMs * (1 + 1e-12));
    const double solve = fiveLevels().levels[tight[0].level].costMs[0];
    EXPECT_DOUBLE_EQ(tight[0].predictedCostMs * tight[0].updateInterval, solve + (tight[0].selfCollision ? 2.0 : 0.0));
}

TEST(CrowdScheduler, CountsTheCollisionDetailsCostInTheBudget) {
    // The same near garment, with and without a body-mesh cost on top of its solve: its predicted
    // cost carries the mesh's, and under one budget the crowd around it gets coarser to pay for it.
    GarmentProfile meshCosts = fiveLevels();
    for (LevelProfile& level : meshCosts.levels) {
        level.collisionCostMs[int(CollisionDetail::Mesh)] = 0.5;
        level.collisionCostMs[int(CollisionDetail::MeshContinuous)] = 1.0;
    }
    std::vector<GarmentRequest> requests = {garmentAt(0, 1.5, 3.0)};
    for (int i = 1; i < 40; ++i) requests.push_back(garmentAt(i, 4.0 + i, 1.0));
    const auto plain = schedule(unlimited(), requests);
    const auto costly = schedule(unlimited(), requests, meshCosts);
    ASSERT_EQ(costly[0].collision, CollisionDetail::MeshContinuous);
    const double solve = fiveLevels().levels[costly[0].level].costMs[0];
    EXPECT_DOUBLE_EQ(costly[0].predictedCostMs * costly[0].updateInterval, solve + 1.0);
    for (std::size_t i = 1; i < requests.size(); ++i) {
        if (costly[i].collision == CollisionDetail::Proxies) {
            EXPECT_DOUBLE_EQ(costly[i].predictedCostMs, plain[i].predictedCostMs) << "capsules add nothing";
        }
    }

    double plainCost = 0.0;
    for (const auto& s : plain) plainCost += s.predictedCostMs;
    SchedulerSettings settings = unlimited();
    settings.budgetMs = plainCost;  // fits the plain crowd exactly, not the one with the mesh's cost
    const auto cheap = schedule(settings, requests), tight = schedule(settings, requests, meshCosts);
    double cost = 0.0, cheapError = 0.0, tightError = 0.0;
    for (std::size_t i = 0; i < requests.size(); ++i) {
        cost += tight[i].predictedCostMs;
        cheapError += cheap[i].predictedErrorPx;
        tightError += tight[i].predictedErrorPx;
    }
    EXPECT_LE(cost, settings.budgetMs * (1 + 1e-12));
    EXPECT_GT(tightError, cheapError) << "the mesh's cost is paid for with accuracy elsewhere";

}

/// fiveLevels with measured errors (an error table's) instead of the formula's: error per radius
/// at 1 m/s and 3 m/s, the faster motion twice as wrong.
GarmentProfile measuredFiveLevels() {
    GarmentProfile profile = fiveLevels();
    for (int l = 0; l < 5; ++l) {
        LevelProfile& level = profile.levels[l];
        level.errorMetres = 0.0;
        level.errorPerRadius[0] = 0.002 * (5 - l);
        level.errorPerRadius[1] = 2.0 * level.errorPerRadius[0];
        level.errorSpeeds[0] = 1.0;
        level.errorSpeeds[1] = 3.0;
    }
    return profile;
}

TEST(CrowdScheduler, PredictsMeasuredErrorsInProportionToTheGarmentsSizeAndSpeed) {
    const GarmentProfile profile = measuredFiveLevels();
    SchedulerSettings settings = unlimited();
    settings.typicalAcceleration = 0.0;  // no update lag: the level's error alone
    settings.maxUpdateInterval = 1;
    settings.pixelTolerance = 1e-9;      // every garment at the finest level
    // Below the slower speed, at it, halfway, at and beyond the faster one (held).
    const double speeds[] = {0.0, 1.0, 2.0, 3.0, 9.0};
    const double perRadius[] = {0.002, 0.002, 0.003, 0.004, 0.004};
    for (int k = 0; k < 5; ++k)
        for (double radius : {0.5, 1.0}) {
            GarmentRequest r = garmentAt(1, 10.0, speeds[k]);
            r.radius = radius;
            const double pixelsPerMetre = projectSphere(cameraAtOrigin(), r.center, radius).pixelsPerMetre;
            const auto out = schedule(settings, {r}, profile);
            ASSERT_EQ(out[0].level, 4);
            EXPECT_NEAR(out[0].predictedErrorPx, perRadius[k] * radius * pixelsPerMetre, 1e-9 * pixelsPerMetre)
                << "speed " << speeds[k] << " radius " << radius;
        }
}

TEST(CrowdScheduler, KeepsGarmentsWithinTheToleranceByMeasuredErrorsAndDegradesByThem) {
    std::vector<GarmentRequest> requests;
    requests.reserve(40);
    for (int i = 0; i < 40; ++i) requests.push_back(garmentAt(i, 2.0 + 3.0 * i, i % 3 == 0 ? 3.0 : 1.0));
    const GarmentProfile profile = measuredFiveLevels();
    const auto free = schedule(unlimited(), requests, profile);
    for (std::size_t i = 0; i < free.size(); ++i) {
        // Within the tolerance wherever some level is: the finest one's error is 0.002 (0.004 fast) x radius.
        const GarmentRequest& r = requests[i];
        const double radiusPx = r.radius * projectSphere(cameraAtOrigin(), r.center, r.radius).pixelsPerMetre;
        const double finestPx = radiusPx * (r.speed > 2.0 ? 0.004 : 0.002);
        if (finestPx <= 1.0) {
            EXPECT_LE(free[i].predictedErrorPx, 1.0) << "garment " << i;
        }
        // The coarsest such level: one coarser would leave the tolerance (or the garment is at level 0).
        if (free[i].level > 0 && finestPx <= 1.0) {
            const double coarserPx = finestPx * (5 - (free[i].level - 1));
            EXPECT_GT(coarserPx, 1.0 * (1.0 - 1e-12)) << "garment " << i;
        }
    }
    // Over budget: the garment whose measured error grows least per millisecond saved goes first,
    // so of two twins at the finest level the slow one gives its level up, the fast one (measured
    // twice as wrong) keeps it.
    SchedulerSettings settings = unlimited();
    settings.pixelTolerance = 1e-9;
    settings.maxUpdateInterval = 1;
    const std::vector<GarmentRequest> twins = {garmentAt(1, 4.0, 1.0), garmentAt(2, 4.0, 3.0)};
    const auto both = schedule(settings, twins, profile);
    ASSERT_EQ(both[0].level, 4);
    ASSERT_EQ(both[1].level, 4);
    settings.budgetMs = 0.9 * (both[0].predictedCostMs + both[1].predictedCostMs);
    const auto tight = schedule(settings, twins, profile);
    EXPECT_LE(tight[0].predictedCostMs + tight[1].predictedCostMs, settings.budgetMs * (1 + 1e-12));
    EXPECT_LT(tight[0].level, 4) << "the slow garment gives up its level";
    EXPECT_EQ(tight[1].level, 4) << "the fast one keeps it";
}

TEST(CrowdScheduler, WhereNoLevelMeetsTheToleranceTakesTheCoarsestWithTheLeastError) {
    // Measured errors that level off: levels 2-4 alike (a table's pooled block), all above 1 px.
    GarmentProfile profile = measuredFiveLevels();
    const double perRadius[5] = {0.04, 0.03, 0.02, 0.02, 0.02};
    for (int l = 0; l < 5; ++l) profile.levels[l].errorPerRadius[0] = profile.levels[l].errorPerRadius[1] = perRadius[l];
    const auto out = schedule(unlimited(), {garmentAt(1, 3.0)}, profile);
    EXPECT_GT(out[0].predictedErrorPx, 1.0);
    EXPECT_EQ(out[0].level, 2) << "levels 3 and 4 cost more for nothing measured";
    // Coming from the finest level, it moves there too (no hysteresis holds a level that buys nothing).
    GarmentRequest was = garmentAt(1, 3.0);
    was.previous = out[0];
    was.previous.level = 4;
    EXPECT_EQ(schedule(unlimited(), {was}, profile)[0].level, 2);
    // The formula's finest level errs nothing: a near garment still gets it.
    EXPECT_EQ(schedule(unlimited(), {garmentAt(1, 1.0)})[0].level, 4);
}

TEST(CrowdScheduler, RejectsBadInputNamingIt) {
    const SchedulerCamera camera = cameraAtOrigin();
    const GarmentProfile profile = fiveLevels();
    auto run = [&](const std::vector<GarmentRequest>& requests, const SchedulerSettings& settings = {},
                   const GarmentProfile& p = fiveLevels()) {
        std::vector<GarmentSchedule> out(requests.size());
        return scheduleGarments(settings, Span<const SchedulerCamera>(&camera, 1),
                                Span<const GarmentProfile>(&p, 1), requests, out);
    };
    Status s = run({garmentAt(5, 1.0), garmentAt(5, 2.0)});
    EXPECT_NE(s.message().find("garment id 5 appears twice"), std::string::npos) << s.message();
    GarmentRequest nan = garmentAt(6, 1.0);
    nan.center.x() = std::nan("");
    s = run({nan});
    EXPECT_NE(s.message().find("garment 6: center"), std::string::npos) << s.message();
    GarmentRequest badProfile = garmentAt(7, 1.0);
    badProfile.profile = 3;
    EXPECT_NE(run({badProfile}).message().find("profile 3 out of range"), std::string::npos);
    SchedulerSettings settings;
    settings.maxUpdateInterval = 3;
    EXPECT_NE(run({garmentAt(1, 1.0)}, settings).message().find("maxUpdateInterval"), std::string::npos);
    GarmentProfile noSolver = fiveLevels();
    noSolver.levels[2].costMs[0] = noSolver.levels[2].costMs[1] = 0.0;
    EXPECT_NE(run({garmentAt(1, 1.0)}, {}, noSolver).message().find("profile 0 level 2 offers no solver"),
              std::string::npos);
    GarmentProfile negative = fiveLevels();
    negative.levels[1].collisionCostMs[int(CollisionDetail::Mesh)] = -1.0;
    EXPECT_NE(run({garmentAt(1, 1.0)}, {}, negative).message().find("profile 0 level 1: collisionCostMs"),
              std::string::npos);
    GarmentProfile measured = measuredFiveLevels();
    measured.levels[3].errorPerRadius[1] = std::nan("");
    EXPECT_NE(run({garmentAt(1, 1.0)}, {}, measured).message().find("profile 0 level 3: errorPerRadius"),
              std::string::npos);
    measured = measuredFiveLevels();
    measured.levels[0].errorSpeeds[1] = measured.levels[0].errorSpeeds[0];
    EXPECT_NE(run({garmentAt(1, 1.0)}, {}, measured).message().find("profile 0 level 0: errorSpeeds"),
              std::string::npos);
}

} // namespace
} // namespace cc::lod
