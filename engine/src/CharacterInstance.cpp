#include "CharacterInstance.h"

#include <limits>

namespace cc::detail {

Status CharacterInstance::updatePose() {
    std::lock_guard<std::mutex> lock(mMutex);
    return updatePoseLocked();
}

Status CharacterInstance::updatePoseLocked() {
    if (body->hostSkinned) return Status::ok();
    if (!poseCurrent) {
        poseCurrent = true;
        mPoseStatus = pose.evaluate(body->mannequin.character, clip, clipTime, ClipWrap::Loop);
    }
    return mPoseStatus;
}

Status CharacterInstance::updateSkin() {
    std::lock_guard<std::mutex> lock(mMutex);
    return updateSkinLocked();
}

Status CharacterInstance::updateSkinLocked() {
    if (skinnedCurrent) return Status::ok();
    if (body->hostSkinned) {
        if (!hostVerticesGiven)
            return Status::error(StatusCode::InvalidOperation,
                                 "host-skinned character: setCharacterSkinnedVertices() was not called before step()");
        skinnedCurrent = true;
        return Status::ok();
    }
    if (Status s = updatePoseLocked(); !s) return s;
    skinnedPositions.resize(body->mesh().vertexCount());
    skinnedCurrent = true;
    return skinVertices(body->mesh(), pose.skinMatrices(), skinnedPositions, Span<Vec3>());
}

namespace {

/// A collider last used more than this many of the asking garment's steps ago is reset, not moved.
constexpr double kMaxSweepSteps = 1.5;

} // namespace

Result<const collision::Collider*> CharacterInstance::meshColliderAt(collision::CollisionDevice& device, double time,
                                                                     double sweep) {
    std::lock_guard<std::mutex> lock(mMutex);
    if (mMeshColliderTime == time) return static_cast<const collision::Collider*>(meshCollider.get());
    if (Status s = updateSkinLocked(); !s) return s;
    if (!meshCollider) {
        auto made = collision::BodyCollider::create(device, bodyTopology, skinnedPositions);
        if (!made.isOk()) return made.status();
        meshCollider = std::move(made).value();
        mMeshColliderRebuilt = time;
    } else if (time - mMeshColliderTime > kMaxSweepSteps * sweep) {
        if (Status s = meshCollider->reset(skinnedPositions); !s) return s;
        mMeshColliderRebuilt = time;
    } else if (Status s = meshCollider->update(skinnedPositions, time - mMeshColliderTime); !s) {
        return s;
    }
    mMeshColliderTime = time;
    return static_cast<const collision::Collider*>(meshCollider.get());
}

bool CharacterInstance::meshColliderIdle(double time, double idle) const {
    return meshCollider && time - mMeshColliderTime > idle;
}

std::unique_ptr<collision::BodyCollider> CharacterInstance::takeMeshCollider() {
    mMeshColliderTime = -std::numeric_limits<double>::infinity();
    return std::move(meshCollider);
}

void CharacterInstance::adoptMeshCollider(std::unique_ptr<collision::BodyCollider> collider) {
    meshCollider = std::move(collider);
    mMeshColliderTime = -std::numeric_limits<double>::infinity();  // its pose is another character's
}

Status CharacterInstance::posedCapsules(std::vector<collision::Capsule>& out) {
    if (body->hostSkinned) return Status::error(StatusCode::InvalidOperation, "a host-skinned body has no capsules");
    if (Status s = updatePose(); !s) return s;
    posedCapsulesLocked(out);
    return Status::ok();
}

void CharacterInstance::posedCapsulesLocked(std::vector<collision::Capsule>& out) const {
    const auto& fitted = body->mannequin.capsules;
    const auto skin = pose.skinMatrices();
    out.resize(fitted.size());
    for (std::size_t k = 0; k < fitted.size(); ++k) {
        const Mat4& m = skin[fitted[k].joint];
        out[k].a = m.topLeftCorner<3, 3>() * fitted[k].a + m.topRightCorner<3, 1>();
        out[k].b = m.topLeftCorner<3, 3>() * fitted[k].b + m.topRightCorner<3, 1>();
        out[k].radius = fitted[k].radius;
    }
}

Result<const collision::Collider*> CharacterInstance::proxyColliderAt(collision::CollisionDevice& device, double time,
                                                                      double sweep) {
    if (body->hostSkinned) return meshColliderAt(device, time, sweep);
    std::lock_guard<std::mutex> lock(mMutex);
    if (mProxyColliderTime == time) return static_cast<const collision::Collider*>(&proxyCollider);
    if (Status s = updatePoseLocked(); !s) return s;
    posedCapsulesLocked(mCapsules);
    if (!proxyColliderMade) {
        auto made = collision::CapsuleCollider::create(mCapsules);
        if (!made.isOk()) return made.status();
        proxyCollider = std::move(made).value();
        proxyColliderMade = true;
    } else if (time - mProxyColliderTime > kMaxSweepSteps * sweep) {
        if (Status s = proxyCollider.reset(mCapsules); !s) return s;
    } else if (Status s = proxyCollider.update(mCapsules, time - mProxyColliderTime); !s) {
        return s;
    }
    mProxyColliderTime = time;
    return static_cast<const collision::Collider*>(&proxyCollider);
}

} // namespace cc::detail
