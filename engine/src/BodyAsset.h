#pragma once

#include <array>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/character/SkinBinding.h"
#include "crowdcloth/core/Math.h"

namespace cc::detail {

/// A body that characters share: a skinned mannequin (skeleton, clips, capsules, landmarks) or a
/// mesh the host skins itself and hands in each frame.
struct BodyAsset {
    bool hostSkinned = false;
    Mannequin mannequin;  ///< built-in bodies; for host-skinned ones only character.body's
                          ///< bindPositions and triangles are set

    SkinnedMesh anchorMesh;  ///< what garments hang from: the mannequin's torso and neck (a cape
                             ///< bound to a swinging arm would be torn along its top edge);
                             ///< a host-skinned body's whole mesh

    const SkinnedMesh& mesh() const { return mannequin.character.body; }
};

Result<BodyAsset> makeMannequinBody(const MannequinDesc& desc);
Result<BodyAsset> makeHostSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                      const uint32_t* triangles, uint32_t triangleCount);

/// Where a garment's asset space lands in the body's bind space: a translation that hangs the
/// cape behind the shoulders, the skirt round the waist, the dress and poncho from the shoulders.
Vec3 garmentPlacement(const BodyAsset& body, GarmentKind kind, double garmentWidth, double garmentLength,
                      double thickness);

/// Reads `count` xyz float triples `strideBytes` apart; fails naming the first non-finite vertex.
Status readFloat3(const float* data, uint32_t count, uint32_t strideBytes, const char* what,
                  std::vector<Vec3>& outPositions);

} // namespace cc::detail
