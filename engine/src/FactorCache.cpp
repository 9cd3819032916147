#include "FactorCache.h"

namespace cc::detail {

Result<const cloth::SubstepFactor*> FactorCache::get(const GarmentInstance& g, int level, double substep,
                                                     uint64_t frame) {
    const Key key{g.assetIndex(), level, substep};
    Entry& slot = mEntries[key];
    if (!slot.factor) {
        auto built = g.asset().levels[std::size_t(level)].cloth->buildFactor(substep);
        if (!built.isOk()) {
            mEntries.erase(key);
            return built.status();
        }
        slot.factor = std::move(built).value();
    }
    slot.lastUsedFrame = frame;
    return slot.factor.get();
}

void FactorCache::sweep(uint64_t frame) {
    if (frame % kSweepFrames != 0) return;
    for (auto it = mEntries.begin(); it != mEntries.end();)
        it = frame - it->second.lastUsedFrame > kSweepFrames ? mEntries.erase(it) : std::next(it);
}

} // namespace cc::detail
