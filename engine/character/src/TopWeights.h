#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "crowdcloth/character/SkinnedMesh.h"

namespace cc::detail {

/// Accumulates (joint, weight) pairs, merging repeated joints, and writes the four largest
/// renormalised to sum 1 (ties broken by joint index, so the result is deterministic).
class TopWeights {
public:
    static constexpr int kCapacity = 16;

    void add(int32_t joint, double w) {
        if (!(w > 0.0)) return;
        for (int i = 0; i < mCount; ++i) {
            if (mJoints[static_cast<std::size_t>(i)] == joint) {
                mWeights[static_cast<std::size_t>(i)] += w;
                return;
            }
        }
        if (mCount == kCapacity) return;
        mJoints[static_cast<std::size_t>(mCount)] = joint;
        mWeights[static_cast<std::size_t>(mCount)] = w;
        ++mCount;
    }
    int count() const { return mCount; }

    /// Returns false (and writes nothing) when no positive weight was added.
    bool write(std::array<uint16_t, kMaxInfluences>& outJoints, std::array<double, kMaxInfluences>& outWeights) const {
        if (mCount == 0) return false;
        std::array<int, kCapacity> order{};
        for (int i = 0; i < mCount; ++i) order[static_cast<std::size_t>(i)] = i;
        std::sort(order.begin(), order.begin() + mCount, [&](int x, int y) {
            const double wx = mWeights[static_cast<std::size_t>(x)], wy = mWeights[static_cast<std::size_t>(y)];
            return wx != wy ? wx > wy : mJoints[static_cast<std::size_t>(x)] < mJoints[static_cast<std::size_t>(y)];
        });
        const int kept = std::min(mCount, kMaxInfluences);
        double sum = 0.0;
        for (int i = 0; i < kept; ++i) sum += mWeights[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
        outJoints.fill(0);
        outWeights.fill(0.0);
        for (int i = 0; i < kept; ++i) {
            const auto o = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
            outJoints[static_cast<std::size_t>(i)] = static_cast<uint16_t>(mJoints[o]);
            outWeights[static_cast<std::size_t>(i)] = mWeights[o] / sum;
        }
        return true;
    }

private:
    std::array<int32_t, kCapacity> mJoints{};
    std::array<double, kCapacity> mWeights{};
    int mCount = 0;
};

} // namespace cc::detail
