#include <gtest/gtest.h>

#include <vector>

#include "crowdcloth/core/ParallelFor.h"

using namespace cc;

TEST(ParallelFor, CoversEveryIndexOnce) {
    for (int threads : {1, 2, 3, 8}) {
        std::vector<int> hits(10007, 0);
        parallelFor(static_cast<int64_t>(hits.size()), ParallelSettings{threads, 1}, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) ++hits[i];
        });
        for (int h : hits) ASSERT_EQ(h, 1);
    }
}

