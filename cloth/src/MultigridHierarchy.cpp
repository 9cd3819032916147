#include "crowdcloth/cloth/MultigridHierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "AlgebraicCoarsening.h"

namespace cc::cloth {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
// An algebraic level that keeps more than this fraction of the vertices is not worth its cost:
// the hierarchy ends above it.
constexpr double kStalledCoarsening = 0.9;
// The dense coarsest solve stores (3 n)^2 doubles; a hierarchy cut short by maxLevels or a
// stalled coarsening above this size smooths its coarsest level instead.
constexpr uint32_t kMaxDenseVertices = 512;

std::string prolongationName(std::size_t k) {
    return "MultigridSettings.prolongations[" + std::to_string(k) + "]";
}

// Greedy colouring in vertex order: a vertex takes the smallest colour none of its (already
// coloured, lower-index) neighbours has. Vertices of one colour share no block, so a colour's
// Gauss-Seidel updates are independent and may run in parallel in any partition.
void colour(MultigridLevel& level) {
    const uint32_t n = level.size;
    std::vector<uint32_t> colourOf(n, kNone);
    std::vector<uint32_t> usedBy;  // usedBy[c] == v: colour c is taken by a neighbour of v
    uint32_t colours = 0;
    for (uint32_t v = 0; v < n; ++v) {
        for (uint32_t k = level.rowStart[v]; k < level.rowStart[v + 1]; ++k) {
            const uint32_t c = colourOf[level.columns[k]];
            if (c != kNone) usedBy[c] = v;
        }
        uint32_t c = 0;
        while (c < colours && usedBy[c] == v) ++c;
        if (c == colours) {
            ++colours;
            usedBy.push_back(kNone);
        }
        colourOf[v] = c;
    }
    level.colourStart.assign(colours + 1, 0);
    for (uint32_t v = 0; v < n; ++v) ++level.colourStart[colourOf[v] + 1];
    for (uint32_t c = 0; c < colours; ++c) level.colourStart[c + 1] += level.colourStart[c];
    level.colourVertices.resize(n);
    std::vector<uint32_t> next(level.colourStart.begin(), level.colourStart.end() - 1);
    for (uint32_t v = 0; v < n; ++v) level.colourVertices[next[colourOf[v]]++] = v;
}

// The block storage in Gauss-Seidel order (MultigridLevel::storageStart).
void store(MultigridLevel& level) {
    const uint32_t n = level.size;
    level.storageOf.resize(n);
    level.storageStart.assign(1, 0);
    level.storageColumns.clear();
    level.sourceSlot.clear();
    level.storageDiagonal.resize(n);
    for (uint32_t q = 0; q < n; ++q) {
        const uint32_t v = level.colourVertices[q];
        level.storageOf[v] = q;
        for (uint32_t k = level.rowStart[v]; k < level.rowStart[v + 1]; ++k) {
            if (level.columns[k] == v) level.storageDiagonal[v] = uint32_t(level.sourceSlot.size());
            level.storageColumns.push_back(level.columns[k]);
            level.sourceSlot.push_back(k);
        }
        level.storageStart.push_back(uint32_t(level.sourceSlot.size()));
    }
}

// Copies a prolongation into `fine`, terms merged per source and sorted, and builds its transpose.
void setProlongation(const SparseInterpolation& p, MultigridLevel& fine) {
    fine.prolongStart.assign(1, 0);
    fine.prolongSource.clear();
    fine.prolongWeight.clear();
    std::vector<SparseInterpolation::Term> row;
    for (uint32_t r = 0; r < p.rowCount(); ++r) {
        row.assign(p.terms.begin() + p.rowStart[r], p.terms.begin() + p.rowStart[r + 1]);
        std::sort(row.begin(), row.end(),
                  [](const auto& x, const auto& y) { return x.source < y.source; });
        for (std::size_t k = 0; k < row.size();) {
            SparseInterpolation::Term merged = row[k++];
            while (k < row.size() && row[k].source == merged.source)
                merged.weight += row[k++].weight;
            if (merged.weight == 0.0) continue;
            fine.prolongSource.push_back(merged.source);
            fine.prolongWeight.push_back(merged.weight);
        }
        fine.prolongStart.push_back(static_cast<uint32_t>(fine.prolongSource.size()));
    }
    const uint32_t coarse = p.sourceCount;
    fine.restrictStart.assign(coarse + 1, 0);
    for (uint32_t s : fine.prolongSource) ++fine.restrictStart[s + 1];
    for (uint32_t c = 0; c < coarse; ++c) fine.restrictStart[c + 1] += fine.restrictStart[c];
    fine.restrictSource.resize(fine.prolongSource.size());
    fine.restrictWeight.resize(fine.prolongSource.size());
    std::vector<uint32_t> next(fine.restrictStart.begin(), fine.restrictStart.end() - 1);
    for (uint32_t i = 0; i < fine.size; ++i) {  // fine rows ascend within each coarse row
        for (uint32_t t = fine.prolongStart[i]; t < fine.prolongStart[i + 1]; ++t) {
            const uint32_t slot = next[fine.prolongSource[t]]++;
            fine.restrictSource[slot] = i;
            fine.restrictWeight[slot] = fine.prolongWeight[t];
        }
    }
}

// The pattern of T = A P, the coarse pattern of P^T T (every coarse row holds its diagonal, even
// one no fine vertex interpolates from) and both slot maps.
void buildGalerkin(MultigridLevel& fine, MultigridLevel& coarse) {
    const uint32_t n = fine.size, m = coarse.size;
    std::vector<uint32_t> mark(m, kNone), local(m);
    std::vector<uint32_t> cols;
    fine.productStart.assign(1, 0);
    fine.productColumns.clear();
    fine.productMapStart.assign(1, 0);
    fine.productMap.clear();
    for (uint32_t i = 0; i < n; ++i) {
        cols.clear();
        for (uint32_t k = fine.rowStart[i]; k < fine.rowStart[i + 1]; ++k) {
            const uint32_t j = fine.columns[k];
            for (uint32_t t = fine.prolongStart[j]; t < fine.prolongStart[j + 1]; ++t) {
                const uint32_t c = fine.prolongSource[t];
                if (mark[c] != i) {
                    mark[c] = i;
                    cols.push_back(c);
                }
            }
        }
        std::sort(cols.begin(), cols.end());
        const uint32_t base = static_cast<uint32_t>(fine.productColumns.size());
        for (std::size_t q = 0; q < cols.size(); ++q)
            local[cols[q]] = base + static_cast<uint32_t>(q);
        fine.productColumns.insert(fine.productColumns.end(), cols.begin(), cols.end());
        fine.productStart.push_back(static_cast<uint32_t>(fine.productColumns.size()));
        for (uint32_t k = fine.rowStart[i]; k < fine.rowStart[i + 1]; ++k) {
            const uint32_t j = fine.columns[k];
            for (uint32_t t = fine.prolongStart[j]; t < fine.prolongStart[j + 1]; ++t) {
                fine.productMap.push_back(local[fine.prolongSource[t]]);
            }
        }
        fine.productMapStart.push_back(static_cast<uint32_t>(fine.productMap.size()));
    }

    std::fill(mark.begin(), mark.end(), kNone);
    coarse.rowStart.assign(1, 0);
    coarse.columns.clear();
    coarse.diagonal.resize(m);
    fine.galerkinMapStart.assign(1, 0);
    fine.galerkinMap.clear();
    for (uint32_t c = 0; c < m; ++c) {
        cols.assign(1, c);
        mark[c] = c;
        for (uint32_t t = fine.restrictStart[c]; t < fine.restrictStart[c + 1]; ++t) {
            const uint32_t i = fine.restrictSource[t];
            for (uint32_t s = fine.productStart[i]; s < fine.productStart[i + 1]; ++s) {
                const uint32_t d = fine.productColumns[s];
                if (mark[d] != c) {
                    mark[d] = c;
                    cols.push_back(d);
                }
            }
        }
        std::sort(cols.begin(), cols.end());
        const uint32_t base = static_cast<uint32_t>(coarse.columns.size());
        for (std::size_t q = 0; q < cols.size(); ++q)
            local[cols[q]] = base + static_cast<uint32_t>(q);
        coarse.diagonal[c] = local[c];
        coarse.columns.insert(coarse.columns.end(), cols.begin(), cols.end());
        coarse.rowStart.push_back(static_cast<uint32_t>(coarse.columns.size()));
        for (uint32_t t = fine.restrictStart[c]; t < fine.restrictStart[c + 1]; ++t) {
            const uint32_t i = fine.restrictSource[t];
            for (uint32_t s = fine.productStart[i]; s < fine.productStart[i + 1]; ++s) {
                fine.galerkinMap.push_back(local[fine.productColumns[s]]);
            }
        }
        fine.galerkinMapStart.push_back(static_cast<uint32_t>(fine.galerkinMap.size()));
    }
}

// Unfiltered Galerkin product of `values` (serial), for the next algebraic level's strengths.
std::vector<Mat3> galerkinValues(const MultigridLevel& fine, const MultigridLevel& coarse,
                                 const std::vector<Mat3>& values) {
    std::vector<Mat3> product(fine.productColumns.size(), Mat3::Zero());
    for (uint32_t i = 0; i < fine.size; ++i) {
        uint32_t q = fine.productMapStart[i];
        for (uint32_t k = fine.rowStart[i]; k < fine.rowStart[i + 1]; ++k) {
            const uint32_t j = fine.columns[k];
            for (uint32_t t = fine.prolongStart[j]; t < fine.prolongStart[j + 1]; ++t) {
                product[fine.productMap[q++]] += fine.prolongWeight[t] * values[k];
            }
        }
    }
    std::vector<Mat3> out(coarse.columns.size(), Mat3::Zero());
    for (uint32_t c = 0; c < coarse.size; ++c) {
        uint32_t q = fine.galerkinMapStart[c];
        for (uint32_t t = fine.restrictStart[c]; t < fine.restrictStart[c + 1]; ++t) {
            const uint32_t i = fine.restrictSource[t];
            for (uint32_t s = fine.productStart[i]; s < fine.productStart[i + 1]; ++s) {
                out[fine.galerkinMap[q++]] += fine.restrictWeight[t] * product[s];
            }
        }
    }
    return out;
}

// One algebraic coarsening of `a`; when the strong graph is too sparse to coarsen (every vertex
// its own coarse vertex), every coupling counts instead (threshold 0).
SparseInterpolation coarsen(const detail::LevelMatrix& a, const MultigridSettings& settings) {
    const auto once = [&](double threshold) {
        const detail::StrengthGraph graph = detail::strongCouplings(a, threshold);
        return settings.coarsening == CoarseningKind::SmoothedAggregation
                   ? detail::smoothedAggregationProlongation(a, graph)
                   : detail::independentSetProlongation(graph);
    };
    SparseInterpolation p = once(settings.strengthThreshold);
    if (p.sourceCount > kStalledCoarsening * a.size() && settings.strengthThreshold > 0.0)
        p = once(0.0);
    return p;
}

// An algebraic prolongation for `level` (with `values`). One independent-set pass only halves a
// 4-8 grid (red-black), and the halved level's Galerkin operator has twice the blocks per row, so
// it costs as much to smooth as the level above; two passes composed coarsen by about eight
// (measured in MultigridBench.cpp).
SparseInterpolation algebraicProlongation(const MultigridLevel& level,
                                          const std::vector<Mat3>& values,
                                          const MultigridSettings& settings) {
    const detail::LevelMatrix a{level.rowStart, level.columns, level.diagonal, values};
    SparseInterpolation first = coarsen(a, settings);
    if (settings.coarsening == CoarseningKind::SmoothedAggregation) return first;
    if (first.sourceCount <= settings.coarsestVertices ||
        first.sourceCount > kStalledCoarsening * level.size) {
        return first;
    }
    MultigridLevel fine, middle;
    fine.size = level.size;
    fine.rowStart = level.rowStart;
    fine.columns = level.columns;
    fine.diagonal = level.diagonal;
    setProlongation(first, fine);
    middle.size = first.sourceCount;
    buildGalerkin(fine, middle);
    const std::vector<Mat3> middleValues = galerkinValues(fine, middle, values);
    const SparseInterpolation second =
        coarsen(detail::LevelMatrix{middle.rowStart, middle.columns, middle.diagonal, middleValues},
                settings);
    if (second.sourceCount > kStalledCoarsening * middle.size) return first;
    return detail::compose(first, second);
}

} // namespace

Status MultigridSettings::validate() const {
    if (!(strengthThreshold >= 0.0 && strengthThreshold < 1.0)) {
        return Status::invalidArgument("MultigridSettings.strengthThreshold = " +
                                       std::to_string(strengthThreshold) + " is outside [0, 1)");
    }
    if (coarsening != CoarseningKind::IndependentSet &&
        coarsening != CoarseningKind::SmoothedAggregation) {
        return Status::invalidArgument("MultigridSettings.coarsening is not a CoarseningKind");
    }
    if (smoothingSweeps < 1 || smoothingSweeps > 8) {
        return Status::invalidArgument("MultigridSettings.smoothingSweeps = " +
                                       std::to_string(smoothingSweeps) + " is outside [1, 8]");
    }
    if (coarsestVertices < 1 || coarsestVertices > kMaxDenseVertices) {
        return Status::invalidArgument("MultigridSettings.coarsestVertices = " +
                                       std::to_string(coarsestVertices) + " is outside [1, 512]");
    }
    if (!(minCoarsening >= 1.0 && minCoarsening <= 16.0)) {
        return Status::invalidArgument("MultigridSettings.minCoarsening = " +
                                       std::to_string(minCoarsening) + " is outside [1, 16]");
    }
    if (maxLevels < 2 || maxLevels > 32) {
        return Status::invalidArgument(
            "MultigridSettings.maxLevels = " + std::to_string(maxLevels) + " is outside [2, 32]");
    }
    return Status::ok();
}

Status MultigridHierarchy::checkProlongations(uint32_t fineSize,
                                              const std::vector<SparseInterpolation>& list) {
    uint32_t rows = fineSize;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const SparseInterpolation& p = list[k];
        if (p.rowStart.empty() || p.rowStart.front() != 0 || p.rowStart.back() != p.terms.size()) {
            return Status::invalidArgument(prolongationName(k) +
                                           ".rowStart must start at 0 and end at terms.size()");
        }
        if (p.rowCount() != rows) {
            return Status::invalidArgument(
                prolongationName(k) + " has " + std::to_string(p.rowCount()) +
                " rows; its finer level has " + std::to_string(rows) + " vertices");
        }
        if (p.sourceCount == 0)
            return Status::invalidArgument(prolongationName(k) + ".sourceCount must be >= 1");
        for (uint32_t r = 0; r < p.rowCount(); ++r) {
            if (p.rowStart[r + 1] < p.rowStart[r]) {
                return Status::invalidArgument(prolongationName(k) + ".rowStart decreases at row " +
                                               std::to_string(r));
            }
            for (uint32_t t = p.rowStart[r]; t < p.rowStart[r + 1]; ++t) {
                if (p.terms[t].source >= p.sourceCount) {
                    return Status::invalidArgument(prolongationName(k) + " row " +
                                                   std::to_string(r) + " refers to coarse vertex " +
                                                   std::to_string(p.terms[t].source) + " of " +
                                                   std::to_string(p.sourceCount));
                }
                if (!std::isfinite(p.terms[t].weight)) {
                    return Status::invalidArgument(prolongationName(k) + " row " +
                                                   std::to_string(r) + " has a non-finite weight");
                }
            }
        }
        rows = p.sourceCount;
    }
    return Status::ok();
}

Result<MultigridHierarchy> MultigridHierarchy::build(const BlockSparseMatrix& fine,
                                                     const MultigridSettings& settings) {
    if (Status s = settings.validate(); !s) return s;
    if (Status s = checkProlongations(fine.size(), settings.prolongations); !s) return s;
    if (fine.size() == 0)
        return Status::invalidArgument("MultigridHierarchy: the matrix has no rows");

    MultigridHierarchy h;
    h.mLevels.emplace_back();
    MultigridLevel& top = h.mLevels.back();
    top.size = fine.size();
    top.rowStart = fine.rowStart();
    top.columns = fine.columns();
    top.diagonal.resize(top.size);
    for (uint32_t i = 0; i < top.size; ++i) top.diagonal[i] = fine.diagonalSlot(i);
    // Values only feed the strength of algebraic levels; copied once at build time.
    std::vector<Mat3> values;
    const bool algebraic = settings.prolongations.size() + 1 < std::size_t(settings.maxLevels);
    if (algebraic) {
        values.resize(fine.blockCount());
        for (std::size_t k = 0; k < values.size(); ++k) values[k] = fine.block(uint32_t(k));
    }

    bool cutShort = false;
    std::size_t given = 0;  // handed-in prolongations used so far
    for (std::size_t k = 0;; ++k) {
        MultigridLevel& level = h.mLevels[k];
        colour(level);
        store(level);
        if (level.size <= settings.coarsestVertices) break;
        if (int(k) + 1 >= settings.maxLevels) {
            cutShort = true;
            break;
        }
        SparseInterpolation p;
        if (given < settings.prolongations.size()) {
            // A handed-in level that coarsens too little is merged with the ones below it.
            p = settings.prolongations[given++];
            while (given < settings.prolongations.size() && p.sourceCount > 0 &&
                   double(level.size) < settings.minCoarsening * double(p.sourceCount)) {
                p = detail::compose(p, settings.prolongations[given++]);
            }
        } else {
            p = algebraicProlongation(level, values, settings);
            if (p.sourceCount > kStalledCoarsening * level.size) {
                cutShort = true;
                break;
            }
        }
        setProlongation(p, level);
        MultigridLevel next;
        next.size = p.sourceCount;
        buildGalerkin(level, next);
        if (algebraic) values = galerkinValues(level, next, values);
        h.mLevels.push_back(std::move(next));  // `level` is not used past this point
    }
    // The Galerkin products write straight into the coarse levels' stored blocks.
    for (std::size_t k = 0; k + 1 < h.mLevels.size(); ++k) {
        const MultigridLevel& coarse = h.mLevels[k + 1];
        std::vector<uint32_t> stored(coarse.columns.size());
        for (uint32_t q = 0; q < coarse.sourceSlot.size(); ++q) stored[coarse.sourceSlot[q]] = q;
        for (uint32_t& slot : h.mLevels[k].galerkinMap) slot = stored[slot];
    }
    h.mDirectCoarsest = !cutShort || h.mLevels.back().size <= kMaxDenseVertices;
    return h;
}

bool MultigridHierarchy::matches(const BlockSparseMatrix& matrix) const {
    return !mLevels.empty() && matrix.rowStart() == mLevels[0].rowStart &&
           matrix.columns() == mLevels[0].columns;
}

double MultigridHierarchy::operatorComplexity() const {
    double total = 0.0;
    for (const MultigridLevel& level : mLevels) total += double(level.columns.size());
    return total / double(mLevels[0].columns.size());
}

} // namespace cc::cloth
