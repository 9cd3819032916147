// The World's workers (engine/src/TaskPool.h): every index runs exactly once per job, on any
// number of threads, job after job; and the caller only returns once all have finished.
#include <atomic>
#include <vector>

#include <gtest/gtest.h>

#include "TaskPool.h"

namespace cc::detail {
namespace {

TEST(TaskPool, RunsEveryIndexExactlyOnceJobAfterJob) {
    for (unsigned threads : {1u, 2u, 4u}) {
        TaskPool pool(threads);
        EXPECT_EQ(pool.threadCount(), threads);
        for (uint32_t count : {0u, 1u, 3u, 64u, 1000u}) {
            for (int job = 0; job < 20; ++job) {
                std::vector<std::atomic<int>> hits(count);
                pool.run(count, [](void* c, uint32_t i) { ++(*static_cast<std::vector<std::atomic<int>>*>(c))[i]; },
                         &hits);
                for (uint32_t i = 0; i < count; ++i)
                    ASSERT_EQ(hits[i].load(), 1) << threads << " threads, " << count << " tasks, index " << i;
            }
        }
    }
}

} // namespace
} // namespace cc::detail
