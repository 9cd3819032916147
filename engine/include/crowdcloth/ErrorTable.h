#pragma once
// Measured errors of a garment design's levels (README, "Speed against accuracy"): what the
// scheduler uses in place of its h^2 / (8 foldRadius) formula once a table is handed to the World.

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/Export.h"
#include "crowdcloth/Status.h"

namespace cc {

struct ClothAssetDesc;
struct WorldDesc;

/// How a table is measured. Every window of both motions (walk, run) runs every level.
struct CC_API ErrorCookDesc {
    double seconds = 3.0;              ///< [s] run per motion; windows from 0.5 s on; [1, 60]
    double windowSeconds = 0.25;       ///< [s] [0.05, 2]
    uint32_t referenceSubsteps = 64;   ///< [-] [2, 64]
    uint32_t referenceIterations = 40; ///< [-] [1, 100]
    Status validate() const;
};

/// How a design's levels err, measured with the design: for each level and motion, the root mean
/// square distance of the render mesh from a reference's (a level above the finest, 64 substeps x
/// 40 iterations: converged in time, not yet in space, README) at the end of short windows, each
/// restarted from the reference's state along a run (TESTPLAN point 3), divided by the garment's
/// bounding radius about its centroid at the window's end. Relative to the
/// radius it carries to the design fitted to another body, and on screen it is that fraction of the
/// garment's projected radius. Measured under one World effort (substeps, iterations, strain limit):
/// another effort needs its own table (errorTableKey).
struct CC_API ErrorTable {
    static constexpr uint32_t kMotions = 2;
    static constexpr uint32_t kFormatVersion = 1;

    uint64_t key = 0;                       ///< errorTableKey() of the design and effort measured
    double speeds[kMotions] = {1.35, 3.5};  ///< [m/s] body speed of each motion (walk, run); ascending
    ErrorCookDesc cook;                     ///< how it was measured (part of the key)
    uint32_t windows = 0;                   ///< [-] windows measured per motion
    /// [-] per level (coarsest first) and motion, level-major: the 95th percentile over the windows
    /// (what the scheduler predicts: a garment within the tolerance in 19 windows of 20).
    std::vector<double> errorPerRadius;
    std::vector<double> medianErrorPerRadius;  ///< [-] the same, the median

    uint32_t levelCount() const { return uint32_t(errorPerRadius.size() / kMotions); }
    double error(uint32_t level, uint32_t motion) const { return errorPerRadius[level * kMotions + motion]; }
    /// The table with each motion's errors fitted non-increasing from the coarsest level to the
    /// finest (pool adjacent violators: the least-squares monotone fit), as World::setErrorTable
    /// uses it: a finer level is never predicted worse than a coarser one, since the spread between
    /// windows is larger than some levels' differences (the crowd sample's nine designs cooked with
    /// 10 windows: level 4 above level 3 walking in 4).
    ErrorTable nonIncreasingInLevel() const;
    /// Names the first field that is not a table: sizes, finite non-negative errors, speeds.
    Status validate() const;
    /// A text form that reads back bit for bit (doubles as hexadecimal floats).
    std::string toText() const;
    static Result<ErrorTable> fromText(const std::string& text);
};

/// The identity of what a table measures: the design's fields, the World's effort and gravity, the
/// cook's settings and the measuring method's version. A table is accepted only for its key.
CC_API uint64_t errorTableKey(const ClothAssetDesc& design, const WorldDesc& world, const ErrorCookDesc& cook = {});

/// Measures a design's table on the built-in mannequin walking and running (one thread, fixed
/// costs: the errors are deterministic; about half a minute for a 5-level design at the defaults).
CC_API Result<ErrorTable> cookErrorTable(const ClothAssetDesc& design, const WorldDesc& world,
                                         const ErrorCookDesc& cook = {});

/// The table cached in `directory` (a file named by its key), cooked and written there when it is
/// absent; a cached file that does not read as the key's table is cooked again and replaced.
CC_API Result<ErrorTable> loadOrCookErrorTable(const std::string& directory, const ClothAssetDesc& design,
                                               const WorldDesc& world, const ErrorCookDesc& cook = {});

} // namespace cc
