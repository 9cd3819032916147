#include "crowdcloth/character/Character.h"

#include <string>

namespace cc {

Status Character::validate() const {
    Status s = skeleton.validate();
    if (!s) return Status::invalidArgument("character '" + name + "': " + s.message());
    s = body.validate(skeleton.jointCount());
    if (!s) return Status::invalidArgument("character '" + name + "': " + s.message());
    for (const AnimationClip& clip : clips) {
        s = clip.validate(skeleton.jointCount());
        if (!s) return Status::invalidArgument("character '" + name + "': " + s.message());
    }
    return Status::ok();
}

int Character::findClip(const std::string& clipName) const {
    for (std::size_t i = 0; i < clips.size(); ++i) {
        if (clips[i].name == clipName) return static_cast<int>(i);
    }
    return -1;
}

CharacterPose::CharacterPose(const Character& character)
    : mLocal(character.skeleton.jointCount()), mGlobal(character.skeleton.jointCount()),
      mSkin(character.skeleton.jointCount()) {
    character.skeleton.restPose(mLocal);
    update(character);
}

Status CharacterPose::evaluate(const Character& character, int clipIndex, double time, ClipWrap wrap) {
    if (mLocal.size() != character.skeleton.jointCount() ||
        character.body.inverseBindMatrices.size() != mLocal.size()) {
        return Status::invalidArgument("CharacterPose: sized for " + std::to_string(mLocal.size()) +
                                       " joints, character '" + character.name + "' has " +
                                       std::to_string(character.skeleton.jointCount()));
    }
    if (clipIndex < -1 || clipIndex >= static_cast<int>(character.clips.size())) {
        return Status::invalidArgument("CharacterPose: clip index " + std::to_string(clipIndex) +
                                       " outside [-1, " + std::to_string(character.clips.size()) + ")");
    }
    if (clipIndex < 0) {
        character.skeleton.restPose(mLocal);
    } else {
        character.clips[static_cast<std::size_t>(clipIndex)].evaluate(character.skeleton, time, wrap, mLocal);
    }
    update(character);
    return Status::ok();
}

void CharacterPose::update(const Character& character) {
    character.skeleton.computeGlobalTransforms(mLocal, mGlobal);
    computeSkinMatrices(mGlobal, character.body.inverseBindMatrices, mSkin);
}

} // namespace cc
