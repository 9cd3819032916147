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
    for (int k = 0; k < kCollisionDetailCount; ++k)
        if (!(mCoefficients.collisionPerUpdateMs[k] >= 0.0 && mCoefficients.collisionPerVertexMs[k] >= 0.0 &&
              std::isfinite(mCoefficients.collisionPerUpdateMs[k]) && std::isfinite(mCoefficients.collisionPerVertexMs[k])))
            return Status::invalidArgument("CostModel.collisionPerUpdateMs and collisionPerVertexMs[" + std::to_string(k) +
                                           "] must be finite and >= 0");
    if (!(mCoefficients.selfCollisionPerVertexMs >= 0.0 && std::isfinite(mCoefficients.selfCollisionPerVertexMs)))
        return Status::invalidArgument("CostModel.selfCollisionPerVertexMs must be finite and >= 0");
    if (!(mCoefficients.learningRate > 0.0 && mCoefficients.learningRate <= 1.0))
        return Status::invalidArgument("CostModel.learningRate must be in (0, 1]");
    if (!(mCoefficients.spread >= 0.0 && mCoefficients.spread <= 10.0))
        return Status::invalidArgument("CostModel.spread must be in [0, 10]");
    return Status::ok();
}

double CostModel::formulaMs(SolverChoice solver, CollisionDetail collision, std::size_t vertexCount, int substeps,
                            int iterations) const {
    const int k = static_cast<int>(solver), c = static_cast<int>(collision);
    return mCoefficients.perUpdateMs + double(vertexCount) * mCoefficients.perVertexMs[k] * substeps * iterations +
           mCoefficients.collisionPerUpdateMs[c] + double(vertexCount) * mCoefficients.collisionPerVertexMs[c];
}

double CostModel::predictMs(uint32_t asset, int level, SolverChoice solver, CollisionDetail collision,
                            std::size_t vertexCount, int substeps, int iterations) const {
    if (mMode == Mode::Learned) {
        auto it = mLearned.find({asset, level, static_cast<int>(solver), static_cast<int>(collision), 0});
        if (it != mLearned.end()) return it->second.mean + mCoefficients.spread * it->second.deviation;
    }
    return formulaMs(solver, collision, vertexCount, substeps, iterations);
}

void CostModel::record(uint32_t asset, int level, SolverChoice solver, CollisionDetail collision, double measuredMs) {
    learn({asset, level, static_cast<int>(solver), static_cast<int>(collision), 0}, measuredMs);
}

double CostModel::predictSelfCollisionMs(uint32_t asset, int level, std::size_t vertexCount) const {
    if (mMode == Mode::Learned) {
        auto it = mLearned.find({asset, level, 0, 0, 1});
        if (it != mLearned.end()) return it->second.mean + mCoefficients.spread * it->second.deviation;
    }
    return double(vertexCount) * mCoefficients.selfCollisionPerVertexMs;
}

void CostModel::recordSelfCollision(uint32_t asset, int level, double measuredMs) {
    learn({asset, level, 0, 0, 1}, measuredMs);
}

void CostModel::learn(const Key& key, double measuredMs) {
    if (mMode != Mode::Learned || !std::isfinite(measuredMs) || measuredMs <= 0.0) return;
    auto [it, inserted] = mLearned.try_emplace(key, Learned{measuredMs, 0.0});
    if (inserted) return;
    Learned& l = it->second;
    const double rate = mCoefficients.learningRate;
    l.deviation += rate * (std::abs(measuredMs - l.mean) - l.deviation);
    l.mean += rate * (measuredMs - l.mean);
}

std::vector<CostModel::LearnedCost> CostModel::learned() const {
    std::vector<LearnedCost> out;
    out.reserve(mLearned.size());
    for (const auto& [key, l] : mLearned) {
        const auto& [asset, level, solver, collision, self] = key;
        out.push_back({asset, level, SolverChoice(solver), CollisionDetail(collision), l.mean, l.deviation, self != 0});
    }
    return out;
}

Status CostModel::setLearned(Span<const LearnedCost> entries) {
    std::map<Key, Learned> learned;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const LearnedCost& e = entries[i];
        const bool valid = e.level >= 0 && int(e.solver) < kSolverChoiceCount &&
                           int(e.collision) < kCollisionDetailCount &&
                           std::isfinite(e.meanMs) && e.meanMs > 0.0 && std::isfinite(e.deviationMs) &&
                           e.deviationMs >= 0.0;
        if (!valid) return Status::invalidArgument("learned cost " + std::to_string(i) + " is out of range");
        const bool placeholders = !e.selfCollision || (e.solver == SolverChoice::SubstepNewton &&
                                                       e.collision == CollisionDetail::None);
        if (!placeholders) return Status::invalidArgument("learned cost " + std::to_string(i) + " is out of range");
        if (!learned.try_emplace({e.asset, e.level, int(e.solver), int(e.collision), e.selfCollision ? 1 : 0},
                                 Learned{e.meanMs, e.deviationMs})
                 .second)
            return Status::invalidArgument("learned cost " + std::to_string(i) + " repeats its key");
    }
    mLearned = std::move(learned);
    return Status::ok();
}

} // namespace cc::lod
