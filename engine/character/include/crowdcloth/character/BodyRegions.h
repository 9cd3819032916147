#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/character/Character.h"

namespace cc {

/// The part of a humanoid a joint or a skin vertex belongs to. Garments attach to Torso and Neck
/// skin only: a cape bound to an arm is torn along its top edge when the arm swings.
enum class BodyRegion : uint8_t { Torso, Neck, Head, LeftArm, RightArm, LeftLeg, RightLeg };

inline bool isArm(BodyRegion r) { return r == BodyRegion::LeftArm || r == BodyRegion::RightArm; }
inline bool isLeg(BodyRegion r) { return r == BodyRegion::LeftLeg || r == BodyRegion::RightLeg; }
const char* regionName(BodyRegion region);

/// Which region every joint and body vertex belongs to, the joints garments are measured from,
/// and the body's facing (Y up), found on the body in its rest pose.
///
///     Result<BodyRegions> r = findBodyRegions(character, restPositions);
///     if (r.isOk() && r.value().vertices[v] == BodyRegion::Torso) ...
struct BodyRegions {
    std::vector<BodyRegion> joints;    ///< per skeleton joint (empty for a body without one)
    std::vector<BodyRegion> vertices;  ///< per body vertex: the region with most of its skin weight
    std::vector<double> anchorWeight;  ///< per body vertex: how surely it is torso or neck skin, [0, 1]
                                       ///< (its skin weight on Torso and Neck joints; from geometry,
                                       ///< 1 falling to 0 towards the shoulder joints)
    int32_t hips = -1;                 ///< joint where the legs branch off (-1 = not found)
    int32_t chest = -1;                ///< joint where the arms branch off
    int32_t neck = -1;                 ///< first neck joint (-1 = the rig has none)
    int32_t head = -1;                 ///< root joint of the head
    std::array<int32_t, 2> upperArm{-1, -1};  ///< [left, right] first arm joint past the clavicle
    std::array<int32_t, 2> thigh{-1, -1};     ///< [left, right] first leg joint
    Vec3 left = Vec3::UnitX();         ///< unit: the character's left (bind space, horizontal)
    Vec3 forward = Vec3::UnitZ();      ///< unit: where the character faces (= left x up)
    std::string method;                ///< how they were found: "joint names", "skeleton structure", "geometry"
};

/// Regions of a skinned humanoid from its skeleton: joint names first (Mixamo, Unreal, Unity and
/// VRM humanoids, Blender Rigify, 3ds Max Biped, glTF exporters' "arm_joint_L" style), then the
/// skeleton's branching (legs branch at the hips, arms at the chest, the head tops the spine) when
/// the names do not describe a humanoid. Either way the result is checked against the geometry
/// (head above the torso, legs below it, one leg on each side). Vertex regions follow the skin
/// weights. `restPositions` is the body skinned at the skeleton's rest pose (a file's bind pose
/// need not be one coherent body: rigid parts may sit at their rest place and skinned parts at
/// their bind place). Fails naming what it could not find (no legs, no head, ...): such a body
/// is not a humanoid garments can be fitted to.
Result<BodyRegions> findBodyRegions(const Character& character, Span<const Vec3> restPositions);

/// Regions of a body mesh from its geometry alone (no skeleton: a host-skinned body), by slicing
/// it horizontally: the torso is the cross-section that splits into two legs at the crotch, arms
/// are the cross-sections beside it, the neck the narrowest section above the shoulders, the head
/// what lies above. The mesh must stand in a rest pose (Y up, arms not touching the torso below the
/// armpits). Joint fields stay -1.
Result<BodyRegions> findBodyRegionsFromGeometry(const SkinnedMesh& mesh);

} // namespace cc
