#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace cc::bench {

/// Forwards every report to the display reporter that --benchmark_format chose, and keeps each
/// successful run so the summary can combine the results of different cases.
class RecordingReporter final : public benchmark::BenchmarkReporter {
public:
    explicit RecordingReporter(std::unique_ptr<benchmark::BenchmarkReporter> display);

    bool ReportContext(const Context& context) override;
    void ReportRuns(const std::vector<Run>& runs) override;
    void Finalize() override;

    /// The last run of the case registered as `name`, or null if it did not run (filtered out or
    /// failed).
    const Run* find(const std::string& name) const;
    bool empty() const { return mRuns.empty(); }

private:
    std::unique_ptr<benchmark::BenchmarkReporter> mDisplay;
    std::map<std::string, Run> mRuns;
};

/// Prints what needs several cases together: the PCG roofline (bytes one CG iteration moves per
/// vertex against the measured triad bandwidth) and our speed relative to Bullet's. Sections whose
/// cases did not run are left out.
void printRunSummary(std::FILE* out, const RecordingReporter& runs);

} // namespace cc::bench
