#include "FrameLog.h"

#include <algorithm>
#include <cstdio>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace crowd {
namespace {

/// [MB] resident memory of this process (a soak's figure; 0 where /proc is missing).
double residentMb() {
    long pages = 0, resident = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

/// [MB] heap the allocator has handed out and not had back: against residentMb, what a growth is
/// (allocations kept, or freed memory the allocator keeps). glibc only; 0 elsewhere.
double heapInUseMb() {
#if defined(__GLIBC__)
    const struct mallinfo2 m = mallinfo2();
    return double(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);  // small chunks and mmapped ones
#else
    return 0.0;
#endif
}

} // namespace

cc::Result<FrameLog> FrameLog::open(const std::filesystem::path& out, bool frameStats) {
    FrameLog log;
    log.mCsvPath = out / "frames.csv";
    log.mCsv.open(log.mCsvPath);
    if (!log.mCsv) return cc::Status::invalidArgument(log.mCsvPath.string() + ": cannot be written");
    log.mCsv << "frame,time,totalMs,budgetMs";
    for (int l = 0; l < kCsvLevels; ++l) log.mCsv << ",L" << l;
    log.mCsv << ",updated,visible,errorMedianPx,errorMaxPx,residentMb,heapMb\n";
    if (frameStats) {
        log.mJsonlPath = out / "frame_stats.jsonl";
        log.mJsonl.open(log.mJsonlPath);
        if (!log.mJsonl) return cc::Status::invalidArgument(log.mJsonlPath.string() + ": cannot be written");
    }
    return log;
}

cc::Status FrameLog::record(const cc::World& world, int frame, double time, double budgetMs,
                            const std::vector<cc::GarmentStats>& garments, const std::vector<bool>& inView) {
    std::vector<double> errors;
    for (std::size_t i = 0; i < garments.size(); ++i)
        if (inView[i]) errors.push_back(garments[i].predictedErrorPx);
    double median = 0.0, max = 0.0;
    if (!errors.empty()) {
        std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(errors.size() / 2), errors.end());
        median = errors[errors.size() / 2];
        max = *std::max_element(errors.begin(), errors.end());
    }
    const cc::FrameStats& fs = world.frameStats();
    mCsv << frame << ',' << time << ',' << fs.totalMs << ',' << budgetMs;
    for (int l = 0; l < kCsvLevels; ++l) mCsv << ',' << fs.garmentsPerLevel[l];
    mCsv << ',' << fs.updated << ',' << fs.visible << ',' << median << ',' << max;
    if (frame % 60 == 1) mResidentMb = residentMb(), mHeapMb = heapInUseMb();  // the rows between repeat it
    mCsv << ',' << mResidentMb << ',' << mHeapMb << '\n';
    if (mJsonl.is_open()) mJsonl << world.statsJson() << '\n';
    if (!mCsv || (mJsonl.is_open() && !mJsonl)) return cc::Status::invalidArgument("frame log: write failed (disk full?)");
    return cc::Status::ok();
}

} // namespace crowd
