#pragma once
// Per-frame records written as the run goes (never held in memory): frames.csv, a small table for
// the summary plot, always; frame_stats.jsonl, World::statsJson() of every frame, on request.

#include <filesystem>
#include <fstream>
#include <vector>

#include "crowdcloth/World.h"

namespace crowd {

/// Number of LOD levels the CSV has a column for (L0..L7).
constexpr int kCsvLevels = 8;

class FrameLog {
public:
    /// Opens OUT/frames.csv and, with `frameStats`, OUT/frame_stats.jsonl.
    static cc::Result<FrameLog> open(const std::filesystem::path& out, bool frameStats);
    /// One row (and line) for the frame just stepped; `garments` are its garments' stats, `inView`
    /// which of them the camera sees (the error columns are over those).
    cc::Status record(const cc::World& world, int frame, double time, double budgetMs,
                      const std::vector<cc::GarmentStats>& garments, const std::vector<bool>& inView);

    const std::filesystem::path& csvPath() const { return mCsvPath; }
    const std::filesystem::path& jsonlPath() const { return mJsonlPath; }  ///< empty without frameStats

private:
    std::filesystem::path mCsvPath, mJsonlPath;
    std::ofstream mCsv, mJsonl;
    double mResidentMb = 0.0, mHeapMb = 0.0;  ///< sampled once a second (mallinfo2 walks the heap)
};

} // namespace crowd
