// Contact planes for the solve reach as far as each vertex's motion over the update
// (GarmentUpdateContext::contactLookahead): cloth thrown at the body meets the body inside the
// solve, where its neighbours respond, rather than being pushed out after it, where the strain
// limit cannot follow a pushed vertex.
#include <algorithm>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "CookedAsset.h"
#include "GarmentFit.h"
#include "GarmentInstance.h"
#include "crowdcloth/collision/BodyTopology.h"
#include "crowdcloth/collision/CollisionDevice.h"

namespace cc::detail {
namespace {

struct Update {
    uint32_t planes = 0;       ///< contact planes the solve had
    uint32_t corrections = 0;  ///< vertices the body pushed out after the solve
    double deepestPush = 0.0;  ///< [m] the farthest the body moved a vertex after the solve
    double totalPush = 0.0;    ///< [m] summed over the vertices
    double strain = 0.0;       ///< largest edge strain after the update
    double thickness = 0.0;    ///< [m] the garment's
};

/// One 1/60 s update of a cape on the standing mannequin, every free vertex thrown at the body's
/// vertical axis at `speed` (a cape's hem swinging onto the back in a stride), the solver as the
/// World runs the finest level.
Update throwCapeAtBody(double lookahead, double speed) {
    const auto body = std::make_shared<const BodyAsset>(makeMannequinBody({}).value());
    CharacterInstance character;
    character.body = body;
    character.pose = CharacterPose(body->mannequin.character);
    character.bodyTopology = collision::BodyTopology::build(body->mesh().triangles, body->mesh().bindPositions).value();
    EXPECT_TRUE(character.updatePose().isOk());
    ClothAssetDesc desc;
    desc.kind = GarmentKind::Cape;
    const auto asset = std::make_shared<const CookedAsset>(cookFittedGarment(desc, *body).value());
    auto garment = GarmentInstance::create(asset, 1, character, CharacterId{1, 1}, {}).value();
    GarmentInstance& g = *garment;
    EXPECT_TRUE(g.switchLevel(int(asset->levels.size()) - 1));

    const double dt = 1.0 / 60.0;
    auto device = collision::CollisionDevice::create({}).value();
    const auto collider = character.meshColliderAt(*device, 0.0, dt);
    EXPECT_TRUE(collider.isOk()) << collider.status().message();
    g.context.dt = dt;
    g.context.collider = collider.value();
    g.context.continuous = true;
    g.context.contactLookahead = lookahead;

    cloth::SubstepLane lane = g.lane();
    for (std::size_t v = 0; v < lane.positions.size(); ++v) {
        const Vec3& x = lane.positions[v];
        const Vec3 toAxis(-x.x(), 0.0, -x.z());  // welded copies share a position, so a velocity
        lane.velocities[v] = speed * toAxis.normalized();
    }

    Update out;
    GarmentUpdateReport report;
    UpdateScratch scratch;
    EXPECT_TRUE(g.prepare(character, scratch, report).isOk());
    out.planes = report.contacts;
    cloth::SubstepSettings settings;
    settings.strainLimit = 0.1;
    settings.contactThickness = desc.thickness;
    settings.friction = cloth::Friction{desc.friction, 0.8 * desc.friction};
    const cloth::ClothLevel& level = *g.cookedLevel().cloth;
    const auto factor = level.buildFactor(dt / settings.substeps).value();
    cloth::SubstepWorkspace workspace;
    cloth::SubstepLaneReport laneReport;
    lane = g.lane();
    EXPECT_TRUE(cloth::stepSubsteps(level, *factor, dt, settings, Span<const cloth::SubstepLane>(&lane, 1), workspace,
                                    Span<cloth::SubstepLaneReport>(&laneReport, 1))
                    .isOk());
    EXPECT_TRUE(laneReport.status.isOk()) << laneReport.status.message();
    const std::vector<Vec3> solved(lane.positions.begin(), lane.positions.end());
    EXPECT_TRUE(g.finish(character, settings, scratch, report).isOk());
    lane = g.lane();
    for (std::size_t v = 0; v < solved.size(); ++v) {
        const double push = (lane.positions[v] - solved[v]).norm();
        out.deepestPush = std::max(out.deepestPush, push);
        out.totalPush += push;
    }
    out.corrections = report.bodyCorrections;
    out.strain = g.maxEdgeStrain();
    out.thickness = desc.thickness;
    return out;
}

TEST(ContactLookahead, ClothThrownAtTheBodyMeetsItInsideTheSolve) {
    for (double speed : {2.0, 4.0}) {
        SCOPED_TRACE(::testing::Message() << speed << " m/s");
        const Update near = throwCapeAtBody(0.0, speed);
        const Update ahead = throwCapeAtBody(2.0, speed);
        std::printf("thrown at %.1f m/s: planes %u -> %u, vertices pushed after the solve %u -> %u, by up to %.1f -> "
                    "%.1f mm (%.0f -> %.0f mm in all), max strain %.1f %% -> %.1f %%\n",
                    speed, near.planes, ahead.planes, near.corrections, ahead.corrections, 1e3 * near.deepestPush,
                    1e3 * ahead.deepestPush, 1e3 * near.totalPush, 1e3 * ahead.totalPush, 100.0 * near.strain,
                    100.0 * ahead.strain);
        // Without the lookahead the body's corrections after the solve do the work, centimetres of
        // it (the case is meaningful); with it the solve does, and what is left after it is a
        // top-up to the thickness. The strain limit holds either way here (no two pushes pinch an
        // edge).
        const double thickness = near.thickness;
        EXPECT_GT(near.deepestPush, thickness);
        EXPECT_GT(ahead.planes, near.planes);
        EXPECT_LT(ahead.deepestPush, 0.1 * thickness);
        EXPECT_LT(ahead.totalPush, 0.05 * near.totalPush);
        EXPECT_LE(ahead.strain, 0.1 * 1.01);
    }
}

} // namespace
} // namespace cc::detail
