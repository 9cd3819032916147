#pragma once

#include <vector>

#include "crowdcloth/character/Mannequin.h"

namespace cc {

/// Collision capsules for any skinned body: one per joint that carries at least `minVertices`
/// vertices (by largest weight), along the main axis of those vertices, with their median distance
/// from the axis as radius and caps reaching the farthest of them. `restPositions` and
/// `restSkinMatrices` are the body and its skin matrices in the rest pose; the capsules are
/// expressed in bind space (BodyCapsule's convention), so the posed capsule is skin[joint] * a.
std::vector<BodyCapsule> fitBodyCapsules(const Character& character, Span<const Vec3> restPositions,
                                         Span<const Mat4> restSkinMatrices, std::size_t minVertices = 8);

} // namespace cc
