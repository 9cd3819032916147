#include "AlgebraicCoarsening.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cc::cloth::detail {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// Appends one prolongation row from (source, weight) terms, merging equal sources (in ascending
// order, so the row is the same whatever order the terms came in) and dropping zero weights.
void appendRow(std::vector<SparseInterpolation::Term>& terms, SparseInterpolation& out) {
    std::sort(terms.begin(), terms.end(),
              [](const auto& x, const auto& y) { return x.source < y.source; });
    for (std::size_t k = 0; k < terms.size();) {
        SparseInterpolation::Term merged = terms[k++];
        while (k < terms.size() && terms[k].source == merged.source)
            merged.weight += terms[k++].weight;
        if (merged.weight != 0.0) out.terms.push_back(merged);
    }
    out.rowStart.push_back(static_cast<uint32_t>(out.terms.size()));
}

} // namespace

StrengthGraph strongCouplings(const LevelMatrix& a, double threshold) {
    const uint32_t n = a.size();
    std::vector<double> diagonalNorm(n);
    for (uint32_t i = 0; i < n; ++i) diagonalNorm[i] = a.values[a.diagonal[i]].norm();
    StrengthGraph g;
    g.start.reserve(n + 1);
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t k = a.rowStart[i]; k < a.rowStart[i + 1]; ++k) {
            const uint32_t j = a.columns[k];
            if (j == i) continue;
            const double s = a.values[k].norm();
            if (s > 0.0 && s >= threshold * std::sqrt(diagonalNorm[i] * diagonalNorm[j])) {
                g.neighbours.push_back(j);
                g.strength.push_back(s);
            }
        }
        g.start.push_back(static_cast<uint32_t>(g.neighbours.size()));
    }
    return g;
}

SparseInterpolation independentSetProlongation(const StrengthGraph& g) {
    const uint32_t n = static_cast<uint32_t>(g.start.size() - 1);
    enum : uint8_t { Undecided, Coarse, Fine };
    std::vector<uint8_t> state(n, Undecided);
    std::vector<uint32_t> coarseIndex(n, kNone);
    uint32_t coarseCount = 0;
    for (uint32_t i = 0; i < n; ++i) {
        if (state[i] != Undecided) continue;
        state[i] = Coarse;
        coarseIndex[i] = coarseCount++;
        for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
            if (state[g.neighbours[k]] == Undecided) state[g.neighbours[k]] = Fine;
        }
    }
    SparseInterpolation p;
    p.sourceCount = coarseCount;
    std::vector<SparseInterpolation::Term> row;
    for (uint32_t i = 0; i < n; ++i) {
        row.clear();
        if (state[i] == Coarse) {
            row.push_back({coarseIndex[i], 1.0});
        } else {
            // Maximality: every fine vertex has a strong coarse neighbour.
            double total = 0.0;
            for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
                if (state[g.neighbours[k]] == Coarse) total += g.strength[k];
            }
            for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
                const uint32_t j = g.neighbours[k];
                if (state[j] == Coarse) row.push_back({coarseIndex[j], g.strength[k] / total});
            }
        }
        appendRow(row, p);
    }
    return p;
}

SparseInterpolation compose(const SparseInterpolation& p1, const SparseInterpolation& p2) {
    SparseInterpolation p;
    p.sourceCount = p2.sourceCount;
    std::vector<SparseInterpolation::Term> row;
    for (uint32_t r = 0; r < p1.rowCount(); ++r) {
        row.clear();
        for (uint32_t t = p1.rowStart[r]; t < p1.rowStart[r + 1]; ++t) {
            const auto& [middle, w1] = p1.terms[t];
            for (uint32_t u = p2.rowStart[middle]; u < p2.rowStart[middle + 1]; ++u) {
                row.push_back({p2.terms[u].source, w1 * p2.terms[u].weight});
            }
        }
        appendRow(row, p);
    }
    return p;
}

SparseInterpolation smoothedAggregationProlongation(const LevelMatrix& a, const StrengthGraph& g) {
    const uint32_t n = a.size();
    // Aggregation in three passes (Vanek, Mandel & Brezina 1996, section 4): (1) a vertex whose
    // strong neighbourhood is untouched roots an aggregate of that neighbourhood; (2) leftovers
    // join the aggregate of their strongest pass-1 neighbour; (3) what remains forms aggregates
    // of its still free neighbourhoods.
    std::vector<uint32_t> aggregate(n, kNone);
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; ++i) {
        bool free = aggregate[i] == kNone;
        for (uint32_t k = g.start[i]; free && k < g.start[i + 1]; ++k)
            free = aggregate[g.neighbours[k]] == kNone;
        if (!free) continue;
        aggregate[i] = count;
        for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) aggregate[g.neighbours[k]] = count;
        ++count;
    }
    const std::vector<uint32_t> firstPass = aggregate;
    for (uint32_t i = 0; i < n; ++i) {
        if (firstPass[i] != kNone) continue;
        double best = 0.0;
        for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
            const uint32_t j = g.neighbours[k];
            if (firstPass[j] != kNone && g.strength[k] > best) {
                best = g.strength[k];
                aggregate[i] = firstPass[j];
            }
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        if (aggregate[i] != kNone) continue;
        aggregate[i] = count;
        for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
            if (aggregate[g.neighbours[k]] == kNone) aggregate[g.neighbours[k]] = count;
        }
        ++count;
    }

    // The filtered scalar operator: trace(A_ij) / 3 on the strong couplings, the weak ones lumped
    // onto the diagonal so that row sums (and so the translations' image) are kept.
    std::vector<double> diagonal(n), rowAbs(n, 0.0);
    std::vector<double> strongValue(g.neighbours.size());
    for (uint32_t i = 0; i < n; ++i) {
        double d = 0.0;
        uint32_t s = g.start[i];
        for (uint32_t k = a.rowStart[i]; k < a.rowStart[i + 1]; ++k) {
            const uint32_t j = a.columns[k];
            const double value = a.values[k].trace() / 3.0;
            if (s < g.start[i + 1] && g.neighbours[s] == j) {
                strongValue[s++] = value;
                rowAbs[i] += std::abs(value);
            } else {
                d += value;
            }
        }
        diagonal[i] = d;
    }
    // omega = 4 / (3 rho(D^-1 A)), with rho bounded by Gershgorin (the usual SA damping).
    double rho = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        if (diagonal[i] > 0.0) rho = std::max(rho, 1.0 + rowAbs[i] / diagonal[i]);
    }
    const double omega = rho > 0.0 ? 4.0 / (3.0 * rho) : 0.0;

    SparseInterpolation p;
    p.sourceCount = count;
    std::vector<SparseInterpolation::Term> row;
    for (uint32_t i = 0; i < n; ++i) {
        row.clear();
        if (!(diagonal[i] > 0.0)) {
            row.push_back({aggregate[i], 1.0});
        } else {
            // Row i of (I - omega D^-1 A) P_tentative.
            row.push_back({aggregate[i], 1.0 - omega});
            for (uint32_t k = g.start[i]; k < g.start[i + 1]; ++k) {
                row.push_back({aggregate[g.neighbours[k]], -omega * strongValue[k] / diagonal[i]});
            }
        }
        appendRow(row, p);
    }
    return p;
}

} // namespace cc::cloth::detail
