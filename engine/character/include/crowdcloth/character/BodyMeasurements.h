#pragma once

#include <vector>

#include "crowdcloth/character/BodyRegions.h"

namespace cc {

/// A horizontal cross-section of the body where a garment meets it, measured the way a tailor's
/// tape does: around the convex hull of the section.
struct BodyRing {
    double height = 0.0;          ///< [m] y of the section
    Vec3 centre = Vec3::Zero();   ///< [m] centre of the section's extent along left and forward
    double girth = 0.0;           ///< [m] hull perimeter
    double halfWidth = 0.0;       ///< [m] half the extent along the body's left axis
    double halfDepth = 0.0;       ///< [m] half the extent along its forward axis
    std::vector<Vec2> hull;       ///< the section's convex hull, (x, z), counter-clockwise
};

/// The landmarks garments are fitted to, measured on a humanoid standing in its rest pose (arms
/// relaxed, see relaxedArmsPose), Y up. Heights are absolute y values in the body's frame.
struct BodyMeasurements {
    Vec3 left = Vec3::UnitX();     ///< unit, horizontal: the character's left
    Vec3 forward = Vec3::UnitZ();  ///< unit, horizontal: where it faces
    double groundY = 0.0;          ///< [m] lowest point (soles)
    double topY = 0.0;             ///< [m] top of the head
    double height = 0.0;           ///< [m] topY - groundY
    double crotchY = 0.0;          ///< [m] where the legs part
    double shoulderY = 0.0;        ///< [m] height of the shoulder joints
    double shoulderWidth = 0.0;    ///< [m] outer shoulder to outer shoulder, along left
    Vec3 leftShoulder = Vec3::Zero();   ///< [m] top of the left shoulder at its outer edge
    Vec3 rightShoulder = Vec3::Zero();  ///< [m] same, right
    BodyRing neck;                 ///< where the neck meets the shoulders (a collar's line)
    BodyRing chest;                ///< under the arms
    BodyRing waist;                ///< the natural waist: narrowest torso section above the hips
    BodyRing hips;                 ///< widest section of hips and thighs
    double stride = 0.0;           ///< [rad] widest stride of the body's clips (widestClipStride);
                                   ///< 0 = none known
    std::string method;            ///< where the regions came from (BodyRegions::method)
};

/// Measures a humanoid. `positions` is the body in its rest pose (arms relaxed), `regions` its
/// regions, `jointPositions` the rest-pose joint positions (empty for a body without skeleton:
/// heights then come from the geometry alone). Every landmark is checked against the geometry (the
/// waist lies between hips and chest, the neck is narrower than the chest, ...); the error names
/// the landmark that could not be found.
Result<BodyMeasurements> measureBody(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                                     const BodyRegions& regions, Span<const Vec3> jointPositions);

/// A cross-section of chosen regions at height y [m] (convex hull, girth, extent); an empty ring
/// (girth 0) when nothing is cut there.
BodyRing measureRing(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                     const std::vector<uint8_t>& keepTriangle, double y, const Vec3& left, const Vec3& forward);

/// Triangles whose corners lie mostly (two of three) in one of `wanted` regions.
std::vector<uint8_t> trianglesOf(const std::vector<std::array<uint32_t, 3>>& triangles,
                                 const std::vector<BodyRegion>& vertexRegions, std::initializer_list<BodyRegion> wanted);

/// The rest pose with each upper arm lowered to hang `abduction` [rad] from vertical (in the plane
/// of the arm and the vertical) when the rest pose holds it higher than `threshold` [rad] from
/// vertical (T and A poses): garments are fitted around arms where a walk or an idle holds them.
/// Writes local transforms (outLocal.size() == joint count).
void relaxedArmsPose(const Character& character, const BodyRegions& regions, Span<const Vec3> restPositions,
                     double abduction, double threshold, Span<Transform> outLocal);

} // namespace cc
