#include "crowdcloth/character/Character.h"

#include <cmath>
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

Status changeBasis(Character& character, double scale, const Mat3& rotation) {
    if (!std::isfinite(scale) || !(scale > 0.0)) return Status::invalidArgument("changeBasis: scale must be finite and > 0");
    if (!rotation.allFinite() || (rotation * rotation.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
        rotation.determinant() < 0.0) {
        return Status::invalidArgument("changeBasis: rotation must be orthonormal with determinant +1");
    }
    const Quat r(rotation);
    const Mat3 absR = rotation.cwiseAbs();
    Mat4 c = Mat4::Identity();
    c.topLeftCorner<3, 3>() = scale * rotation;
    const Mat4 cInv = affineInverse(c);
    const auto mapVec = [&](Vec3& t) { t = scale * (rotation * t); };
    const auto mapQuat = [&](Quat& q) { q = (r * q * r.conjugate()).normalized(); };
    const auto mapScale = [&](Vec3& s) { s = absR * s; };
    for (Joint& j : character.skeleton.joints) {
        mapVec(j.restLocal.translation);
        mapQuat(j.restLocal.rotation);
        mapScale(j.restLocal.scale);
    }
    for (AnimationClip& clip : character.clips) {
        mapVec(clip.rootVelocity);
        for (JointChannel& ch : clip.channels) {
            for (Vec3& t : ch.translations) mapVec(t);
            for (Quat& q : ch.rotations) mapQuat(q);
            for (Vec3& s : ch.scales) mapScale(s);
        }
    }
    for (Vec3& p : character.body.bindPositions) mapVec(p);
    for (Vec3& n : character.body.bindNormals) n = rotation * n;
    for (Mat4& m : character.body.inverseBindMatrices) m = c * m * cInv;
    return Status::ok();
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
