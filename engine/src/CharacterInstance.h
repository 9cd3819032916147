#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "BodyAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/character/Character.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/CapsuleCollider.h"

namespace cc::detail {

class SnapshotReader;
class SnapshotWriter;

/// [m] farthest a character may stand from the origin: float render meshes keep 1 m there.
constexpr double kMaxCoordinate = 1e7;
/// Clip seconds per world second a character may play at: [0, kMaxPlaybackRate].
constexpr double kMaxPlaybackRate = 10.0;

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
    double previousYaw = 0.0;
    double speed = 0.0;             ///< [m/s] root speed over the last frame
    Vec3 velocity = Vec3::Zero();   ///< [m/s] root velocity over the last frame (world axes); kept
                                    ///< through a teleport
    double yawRate = 0.0;           ///< [rad/s] heading's rate over the last frame; kept through a
                                    ///< teleport
    bool motionKnown = false;       ///< velocity and yawRate measured over a step (not the spawn's 0)
    CharacterPose pose;             ///< skin matrices at clipTime (character space)
    bool poseCurrent = false;       ///< pose evaluated this frame
    std::vector<Vec3> skinnedPositions;  ///< character space; valid when skinnedCurrent
    bool skinnedCurrent = false;
    bool hostVerticesGiven = false; ///< host-skinned: setCharacterSkinnedVertices() this frame
    std::vector<GarmentId> garments;
    std::vector<float> drawPositions, drawNormals;  ///< characterMesh() buffers (world space)
    std::vector<uint32_t> drawIndices;

    /// Colliders of the body in the character's frame, made on first need and moved to this
    /// frame's pose once per frame by whichever garment task asks first. The previous pose is
    /// the one of the last update, so a garment updated every n-th frame sweeps the body over its
    /// whole n-frame step.
    std::unique_ptr<collision::BodyCollider> meshCollider;
    collision::CapsuleCollider proxyCollider;
    bool proxyColliderMade = false;
    bool meshColliderBuildFailed = false;  ///< a deferred build failed: build when needed (errors surface)
    BodyId bodyId{};  ///< the body record whose spare colliders this character's collider returns to
    std::shared_ptr<const collision::BodyTopology> bodyTopology;  ///< the body's, shared by its colliders

    /// Root transform (character space -> world).
    Mat3 rotation() const { return Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix(); }
    Vec3 toWorld(const Vec3& local) const { return rotation() * local + position; }

    /// Evaluates the pose for this frame (once; safe to call from the tasks of several garments of
    /// this character at once: the first evaluates, the others wait and read).
    Status updatePose();
    /// Skins the body mesh (once per frame, thread-safe as updatePose; host-skinned bodies already
    /// hold their vertices).
    Status updateSkin();

    /// The body mesh collider at this frame's pose (skins the body first). Its motion (surface
    /// velocities, swept tests) is that since its last use when that was at most about `sweep`
    /// seconds ago (the asking garment's step); a collider last used longer ago is teleported to
    /// the pose, at rest: a body seen again after a while did not sweep through the cloth.
    Result<const collision::Collider*> meshColliderAt(collision::CollisionDevice& device, double time, double sweep);
    /// Capsules fitted to the skeleton at this frame's pose, with the same motion rule; host-skinned
    /// bodies have none and answer with their mesh.
    Result<const collision::Collider*> proxyColliderAt(collision::CollisionDevice& device, double time, double sweep);

    /// The capsules fitted to the skeleton at this frame's pose (posed first; host-skinned bodies
    /// have none: an error).
    Status posedCapsules(std::vector<collision::Capsule>& out);

    /// A mesh collider no garment asked for since `time - idle` seconds (or none): the World takes
    /// it back into its body's spares, so a crowd keeps as many as are near the camera.
    bool meshColliderIdle(double time, double idle) const;
    std::unique_ptr<collision::BodyCollider> takeMeshCollider();
    /// The mesh collider was built or reset at `time` (its garments' update times then hold a
    /// one-off, which the cost model must not learn).
    bool meshColliderRebuiltAt(double time) const { return mMeshColliderRebuilt == time; }
    /// A spare collider of the same body, moved to this character's pose on first use (a reset).
    void adoptMeshCollider(std::unique_ptr<collision::BodyCollider> collider);

    /// Snapshots (WorldSnapshot.cpp): what carries to the next frame (clocks, root motion, the
    /// host's last vertices, the colliders' last poses and times), after `body` and its ids are set.
    void saveState(SnapshotWriter& out) const;
    Status restoreState(SnapshotReader& in, collision::CollisionDevice& device);

private:
    Status updatePoseLocked();
    Status updateSkinLocked();
    void posedCapsulesLocked(std::vector<collision::Capsule>& out) const;
    std::mutex mMutex;
    Status mPoseStatus;
    double mMeshColliderTime = -1.0;
    double mMeshColliderRebuilt = -1.0;
    double mProxyColliderTime = -1.0;
    std::vector<collision::Capsule> mCapsules;
};

} // namespace cc::detail
