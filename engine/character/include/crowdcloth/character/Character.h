#pragma once

#include <string>
#include <vector>

#include "crowdcloth/character/AnimationClip.h"
#include "crowdcloth/character/Skeleton.h"
#include "crowdcloth/character/SkinnedMesh.h"

namespace cc {

/// An animated body: skeleton, skinned body mesh and clips. Plain data, immutable once built and
/// shareable between any number of agents (per-agent state lives in CharacterPose).
struct Character {
    std::string name;
    Skeleton skeleton;
    SkinnedMesh body;
    std::vector<AnimationClip> clips;

    /// Validates skeleton, body (against the joint count) and every clip.
    Status validate() const;
    /// Index of the clip with that name, or -1.
    int findClip(const std::string& clipName) const;
};

/// Re-expresses a character in other units and axes: every model-space point p becomes
/// scale * rotation * p. Joint transforms and clip keys are conjugated (T -> C T C^-1 with
/// C = scale * rotation), bind positions and inverse bind matrices mapped alike, so every skinned
/// result is mapped the same way. `rotation` must be orthonormal with determinant +1; joints with
/// non-uniform scale keep exact results only when it permutes axes (as unit/axis fixes do).
Status changeBasis(Character& character, double scale, const Mat3& rotation);

/// Per-agent pose buffers: local pose, global joint matrices and skin matrices. Sized once by
/// the constructor; evaluate() then makes no allocation. Not thread-safe; one per agent/thread.
///
///     CharacterPose pose(character);
///     pose.evaluate(character, character.findClip("walk"), t, ClipWrap::Loop);
///     skinVertices(character.body, pose.skinMatrices(), positions, normals);
class CharacterPose {
public:
    CharacterPose() = default;
    explicit CharacterPose(const Character& character);

    /// Poses the skeleton with clip `clipIndex` at `time` [s] (clipIndex -1 = rest pose) and
    /// computes the global and skin matrices. The character must be the one this pose was sized
    /// for; a clip index outside [-1, clips.size()) gives an error.
    Status evaluate(const Character& character, int clipIndex, double time, ClipWrap wrap);
    /// Computes global and skin matrices from a local pose the caller wrote into localPose().
    void update(const Character& character);

    Span<Transform> localPose() { return mLocal; }
    Span<const Mat4> globalTransforms() const { return mGlobal; }
    Span<const Mat4> skinMatrices() const { return mSkin; }

private:
    std::vector<Transform> mLocal;
    std::vector<Mat4> mGlobal;
    std::vector<Mat4> mSkin;
};

} // namespace cc
