#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace cc::detail {

/// The World's own workers for its per-frame phases: threads that sleep on a condition variable
/// between phases instead of spinning. OpenMP's workers spin at the end of each parallel region
/// (libgomp's default wait policy), which on shared cores steals the time the frame needs:
/// measured on the 2-core VM with other work running, the 200-character crowd took a median
/// 22.6 ms per frame with OpenMP's default policy against 10.1 ms with OMP_WAIT_POLICY=passive.
/// Indices are handed out one at a time (items of uneven cost, such as garments); the tasks must
/// write only what their index owns, so the order never changes a result.
class TaskPool {
public:
    /// `threads` - 1 workers; the calling thread is the last one. 1 = everything on the caller.
    explicit TaskPool(unsigned threads);
    ~TaskPool();
    TaskPool(const TaskPool&) = delete;
    TaskPool& operator=(const TaskPool&) = delete;

    unsigned threadCount() const { return unsigned(mWorkers.size()) + 1; }

    /// Runs task(context, i) for every i in [0, count) and returns when all have finished.
    void run(uint32_t count, void (*task)(void* context, uint32_t index), void* context);

private:
    void workerLoop();
    void drain();  // takes indices of the current job until none is left

    std::vector<std::thread> mWorkers;
    std::mutex mMutex;
    std::condition_variable mWake, mDone;
    uint64_t mGeneration = 0;  // a new job each run()
    bool mStop = false;
    // The current job (set under the mutex before the generation advances).
    void (*mTask)(void*, uint32_t) = nullptr;
    void* mContext = nullptr;
    uint32_t mCount = 0;
    uint32_t mNext = 0;      // next index to hand out (under the mutex)
    uint32_t mFinished = 0;  // indices done (under the mutex)
};

} // namespace cc::detail
