#pragma once

#include <cstdint>
#include <map>
#include <tuple>

#include "crowdcloth/core/Status.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::lod {

/// Seeds of the cost formula, measured on a 2-core EPYC (samples/bench).
struct CostCoefficients {
    double perUpdateMs = 0.01;  ///< [ms] fixed overhead of updating one garment; >= 0
    double perVertexMs[kSolverChoiceCount] = {
        8.0e-5,  ///< Newton, per vertex, substep and CG iteration (measured: 80 ns at 65^2, alone)
        7.0e-5}; ///< local/global, per vertex, substep and iteration (measured: 70 ns at 65^2)
    double learningRate = 0.1;  ///< [-] weight of a new measurement in the average; (0, 1]
};

/// Predicted cost of one garment update, fixed or learned from measurements.
///
/// Fixed: `perUpdateMs + vertices * perVertexMs[solver] * substeps * iterations`, deterministic, for tests and
/// reproducible runs. Learned (the default for real use): the same formula seeds each (asset,
/// level, solver) entry, then exponential moving averages of the measured time and of its absolute
/// deviation replace it, and the prediction is mean + 2 deviations: a frame's worst case is set by
/// the updates that split their step, not by the average one.
class CostModel {
public:
    enum class Mode { Fixed, Learned };

    explicit CostModel(Mode mode = Mode::Learned, const CostCoefficients& coefficients = {});

    Status validate() const;
    Mode mode() const { return mMode; }

    /// [ms] one update of `vertexCount` vertices at `substeps` x `iterations` with `solver`.
    double predictMs(uint32_t asset, int level, SolverChoice solver, std::size_t vertexCount, int substeps,
                     int iterations) const;
    /// Feeds a measured update time [ms] (ignored in Fixed mode, and when not finite or <= 0).
    void record(uint32_t asset, int level, SolverChoice solver, double measuredMs);

private:
    double formulaMs(SolverChoice solver, std::size_t vertexCount, int substeps, int iterations) const;

    Mode mMode;
    CostCoefficients mCoefficients;
    struct Learned {
        double mean = 0.0;       ///< [ms]
        double deviation = 0.0;  ///< [ms] mean absolute deviation
    };
    std::map<std::tuple<uint32_t, int, int>, Learned> mLearned;
};

} // namespace cc::lod
