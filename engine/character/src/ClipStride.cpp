#include "crowdcloth/character/ClipStride.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cc {

namespace {

/// [Hz] clip samples: a stride's extreme lasts about a tenth of a second.
constexpr double kSampleRate = 30.0;
/// Most samples of one clip (two minutes at kSampleRate; a longer clip, or a file's absurd
/// duration, is sampled this many times evenly).
constexpr int kMostSamples = 3600;

/// The knee of the leg starting at `thigh`: down the leg's main chain (at each joint the child
/// with the most joints below it, so a twist or helper leaf beside the shin is passed over), the
/// joint nearest halfway between the thigh joint and the chain's end in the rest pose; -1 for a
/// chain of one.
int32_t kneeOf(const Skeleton& skeleton, const std::vector<Mat4>& rest, int32_t thigh) {
    const std::size_t n = skeleton.jointCount();
    // Joints below each joint, itself included (parents precede their children).
    std::vector<uint32_t> below(n, 1);
    for (std::size_t j = n; j-- > 0;)
        if (const int32_t parent = skeleton.joints[j].parent; parent >= 0)
            below[std::size_t(parent)] += below[j];
    std::vector<int32_t> chain{thigh};
    for (;;) {
        int32_t next = -1;
        for (std::size_t j = std::size_t(chain.back()) + 1; j < n; ++j)
            if (skeleton.joints[j].parent == chain.back() &&
                (next < 0 || below[j] > below[std::size_t(next)]))
                next = int32_t(j);
        if (next < 0) break;
        chain.push_back(next);
    }
    if (chain.size() < 2) return -1;
    const double middle =
        0.5 * (rest[std::size_t(chain.front())](1, 3) + rest[std::size_t(chain.back())](1, 3));
    int32_t knee = -1;
    double best = 0.0;
    for (std::size_t k = 1; k < chain.size(); ++k) {
        const double off = std::abs(rest[std::size_t(chain[k])](1, 3) - middle);
        if (knee < 0 || off < best) knee = chain[k], best = off;
    }
    return knee;
}

} // namespace

double widestClipStride(const Character& character, const BodyRegions& regions) {
    const Skeleton& skeleton = character.skeleton;
    const std::size_t n = skeleton.jointCount();
    if (character.clips.empty() || n == 0) return 0.0;
    for (int32_t thigh : regions.thigh)
        if (thigh < 0 || std::size_t(thigh) >= n) return 0.0;
    std::vector<Transform> local(n);
    std::vector<Mat4> global(n);
    skeleton.restPose(local);
    skeleton.computeGlobalTransforms(local, global);
    const int32_t knee[2] = {kneeOf(skeleton, global, regions.thigh[0]),
                             kneeOf(skeleton, global, regions.thigh[1])};
    if (knee[0] < 0 || knee[1] < 0) return 0.0;
    const Vec3 up = Vec3::UnitY();
    double widest = 0.0;
    for (const AnimationClip& clip : character.clips) {
        const int samples =
            1 + int(std::min(std::ceil(clip.duration * kSampleRate), double(kMostSamples)));
        for (int s = 0; s < samples; ++s) {
            const double time = samples > 1 ? clip.duration * s / double(samples - 1) : 0.0;
            clip.evaluate(skeleton, time, ClipWrap::Clamp, local);
            skeleton.computeGlobalTransforms(local, global);
            double angle[2];
            for (int leg = 0; leg < 2; ++leg) {
                const Vec3 d = global[std::size_t(knee[leg])].topRightCorner<3, 1>() -
                               global[std::size_t(regions.thigh[leg])].topRightCorner<3, 1>();
                angle[leg] = std::atan2(d.dot(regions.forward), -d.dot(up));
            }
            double between = std::abs(angle[0] - angle[1]);
            if (between > kPi) between = 2.0 * kPi - between;
            const double stride = 0.5 * between;
            if (std::isfinite(stride)) widest = std::max(widest, stride);
        }
    }
    return widest;
}

} // namespace cc
