#pragma once

#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::lod {

/// Seeds of the cost formula, measured on a 2-core EPYC (samples/bench).
struct CostCoefficients {
    double perUpdateMs = 0.01;  ///< [ms] fixed overhead of updating one garment; >= 0
    double perVertexMs[kSolverChoiceCount] = {
        8.0e-5,  ///< Newton, per vertex, substep and CG iteration (measured: 80 ns at 65^2, alone)
        7.0e-5}; ///< local/global, per vertex, substep and iteration (measured: 70 ns at 65^2)
    /// [ms] fixed and per-vertex cost a collision detail adds to an update (seeds: body-mesh
    /// queries and refits, measured on the 5,776-triangle mannequin; capsules are in the above)
    double collisionPerUpdateMs[kCollisionDetailCount] = {0.0, 0.0, 0.5, 0.5};
    double collisionPerVertexMs[kCollisionDetailCount] = {0.0, 0.0, 5e-3, 1.2e-2};
    /// [ms] per vertex of one update's self-collision (seed: 2.3-6.2 us per vertex measured on the
    /// walking mannequin at the finest levels, `cc_crowd --self-collision`)
    double selfCollisionPerVertexMs = 3e-3;
    double learningRate = 0.1;  ///< [-] weight of a new measurement in the average; (0, 1]
    double spread = 0.5;        ///< [-] learned prediction = mean + spread x mean absolute deviation; [0, 10]
};

/// Predicted cost of one garment update, fixed or learned from measurements.
///
/// Fixed: `perUpdateMs + vertices * perVertexMs[solver] * substeps * iterations`, plus the collision
/// detail's `collisionPerUpdateMs + vertices * collisionPerVertexMs`, deterministic, for tests and
/// reproducible runs. Learned (the default for real use): the same formula seeds each (asset,
/// level, solver, collision detail) entry, then exponential moving averages of the measured time
/// and of its absolute deviation replace it. The collision detail is part of the key because it
/// changes an update's cost 10-30x: keyed without it, the rare mesh updates of near garments
/// inflate the prediction of every far one (5x at level 2 in a 1000-character crowd) and are
/// themselves under-predicted 4x. The prediction is mean + `spread` deviations: a frame's budget
/// is a sum over hundreds of updates whose deviations mostly cancel (mean + 2 deviations summed
/// predicted 18 ms for 14.7 measured), while a little margin covers the updates that split steps.
class CostModel {
public:
    enum class Mode { Fixed, Learned };

    explicit CostModel(Mode mode = Mode::Learned, const CostCoefficients& coefficients = {});

    Status validate() const;
    Mode mode() const { return mMode; }

    /// [ms] one update of `vertexCount` vertices at `substeps` x `iterations` with `solver`,
    /// meeting the body with `collision`.
    double predictMs(uint32_t asset, int level, SolverChoice solver, CollisionDetail collision,
                     std::size_t vertexCount, int substeps, int iterations) const;
    /// Feeds a measured update time [ms] (ignored in Fixed mode, and when not finite or <= 0).
    void record(uint32_t asset, int level, SolverChoice solver, CollisionDetail collision, double measuredMs);
    /// [ms] what self-collision adds to one update at `level` (learned apart from the update's
    /// own cost: only garments seen large take it, and it costs 1-4 solves).
    double predictSelfCollisionMs(uint32_t asset, int level, std::size_t vertexCount) const;
    /// Feeds a measured self-collision time [ms], as record() does.
    void recordSelfCollision(uint32_t asset, int level, double measuredMs);

    /// One learned prediction, for snapshots (World::saveState): what record() has averaged.
    struct LearnedCost {
        uint32_t asset = 0;
        int level = 0;
        SolverChoice solver = SolverChoice::SubstepNewton;
        CollisionDetail collision = CollisionDetail::None;
        double meanMs = 0.0;       ///< [ms] > 0
        double deviationMs = 0.0;  ///< [ms] >= 0
        bool selfCollision = false;  ///< self-collision's own cost at the level (solver and
                                     ///< collision then unused: Newton, None)
    };
    /// Every learned entry, in key order.
    std::vector<LearnedCost> learned() const;
    /// Replaces the learned entries; names the first invalid one (nothing changes then).
    Status setLearned(Span<const LearnedCost> entries);

private:
    double formulaMs(SolverChoice solver, CollisionDetail collision, std::size_t vertexCount, int substeps,
                     int iterations) const;

    Mode mMode;
    CostCoefficients mCoefficients;
    struct Learned {
        double mean = 0.0;       ///< [ms]
        double deviation = 0.0;  ///< [ms] mean absolute deviation
    };
    using Key = std::tuple<uint32_t, int, int, int, int>;  ///< asset, level, solver, collision, self-collision
    void learn(const Key& key, double measuredMs);
    std::map<Key, Learned> mLearned;
};

} // namespace cc::lod
