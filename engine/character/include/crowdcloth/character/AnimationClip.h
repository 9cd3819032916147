#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/character/Skeleton.h"

namespace cc {

/// Cap on keys per channel and per curve, checked before allocation on import.
constexpr std::size_t kMaxKeysPerCurve = 1u << 20;

/// The keys of one joint. Each curve has strictly increasing times [s] (from the clip's start,
/// >= 0) and one value per time; an empty curve leaves that component at the joint's rest value.
struct JointChannel {
    int32_t joint = -1;
    std::vector<double> translationTimes; ///< [s]
    std::vector<Vec3> translations;       ///< [m]
    std::vector<double> rotationTimes;    ///< [s]
    std::vector<Quat> rotations;          ///< unit quaternions
    std::vector<double> scaleTimes;       ///< [s]
    std::vector<Vec3> scales;             ///< [-]
};

/// How a time outside [0, duration] is mapped into the clip.
enum class ClipWrap { Loop, Clamp };

/// A keyed animation of a skeleton's local transforms. Between keys translation and scale are
/// interpolated linearly and rotation by slerp (shorter arc); outside the keys a curve holds its
/// first/last value.
///
/// Clips authored "in place" carry the body's average velocity in `rootVelocity`: a host moves
/// the character by rootVelocity * t (and the clip loops seamlessly because it does not translate).
///
///     std::vector<Transform> local(skeleton.jointCount());
///     clip.evaluate(skeleton, 0.35, ClipWrap::Loop, local);
struct AnimationClip {
    std::string name;
    double duration = 0.0;                ///< [s] length of one cycle; >= 0 (0 = a single pose)
    Vec3 rootVelocity = Vec3::Zero();     ///< [m/s] in-place clips: the host's locomotion speed
    std::vector<JointChannel> channels;   ///< at most one per joint

    /// Checks finite duration, channel joints within [0, jointCount) and unique, key counts
    /// matching times, caps, finite values, strictly increasing times within [0, duration] and
    /// unit quaternions. The message names the clip, channel joint and key.
    Status validate(std::size_t jointCount) const;

    /// Local pose at `time` [s]: rest transforms overwritten by the animated curves.
    /// outLocal.size() must equal skeleton.jointCount(). No allocation.
    void evaluate(const Skeleton& skeleton, double time, ClipWrap wrap, Span<Transform> outLocal) const;

    /// Maps a time onto [0, duration] (Loop: modulo; Clamp: clamped).
    double wrapTime(double time, ClipWrap wrap) const;
};

} // namespace cc
