#pragma once

#include <array>
#include <string>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/character/BodyMeasurements.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/character/SkinBinding.h"
#include "crowdcloth/core/Math.h"

namespace cc::detail {

/// A body that characters share: a skinned character the World poses (the built-in mannequin or
/// an imported one: skeleton, clips, capsules) or a mesh the host skins itself and hands in each
/// frame; plus what garments are fitted to (regions, measurements) and bound to (torso skin).
struct BodyAsset {
    bool hostSkinned = false;
    Mannequin mannequin;  ///< the character with its capsules (parts and landmarks: the built-in
                          ///< mannequin only); for host-skinned bodies only character.body's
                          ///< bindPositions and triangles are set

    SkinnedMesh anchorMesh;  ///< what garments hang from: the torso and neck skin (a cape bound to
                             ///< a swinging arm would be torn along its top edge); all vertices,
                             ///< the torso's triangles

    /// Garments are fitted and bound in the rest pose: a file's bind-space mesh need not be one
    /// coherent shape (rigid parts at their rest place, skinned parts at their bind place).
    std::vector<Vec3> restPositions;  ///< [m] the body skinned at the rest pose
    std::vector<Mat4> restSkin;       ///< skin matrices of the rest pose (empty: host-skinned)
    std::vector<Vec3> fitPositions;   ///< [m] the rest pose with relaxed arms: what garments clear
    BodyRegions regions;              ///< valid when fitStatus is ok
    BodyMeasurements measurements;    ///< valid when fitStatus is ok
    Status fitStatus;                 ///< why no garment fits this body (not a humanoid), else ok
    uint64_t landmarkRevision = 0;    ///< bumped by setBodyLandmarks (fitted garments re-cook)

    const SkinnedMesh& mesh() const { return mannequin.character.body; }
    const Character& character() const { return mannequin.character; }
};

Result<BodyAsset> makeMannequinBody(const MannequinDesc& desc);
Result<BodyAsset> makeCharacterBody(const Character& character, const BodyDesc& desc);
Result<BodyAsset> makeHostSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                      const uint32_t* triangles, uint32_t triangleCount);

/// Replaces the body's measurements with a host's landmarks (girths left at 0 measured there).
Status applyLandmarks(BodyAsset& body, const BodyLandmarkDesc& landmarks);
/// The measurements as the public landmark struct.
BodyLandmarkDesc landmarksOf(const BodyAsset& body);

/// Binds garment positions given in the body's rest pose to its torso skin (see BodyAsset).
Result<SkinBinding> bindToBody(const BodyAsset& body, Span<const Vec3> restPositions, const SkinBindingSettings& settings);

/// The clip a character plays (-1 = rest pose) and its start time [s], from its desc: by index,
/// else by name (exact, then ignoring case). Errors name the clip and list the body's clips.
Status resolveClip(const BodyAsset& body, const CharacterDesc& desc, int& outClip, double& outClipTime);

/// Reads `count` xyz float triples `strideBytes` apart; fails naming the first non-finite vertex.
Status readFloat3(const float* data, uint32_t count, uint32_t strideBytes, const char* what,
                  std::vector<Vec3>& outPositions);

} // namespace cc::detail
