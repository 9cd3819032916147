#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cc {

/// The p-quantile of `values` (nearest rank: the smallest value with at least a fraction p of them
/// at or below it); 0 for none. p in [0, 1].
inline double percentile(std::vector<double> values, double p) {
    if (values.empty()) return 0.0;
    const double rank = std::ceil(p * double(values.size())) - 1.0;
    const std::size_t k = std::min(values.size() - 1, std::size_t(std::max(0.0, rank)));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

} // namespace cc
