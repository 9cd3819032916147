#include "FrameLog.h"

#include <algorithm>

namespace crowd {

cc::Result<FrameLog> FrameLog::open(const std::filesystem::path& out, bool frameStats) {
    FrameLog log;
    log.mCsvPath = out / "frames.csv";
    log.mCsv.open(log.mCsvPath);
    if (!log.mCsv) return cc::Status::invalidArgument(log.mCsvPath.string() + ": cannot be written");
    log.mCsv << "frame,time,totalMs,budgetMs";
    for (int l = 0; l < kCsvLevels; ++l) log.mCsv << ",L" << l;
    log.mCsv << ",updated,visible,errorMedianPx,errorMaxPx\n";
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
    mCsv << ',' << fs.updated << ',' << fs.visible << ',' << median << ',' << max << '\n';
    if (mJsonl.is_open()) mJsonl << world.statsJson() << '\n';
    if (!mCsv || (mJsonl.is_open() && !mJsonl)) return cc::Status::invalidArgument("frame log: write failed (disk full?)");
    return cc::Status::ok();
}

} // namespace crowd
