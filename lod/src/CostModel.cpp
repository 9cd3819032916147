#include "crowdcloth/lod/CostModel.h"

#include <cmath>

namespace cc::lod {

CostModel::CostModel(Mode mode, const CostCoefficients& coefficients)
    : mMode(mode), mCoefficients(coefficients) {}

Status CostModel::validate() const {
    if (!std::isfinite(mCoefficients.perUpdateMs) || mCoefficients.perUpdateMs < 0.0)
        return Status::invalidArgument("CostModel.perUpdateMs must be finite and >= 0");
    for (int k = 0; k < kSolverChoiceCount; ++k)
        if (!std::isfinite(mCoefficients.perVertexMs[k]) || mCoefficients.perVertexMs[k] <= 0.0)
            return Status::invalidArgument("CostModel.perVertexMs[" + std::to_string(k) + "] must be > 0");
    if (!(mCoefficients.learningRate > 0.0 && mCoefficients.learningRate <= 1.0))
        return Status::invalidArgument("CostModel.learningRate must be in (0, 1]");
    return Status::ok();
}

double CostModel::formulaMs(SolverChoice solver, std::size_t vertexCount, int substeps, int iterations) const {
    const int k = static_cast<int>(solver);
    return mCoefficients.perUpdateMs + double(vertexCount) * mCoefficients.perVertexMs[k] * substeps * iterations;
}

double CostModel::predictMs(uint32_t asset, int level, SolverChoice solver, std::size_t vertexCount, int substeps,
                            int iterations) const {
    if (mMode == Mode::Learned) {
        auto it = mLearned.find({asset, level, static_cast<int>(solver)});
        if (it != mLearned.end()) return it->second.mean + 2.0 * it->second.deviation;
    }
    return formulaMs(solver, vertexCount, substeps, iterations);
}

void CostModel::record(uint32_t asset, int level, SolverChoice solver, double measuredMs) {
    if (mMode != Mode::Learned || !std::isfinite(measuredMs) || measuredMs <= 0.0) return;
    auto [it, inserted] = mLearned.try_emplace({asset, level, static_cast<int>(solver)}, Learned{measuredMs, 0.0});
    if (inserted) return;
    Learned& l = it->second;
    const double rate = mCoefficients.learningRate;
    l.deviation += rate * (std::abs(measuredMs - l.mean) - l.deviation);
    l.mean += rate * (measuredMs - l.mean);
}

} // namespace cc::lod
