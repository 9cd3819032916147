#include "CharacterInstance.h"

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

} // namespace cc::detail
