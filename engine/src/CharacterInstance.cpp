#include "CharacterInstance.h"

namespace cc::detail {

Status CharacterInstance::updatePose() {
    if (poseCurrent || body->hostSkinned) return Status::ok();
    poseCurrent = true;
    return pose.evaluate(body->mannequin.character, clip, clipTime, ClipWrap::Loop);
}

Status CharacterInstance::updateSkin() {
    if (skinnedCurrent) return Status::ok();
    if (body->hostSkinned) {
        if (!hostVerticesGiven)
            return Status::error(StatusCode::InvalidOperation,
                                 "host-skinned character: setCharacterSkinnedVertices() was not called before step()");
        skinnedCurrent = true;
        return Status::ok();
    }
    if (Status s = updatePose(); !s) return s;
    skinnedPositions.resize(body->mesh().vertexCount());
    skinnedCurrent = true;
    return skinVertices(body->mesh(), pose.skinMatrices(), skinnedPositions, Span<Vec3>());
}

} // namespace cc::detail
