#include "crowdcloth/character/AnimationClip.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace cc {
namespace {

// Finds the key interval holding t: returns i and the fraction f so that the value is
// lerp(values[i], values[i + 1], f); holds the end values outside the keys.
void locate(const std::vector<double>& times, double t, std::size_t& outIndex, double& outFraction) {
    const std::size_t n = times.size();
    if (n == 1 || t <= times.front()) {
        outIndex = 0;
        outFraction = 0.0;
        return;
    }
    if (t >= times.back()) {
        outIndex = n - 1;
        outFraction = 0.0;
        return;
    }
    const auto it = std::upper_bound(times.begin(), times.end(), t);
    const std::size_t i = static_cast<std::size_t>(it - times.begin()) - 1;
    outIndex = i;
    outFraction = (t - times[i]) / (times[i + 1] - times[i]);
}

Vec3 sampleVec(const std::vector<double>& times, const std::vector<Vec3>& values, double t) {
    std::size_t i;
    double f;
    locate(times, t, i, f);
    if (f == 0.0) return values[i];
    return values[i] + f * (values[i + 1] - values[i]);
}

Quat sampleQuat(const std::vector<double>& times, const std::vector<Quat>& values, double t) {
    std::size_t i;
    double f;
    locate(times, t, i, f);
    if (f == 0.0) return values[i];
    return slerpShortest(values[i], values[i + 1], f);
}

template <typename T>
Status checkCurve(const std::string& where, const char* what, const std::vector<double>& times,
                  const std::vector<T>& values, double duration) {
    if (times.size() != values.size()) {
        return Status::invalidArgument(where + ": " + what + " has " + std::to_string(times.size()) +
                                       " times but " + std::to_string(values.size()) + " values");
    }
    if (times.size() > kMaxKeysPerCurve) {
        return Status::invalidArgument(where + ": " + what + " has more than " +
                                       std::to_string(kMaxKeysPerCurve) + " keys");
    }
    for (std::size_t k = 0; k < times.size(); ++k) {
        const std::string key = where + ": " + what + " key " + std::to_string(k);
        if (!std::isfinite(times[k]) || times[k] < 0.0 || times[k] > duration * (1.0 + 1e-9) + 1e-12) {
            return Status::invalidArgument(key + ": time " + std::to_string(times[k]) +
                                           " outside [0, duration " + std::to_string(duration) + "]");
        }
        if (k > 0 && !(times[k] > times[k - 1])) {
            return Status::invalidArgument(key + ": times must increase strictly");
        }
    }
    return Status::ok();
}

} // namespace

Status AnimationClip::validate(std::size_t jointCount) const {
    const std::string clipWhere = "clip '" + name + "'";
    if (!std::isfinite(duration) || duration < 0.0) {
        return Status::invalidArgument(clipWhere + ": duration must be finite and >= 0");
    }
    if (!isFinite(rootVelocity)) return Status::invalidArgument(clipWhere + ": non-finite rootVelocity");
    std::vector<char> seen(jointCount, 0);
    for (std::size_t c = 0; c < channels.size(); ++c) {
        const JointChannel& ch = channels[c];
        const std::string where = clipWhere + " channel " + std::to_string(c) + " (joint " +
                                  std::to_string(ch.joint) + ")";
        if (ch.joint < 0 || static_cast<std::size_t>(ch.joint) >= jointCount) {
            return Status::invalidArgument(where + ": joint outside [0, " + std::to_string(jointCount) + ")");
        }
        if (seen[static_cast<std::size_t>(ch.joint)]) return Status::invalidArgument(where + ": second channel for the joint");
        seen[static_cast<std::size_t>(ch.joint)] = 1;
        Status s = checkCurve(where, "translation", ch.translationTimes, ch.translations, duration);
        if (!s) return s;
        s = checkCurve(where, "rotation", ch.rotationTimes, ch.rotations, duration);
        if (!s) return s;
        s = checkCurve(where, "scale", ch.scaleTimes, ch.scales, duration);
        if (!s) return s;
        for (std::size_t k = 0; k < ch.translations.size(); ++k) {
            if (!isFinite(ch.translations[k])) {
                return Status::invalidArgument(where + ": translation key " + std::to_string(k) + " is not finite");
            }
        }
        for (std::size_t k = 0; k < ch.rotations.size(); ++k) {
            const Quat& q = ch.rotations[k];
            const double n = q.norm();
            if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-6) {
                return Status::invalidArgument(where + ": rotation key " + std::to_string(k) +
                                               " is not a unit quaternion (norm " + std::to_string(n) + ")");
            }
        }
        for (std::size_t k = 0; k < ch.scales.size(); ++k) {
            if (!isFinite(ch.scales[k]) || !(ch.scales[k].minCoeff() > 0.0)) {
                return Status::invalidArgument(where + ": scale key " + std::to_string(k) +
                                               " is not finite and positive");
            }
        }
    }
    return Status::ok();
}

double AnimationClip::wrapTime(double time, ClipWrap wrap) const {
    if (!(duration > 0.0) || !std::isfinite(time)) return 0.0;
    if (wrap == ClipWrap::Clamp) return std::clamp(time, 0.0, duration);
    double t = std::fmod(time, duration);
    if (t < 0.0) t += duration;
    return t;
}

void AnimationClip::evaluate(const Skeleton& skeleton, double time, ClipWrap wrap,
                             Span<Transform> outLocal) const {
    skeleton.restPose(outLocal);
    const double t = wrapTime(time, wrap);
    for (const JointChannel& ch : channels) {
        Transform& x = outLocal[static_cast<std::size_t>(ch.joint)];
        if (!ch.translationTimes.empty()) x.translation = sampleVec(ch.translationTimes, ch.translations, t);
        if (!ch.rotationTimes.empty()) x.rotation = sampleQuat(ch.rotationTimes, ch.rotations, t);
        if (!ch.scaleTimes.empty()) x.scale = sampleVec(ch.scaleTimes, ch.scales, t);
    }
}

} // namespace cc
