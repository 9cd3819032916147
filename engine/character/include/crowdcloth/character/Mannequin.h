#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/character/Character.h"

namespace cc {

/// Proportions of the procedural mannequin. Defaults give a 1.8 m adult; vary them per agent so
/// a crowd is not made of clones. Lengths scale with height except the widths given here.
struct MannequinParams {
    double height = 1.80;          ///< [m] floor to top of head in the bind pose; [1.0, 2.5]
    double shoulderWidth = 0.40;   ///< [m] outer shoulder to outer shoulder; [0.25, 0.6]
    double hipWidth = 0.34;        ///< [m] widest hip breadth; [0.22, 0.55]
    double waistWidth = 0.28;      ///< [m] waist breadth; [0.18, 0.5], < hipWidth + 0.1
    double limbGirth = 1.0;        ///< [-] scales arm and leg radii; [0.6, 1.6]
    double torsoDepth = 1.0;       ///< [-] scales front-to-back torso depth; [0.7, 1.5]
    double headSize = 1.0;         ///< [-] scales the head; [0.8, 1.2]
    double armAbduction = 0.26;    ///< [rad] bind-pose arm angle away from the body; [0.15, 0.8]
    double walkSpeed = 1.35;       ///< [m/s] walk clip's rootVelocity; [0.5, 2.5]
    double runSpeed = 4.6;         ///< [m/s] run clip's rootVelocity; [2, 7]
    double phase = 0.0;            ///< [-] fraction of a cycle every clip starts at; [0, 1)

    /// Names the first field outside its range.
    Status validate() const;
};

/// Joint indices of the mannequin's skeleton (left = +X; the mannequin faces +Z, Y up).
enum class MannequinJoint : int32_t {
    Hips, Spine, Chest, Neck, Head,
    LeftShoulder, LeftUpperArm, LeftForearm, LeftHand,
    RightShoulder, RightUpperArm, RightForearm, RightHand,
    LeftThigh, LeftShin, LeftFoot,
    RightThigh, RightShin, RightFoot,
    Count
};

/// One closed part of the body surface (a contiguous vertex and triangle range of the body).
struct BodyPart {
    std::string name;
    int32_t joint = -1;          ///< the joint that carries most of the part
    uint32_t firstVertex = 0, vertexCount = 0;
    uint32_t firstTriangle = 0, triangleCount = 0;
};

/// A collision proxy rigidly attached to a joint: the segment a-b swept by a sphere of `radius`.
/// a and b are bind-space points: the posed capsule is skin[joint] * a .. skin[joint] * b (for
/// joint-local end points use body.inverseBindMatrices[joint] * a). Fitted to the body part: the
/// radius is the median distance of the part's vertices from its axis, and the caps reach the
/// part's poles.
struct BodyCapsule {
    int32_t joint = -1;
    Vec3 a = Vec3::Zero();   ///< [m] bind space
    Vec3 b = Vec3::Zero();   ///< [m] bind space
    double radius = 0.0;     ///< [m]
};

/// Places in the bind pose that garments attach to (all in bind space, metres).
struct BodyLandmarks {
    int32_t waistJoint = -1;              ///< joint the waist ring follows
    Vec3 waistCentre = Vec3::Zero();      ///< centre of the waist cross-section
    double waistRadiusX = 0.0;            ///< [m] half-width of the waist (ellipse)
    double waistRadiusZ = 0.0;            ///< [m] half-depth of the waist (ellipse)
    int32_t hipJoint = -1;                ///< joint the hip ring follows
    Vec3 hipCentre = Vec3::Zero();        ///< centre of the widest hip cross-section
    double hipRadiusX = 0.0, hipRadiusZ = 0.0; ///< [m]
    Vec3 leftShoulder = Vec3::Zero();     ///< highest surface point above the left shoulder joint
    Vec3 rightShoulder = Vec3::Zero();    ///< same, right
    int32_t neckJoint = -1;
    Vec3 neckBase = Vec3::Zero();         ///< centre of the neck where it meets the torso
    double neckRadius = 0.0;              ///< [m]
};

/// The generated mannequin: a Character (skeleton, body, clips "idle", "walk", "run") plus the
/// body's part ranges, fitted capsules and landmarks. Y up, metres, facing +Z, soles on y = 0;
/// bind pose = rest pose (every joint rotation identity, arms lowered by armAbduction).
///
/// Clips are procedural gait cycles sampled at 40-48 keys per cycle, played in place: the last
/// key repeats the first (seamless loop) and `rootVelocity` (0, 0, walkSpeed or runSpeed) is the
/// locomotion a host adds. Periods: idle 4 s, walk 1.1 s and run 0.7 s (times sqrt(height/1.8)).
/// The thigh swing is set so the stance foot moves back at about the locomotion speed. Measured
/// world-space peak speeds at default parameters (MannequinTest): run hands 9.1 m/s, feet 11.9 m/s;
/// walk hands 2.8 m/s, feet 3.6 m/s.
///
/// Body surface: a union of closed parts (torso, neck, head, and per side upper arm, forearm,
/// hand, thigh, shin, foot), each a watertight, 2-manifold, outward-oriented (CCW from outside)
/// triangle mesh of sphere topology. Parts overlap at the joints, so a point is inside the body
/// iff the generalized winding number summed over all triangles is >= 0.5 (it is ~k inside k
/// overlapping parts).
struct Mannequin {
    Character character;
    std::vector<BodyPart> parts;
    std::vector<BodyCapsule> capsules;
    BodyLandmarks landmarks;
};

/// Builds the mannequin from parameters (deterministic; no file). About 5,000 triangles.
Result<Mannequin> buildMannequin(const MannequinParams& params = {});

/// Cycle length [s] of the generated clips for these parameters (idle, walk, run).
double mannequinIdlePeriod(const MannequinParams& params);
double mannequinWalkPeriod(const MannequinParams& params);
double mannequinRunPeriod(const MannequinParams& params);

} // namespace cc
