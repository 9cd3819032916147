#include "TaskPool.h"

namespace cc::detail {

TaskPool::TaskPool(unsigned threads) {
    for (unsigned t = 1; t < threads; ++t) mWorkers.emplace_back([this] { workerLoop(); });
}

TaskPool::~TaskPool() {
    {
        std::lock_guard<std::mutex> lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    for (std::thread& t : mWorkers) t.join();
}

void TaskPool::run(uint32_t count, void (*task)(void*, uint32_t), void* context) {
    if (count == 0) return;
    if (mWorkers.empty() || count == 1) {
        for (uint32_t i = 0; i < count; ++i) task(context, i);
        return;
    }
    {
        std::lock_guard<std::mutex> lock(mMutex);
        mTask = task;
        mContext = context;
        mCount = count;
        mNext = 0;
        mFinished = 0;
        ++mGeneration;
    }
    mWake.notify_all();
    drain();
    std::unique_lock<std::mutex> lock(mMutex);
    mDone.wait(lock, [&] { return mFinished == mCount; });
    mTask = nullptr;
}

void TaskPool::drain() {
    std::unique_lock<std::mutex> lock(mMutex);
    while (mTask && mNext < mCount) {
        const uint32_t index = mNext++;
        auto* task = mTask;
        void* context = mContext;
        lock.unlock();
        task(context, index);
        lock.lock();
        if (++mFinished == mCount) mDone.notify_all();
    }
}

void TaskPool::workerLoop() {
    uint64_t seen = 0;
    for (;;) {
        {
            std::unique_lock<std::mutex> lock(mMutex);
            mWake.wait(lock, [&] { return mStop || mGeneration != seen; });
            if (mStop) return;
            seen = mGeneration;
        }
        drain();
    }
}

} // namespace cc::detail
