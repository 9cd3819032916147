#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

#include "GarmentInstance.h"
#include "crowdcloth/cloth/SubstepSolver.h"
#include "crowdcloth/core/Status.h"

namespace cc::detail {

/// The substep solver's prefactored matrices, one per asset level and substep size, shared by every
/// garment stepped with them (the World's batches and the shadow check's copies alike): built on
/// first need, dropped when no garment used them for a while, so the cache stays as small as the
/// crowd's current variety. A factor depends only on its key, so sharing changes no result.
class FactorCache {
public:
    /// Frames a factor may go unused before sweep() drops it.
    static constexpr uint64_t kSweepFrames = 600;

    /// The factor of `g`'s asset at `level` for substeps of `substep` seconds, marked used in
    /// `frame`. Serial: not to be called from several threads at once.
    Result<const cloth::SubstepFactor*> get(const GarmentInstance& g, int level, double substep, uint64_t frame);
    /// Every kSweepFrames frames, drops the factors unused for longer than that.
    void sweep(uint64_t frame);

private:
    using Key = std::tuple<uint32_t, int, double>;  ///< asset index, level, substep [s]
    struct Entry {
        std::shared_ptr<const cloth::SubstepFactor> factor;
        uint64_t lastUsedFrame = 0;
    };
    std::map<Key, Entry> mEntries;
};

} // namespace cc::detail
