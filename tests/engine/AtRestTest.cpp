// Garments on a character standing still come to rest and stay there: after they settle, no vertex
// keeps moving from frame to frame (a shimmer) or creeps away (a drift), nothing turns non-finite
// and no update fails.
//
// DISABLED: not met on main. Measured (2026-12-05, finest level, the assets' defaults, a close
// camera), over 10 s after 20 s of settling, largest move of a vertex in one frame / from the start
// of the 10 s to their end: straight cape 6.4 / 71 mm (it still swings: velocityDamping defaults
// to 0), circle skirt 11.8 / 133, A-line dress 21.8 / 191, poncho 12.8 / 98 mm; 1 px at 2 m is
// ~2 mm. With compressionStiffness 1 instead of the default 0.1: 4.4 / 51, 11.5 / 19, 3.9 / 6.4,
// 10.6 / 33 (folds that cost little to compress keep moving). What keeps them moving: the circle
// skirt's motion lives in the solve itself (the corrections after it change nothing), its hem
// swirling at 0.5 m/s where it meets the hands (rms 0.14 m/s over its vertices); air damping does
// not stop it (velocityDamping 2/s: 1.5 m/s, 61 mm a frame), nor does implicit bending in Newton's
// system (57 mm), inelastic velocities in the strain limit (37 mm) or contact planes that hold only
// within 2-5 cm of their contact point (18-21 mm: a plane is a half-space, so a vertex sliding past
// a hand could be pushed where the hand is not; that is not what drives it). The body's contacts
// do drive it: with none, circle skirt 3.2 mm a frame, dress 0.8, poncho 2.5 (the cape, 8.4, swings
// undamped); friction is not it (35.6 mm without). Earlier, before
// the placement relaxation: cape 4.1 / 71, circle skirt 2.4 / 2.0 (flung up round the torso and
// held there), dress 5.5 / 6.8, poncho 1.7 / 3.3. ClothAssetDesc::damping (Rayleigh) does not reach
// the substep solver.
//
// 2026-12-06, the mean RMS move a frame over the 10 s beside the largest (the largest is one
// vertex's worst frame and jumps between runs: the motion is chaotic, one-run comparisons of it
// mislead): cape 0.54, circle skirt 1.4-4.5, dress 2.6-3.2, poncho 1.8 mm. Seen in cc_dress frames:
// the circle skirt on the standing mannequin billows out and flaps as in wind, at 2/s of air
// damping too. With no body at all and 2/s of air damping, skirt, dress and poncho come to rest
// (0.05-1.2 mm a frame, largest); the cape keeps moving 2.1 mm a frame until its bending joins
// Newton's system (0.36 mm; explicit bending feeds it), then creeps at one corner at ~2 cm/s
// (soft compression). So the body's contacts pump, and the pump is in the solve's planes: with
// only them (the corrections after the solve off), every pushed vertex's velocity set to its
// surface's, no look-ahead, bending implicit, 40 iterations or no strain limit, skirt and dress
// still move 0.8-2.5 mm RMS a frame; 16 substeps instead of 4 make it worse (dress 13.6 mm), and a
// fastest vertex's velocity at the update's end (~4 m/s) is far above its motion over the frame
// (~1.5 m/s): something in the substep loop oscillates at the substep's rate. Not it: the body's
// surface velocity (0), vertices inside the body (none), the attachments (still), pinched vertices
// (opposing planes: few; holding them did not help), the warm start. The corrections after the
// solve push 35-90 vertices back out every frame of a still body. Traced per substep (dress): each
// Newton step raises the kinetic energy 4x (3e-3 -> 1.3e-2 J, a vertex at 5-6 m/s into the body)
// and the push onto the planes takes most of it back: the solve drags contact vertices into the
// body and the push stretches the cloth back out, elastic energy the next solve releases. Holding
// such vertices on their planes inside the solve (Baraff & Witkin 1998's filtered CG; branch
// contacts-in-solve) cut that gain to 1.1x and the poncho's motion to 0.22 mm RMS, but not the
// skirt's or the dress's, and moved five other tests' figures: not landed.
//
// 2026-12-06, stop 39: the solver's kind decides it. Local/global iterations instead of Newton's
// step (4 substeps x 4 iterations, all else equal): dress 0.015 mm RMS a frame, poncho 0.06, cape
// 0.18, circle skirt 0.85 (Newton: 2.6, 1.8, 0.54, 1.4); at 1 or 40 local/global iterations still
// calm, while Newton with 1 or 40 CG iterations, without the warm start, with a backtracking line
// search on the step's energy (it never shortened a step), or with the contact planes' normal
// stiffness added to its system keeps moving; a Hessian stiffer along compressed springs helps
// part of the way (dress 0.46). Local/global's system is stiff across every spring, Newton's only
// as stiff as tension makes it: the pushes feed floppy modes Newton leaves undamped. Rayleigh
// stiffness damping (ClothAssetDesc::damping, which the substep solver now reads) takes that energy
// out: StiffnessDampingSettlesWhatTheContactsKeepMoving. It stays 0 by default: at 0.01 s the cape
// on the walking mannequin meets the body's pushes after the strain limit harder (largest strain
// 16-65 % over four runs at 0.0099-0.0102 s against 9-19 % at 0-1e-5 s in GarmentOnBody), and
// the centrifugal cape hangs 11.1-11.7 degrees steeper than the closed form, past the Inertia test.
//
// 2026-12-06, stop 41: damping 0.01 s with the air's velocityDamping as well (the plaza's 0.4/s is
// near the first row), largest move of a vertex over 5 s after 20 s, velocityDamping 0.5 / 2 per s:
// circle skirt 1.6 / 4.6 mm, dress 1.4 / 1.4, poncho 2.8 / 0.8 (at rest, under a pixel at 2 m),
// cape 67 / 35 mm; the cape still moves 10-13 mm in 5 s after 40 and 80 s of settling (1/s): it
// does not settle, one corner creeping. Damping only along each spring (a frame-invariant
// Rayleigh term, tension's across-stiffness left out) passes the Inertia test at 0.01 s but
// settles less (dress 1.04 mm RMS a frame instead of 0.08): not landed.
//
// 2026-12-07, stop 43, self-collision on (WorldDesc::selfCollision), 0.01 s: cape 0.19, circle
// skirt 0.19, dress 0.08 mm RMS a frame, poncho 0.45-0.82 over three runs at 0.99 / 1 / 1.01 of its
// thickness (0.05 without): a free flap of its hem swings at ~1.25 Hz over 3-9 cm, bouncing off the
// layer under it, and velocityDamping 0.4-1 /s does not stop it (it is pumped, not left over).
// Kinetic energy at each phase of an update, mean over the last 5 s: start 866 uJ, after the solve
// 1755, after the body's corrections 811, after self-collision's resolve 867 (without it 184 / 289
// / 184 / 184: there the solve's gain is velocity into the body that the corrections cancel).
// Measured and not landed: the resolve's impulses applied to the velocities from their own
// approach instead of as the correction over the step (the resolve then only takes energy out, but
// the poncho still moves 0.53 mm and the walking circle skirt's self-collision costs 1.45x); the
// strain limit after the corrections moving positions only and taking out stretching velocity
// (inelastic): with self-collision all four 0.10-0.19 mm in one run, but without it the dress and
// circle skirt 0.65-0.71 mm instead of 0.08-0.19 and the walking cape past its strain (12.4 %), and
// applied after self-collision's resolve alone the poncho 0.45-1.10; static planes, no repulsion,
// or both: 0.04-1.38 mm over the runs, a lottery of where the folds land.
//
// 2026-12-07, stop 49: the default damping is now 7e-4 s (for the substeps' accuracy:
// SubstepAccuracyTest), too little to settle anything at rest: largest move in a frame / drift
// over 10 s / mean RMS a frame, cape 6.7 / 74 / 0.50, circle skirt 32.5 / 188 / 2.79, dress
// 23.5 / 76 / 3.12, poncho 20.7 / 206 / 1.63 mm.
//
// 2026-12-08, stop 50: the pump, located. At rest the skirt, dress and poncho end every update
// with edges at the strain limit (10.00 %; the cape 0.8 %): the solve ends at the limit, then the
// body's push after it stretches 17 % (circle skirt: a hem vertex on the hanging hand, 3 mm inside
// the thickness every update, against the same plane the solve had) or 92 % (dress: a vertex at the
// armpit with contacts of the arm and of the torso facing each other, the two surfaces overlapping
// by 5 mm, pushed 32 mm along the gap by the alternating pushes), and the strain limit pulls it
// back: every update again. Measured and not landed: such a vertex held midway between two facing
// surfaces closer than twice the thickness instead of pushed (the dress's push 92 -> 32 %, its
// motion 3.1 -> 1.9 mm RMS a frame, the others unchanged; but the humanoid suite 471 -> 515 updates
// over the limit, 436 with the held vertex left to the strain limit, checks inside the body 79 ->
// 150-164); the solve's last pushed vertices held in its own strain limit (no change). Damping does
// not stop it (0.01-0.03 s with 0-20 /s of air damping: drift over 10 s 0.4-125 mm, a lottery of
// slips: the dress once 28 mm in one frame at the armpit).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

struct Garment {
    const char* name;
    GarmentKind kind;
    GarmentCut cut;
};

class AtRest : public ::testing::TestWithParam<Garment> {};

std::vector<Vec3> positionsOf(const RenderMeshView& mesh) {
    std::vector<Vec3> out(mesh.vertexCount);
    for (uint32_t v = 0; v < mesh.vertexCount; ++v)
        out[v] = Vec3(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    return out;
}

double largestMove(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
    double most = 0.0;
    for (std::size_t v = 0; v < from.size(); ++v) most = std::max(most, (to[v] - from[v]).norm());
    return most;
}

/// How a garment moves on the still mannequin once settled: `settle` seconds, then `measure`.
struct RestMotion {
    int updates = 0;
    double fastest = 0.0;  ///< [m] largest move of a vertex in one frame while measuring
    double drift = 0.0;    ///< [m] largest move from the start of the measurement to its end
    double meanRms = 0.0;  ///< [m] mean over the frames of the RMS move of the vertices
};

RestMotion motionAtRest(const Garment& g, double damping, int settle, int measure) {
    RestMotion out;
    WorldDesc desc;
    desc.fixedCostModel = true;
    WorldPtr world(World::create(desc).value());
    ClothAssetDesc asset;
    asset.kind = g.kind;
    asset.cut = g.cut;
    asset.damping = damping;
    const AssetId cloth = world->addClothAsset(asset).value();
    CharacterDesc c;
    c.body = world->addMannequinBody({}).value();
    c.clip = "";  // standing still in the rest pose
    const CharacterId still = world->addCharacter(c).value();
    const GarmentId garment = world->addGarment(cloth, still, {}).value();
    EXPECT_TRUE(world->setGarmentLevel(garment, int32_t(asset.levelCount) - 1).isOk());
    // Watched from close by, so the garment stays awake and updates every frame.
    const CameraDesc camera = test::cameraLookingAt(Vec3(0.8, 1.2, -1.6), Vec3(0, 1.0, 0));
    EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
    const double dt = 1.0 / 60;
    std::vector<Vec3> previous, settled;
    for (int f = 0; f < 60 * (settle + measure); ++f) {
        if (!world->step(dt).isOk()) {
            ADD_FAILURE() << g.name << ": frame " << f;
            return out;
        }
        const GarmentStats stats = world->garmentStats(garment).value();
        EXPECT_FALSE(stats.failed);
        out.updates += stats.updated;
        std::vector<Vec3> now = positionsOf(world->renderMesh(garment).value());
        for (const Vec3& p : now) EXPECT_TRUE(isFinite(p));
        if (f == 60 * settle) settled = now;
        if (f > 60 * settle) {
            out.fastest = std::max(out.fastest, largestMove(previous, now));
            double sq = 0.0;
            for (std::size_t v = 0; v < now.size(); ++v) sq += (now[v] - previous[v]).squaredNorm();
            out.meanRms += std::sqrt(sq / double(now.size())) / (60.0 * measure);
        }
        previous = std::move(now);
    }
    out.drift = largestMove(settled, previous);
    std::printf("[ at rest: %s, damping %.3f s ] %d updates; over the last %d s: largest move in a frame %.3f mm, "
                "from their start to their end %.3f mm; mean rms move a frame %.4f mm\n",
                g.name, damping, out.updates, measure, 1e3 * out.fastest, 1e3 * out.drift, 1e3 * out.meanRms);
    return out;
}

TEST_P(AtRest, DISABLED_AGarmentOnAStillCharacterComesToRest) {
    const RestMotion m = motionAtRest(GetParam(), ClothAssetDesc{}.damping, 20, 10);
    EXPECT_GE(m.updates, 30 * 60 - 1) << "the garment must keep updating, not sleep";
    // A quarter of a pixel at 2 m (1080 lines, 60 degrees), where a garment runs its finest level.
    EXPECT_LT(m.fastest, 0.5e-3);
    EXPECT_LT(m.drift, 1e-3);
}

TEST_P(AtRest, StiffnessDampingSettlesWhatTheContactsKeepMoving) {
    // The contacts' pushes feed the fast stretch and shear modes; Rayleigh damping (0.01 s) takes
    // that energy out. Measured (2026-12-06, mean RMS move a frame over 5 s after 20 s, without ->
    // with): cape 0.57 -> 0.14 mm (its swing is not a stretch mode: velocityDamping damps it), circle
    // skirt 1.58 -> 0.19, dress 2.76 -> 0.08, poncho 1.64 -> 0.05 mm. The circle skirt needs the
    // 20 s: after 10 it still reads 1.0 mm.
    const RestMotion undamped = motionAtRest(GetParam(), 0.0, 20, 5);
    const RestMotion damped = motionAtRest(GetParam(), 0.01, 20, 5);
    const bool swings = GetParam().kind == GarmentKind::Cape;
    EXPECT_LT(damped.meanRms, (swings ? 0.6 : 0.25) * undamped.meanRms);
    EXPECT_LT(damped.meanRms, 0.35e-3);
}

INSTANTIATE_TEST_SUITE_P(Garments, AtRest,
                         ::testing::Values(Garment{"cape", GarmentKind::Cape, GarmentCut::Straight},
                                           Garment{"circle_skirt", GarmentKind::Skirt, GarmentCut::Circle},
                                           Garment{"dress", GarmentKind::Dress, GarmentCut::ALine},
                                           Garment{"poncho", GarmentKind::Poncho, GarmentCut::Straight}),
                         [](const ::testing::TestParamInfo<Garment>& param) { return std::string(param.param.name); });

} // namespace
} // namespace cc
