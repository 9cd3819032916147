#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "BodyAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/character/Character.h"

namespace cc::detail {

/// One animated character: its root in the world, its clip, and the pose buffers its garments
/// read. Garments simulate in this character's root frame (local space, as engines run skinned
/// cloth), so walking moves them without moving their simulation.
struct CharacterInstance {
    std::shared_ptr<const BodyAsset> body;
    int clip = -1;                  ///< -1 = rest pose
    double clipTime = 0.0;          ///< [s]
    double playbackRate = 1.0;      ///< [-]
    Vec3 position = Vec3::Zero();   ///< [m] root
    double yaw = 0.0;               ///< [rad] about +Y
    Vec3 previousPosition = Vec3::Zero();
    double speed = 0.0;             ///< [m/s] root speed over the last frame
    CharacterPose pose;             ///< skin matrices at clipTime (character space)
    bool poseCurrent = false;       ///< pose evaluated this frame
    std::vector<Vec3> skinnedPositions;  ///< character space; valid when skinnedCurrent
    bool skinnedCurrent = false;
    bool hostVerticesGiven = false; ///< host-skinned: setCharacterSkinnedVertices() this frame
    std::vector<GarmentId> garments;
    std::vector<float> drawPositions, drawNormals;  ///< characterMesh() buffers (world space)
    std::vector<uint32_t> drawIndices;

    /// Root transform (character space -> world).
    Mat3 rotation() const { return Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix(); }
    Vec3 toWorld(const Vec3& local) const { return rotation() * local + position; }

    /// Evaluates the pose for this frame (once; safe to call from the tasks of several garments of
    /// this character at once: the first evaluates, the others wait and read).
    Status updatePose();
    /// Skins the body mesh (once per frame, thread-safe as updatePose; host-skinned bodies already
    /// hold their vertices).
    Status updateSkin();

private:
    Status updatePoseLocked();
    std::mutex mMutex;
    Status mPoseStatus;
};

} // namespace cc::detail
