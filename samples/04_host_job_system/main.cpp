// 04_host_job_system: a host engine that schedules its own jobs runs crowdcloth's step tasks on
// its thread pool (World::beginStep / runStepTask / nextStepPhase / endStep), and gets exactly the
// state World::step() gives. Headless; prints the state hash of both runs and the time per frame.
//
//   cc_04_host_job_system [workers=3] [characters=24] [frames=120]
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "crowdcloth/World.h"

namespace {

/// The host's job system: a fixed pool of workers that run the indices of one batch of jobs; the
/// calling thread helps and returns when all have finished.
class ThreadPool {
public:
    explicit ThreadPool(int workers) {
        for (int k = 0; k < workers; ++k) mWorkers.emplace_back([this] { work(); });
    }
    ~ThreadPool() {
        {
            std::lock_guard<std::mutex> lock(mMutex);
            mStopping = true;
        }
        mWake.notify_all();
        for (std::thread& t : mWorkers) t.join();
    }

    void run(uint32_t count, const std::function<void(uint32_t)>& job) {
        std::unique_lock<std::mutex> lock(mMutex);
        mJob = &job;
        mCount = count;
        mNext = 0;
        mDone = 0;
        ++mGeneration;
        mWake.notify_all();
        drain(lock);
        mFinished.wait(lock, [&] { return mDone == mCount; });
        mJob = nullptr;
    }

private:
    void work() {
        std::unique_lock<std::mutex> lock(mMutex);
        uint64_t seen = 0;
        for (;;) {
            mWake.wait(lock, [&] { return mStopping || (mGeneration != seen && mNext < mCount); });
            if (mStopping) return;
            seen = mGeneration;
            drain(lock);
        }
    }
    /// Takes indices until none are left (the lock is held only to take one).
    void drain(std::unique_lock<std::mutex>& lock) {
        while (mJob && mNext < mCount) {
            const uint32_t index = mNext++;
            const std::function<void(uint32_t)>& job = *mJob;
            lock.unlock();
            job(index);
            lock.lock();
            if (++mDone == mCount) mFinished.notify_all();
        }
    }

    std::vector<std::thread> mWorkers;
    std::mutex mMutex;
    std::condition_variable mWake, mFinished;
    const std::function<void(uint32_t)>* mJob = nullptr;
    uint32_t mCount = 0, mNext = 0, mDone = 0;
    uint64_t mGeneration = 0;
    bool mStopping = false;
};

void check(const cc::Status& status, const char* what) {
    if (!status.isOk()) {
        std::fprintf(stderr, "%s failed: %s\n", what, status.message().c_str());
        std::exit(1);
    }
}

template <typename T>
T value(cc::Result<T> result, const char* what) {
    check(result.status(), what);
    return result.value();
}

/// A crowd walking along +Z in rows of six, each with a cape; returns the state hash.
uint64_t runCrowd(int characters, int frames, ThreadPool* pool, double* msPerFrame) {
    cc::WorldDesc desc;
    desc.fixedCostModel = true; // with budgetThreads: the same levels for any thread count
    desc.budgetThreads = 4;
    cc::World* world = value(cc::World::create(desc), "World::create");
    const cc::AssetId cape = value(world->addClothAsset({}), "addClothAsset");
    const cc::BodyId body = value(world->addMannequinBody({}), "addMannequinBody");
    std::vector<cc::CharacterId> walkers;
    for (int i = 0; i < characters; ++i) {
        cc::CharacterDesc c;
        c.body = body;
        c.clipPhase = 0.37 * i - int(0.37 * i);
        const int row = i / 6; // six characters to a row
        c.position[0] = 1.5 * (i % 6);
        c.position[2] = -2.0 * row;
        walkers.push_back(value(world->addCharacter(c), "addCharacter"));
        // A forced level is simulated every frame, camera or not: every cape is a task each frame.
        cc::GarmentDesc garment;
        garment.forceLevel = 2;
        value(world->addGarment(cape, walkers.back(), garment), "addGarment");
    }
    const double dt = 1.0 / 60.0;
    const auto start = std::chrono::steady_clock::now();
    for (int frame = 1; frame <= frames; ++frame) {
        for (int i = 0; i < characters; ++i) {
            const int row = i / 6;
            const double position[3] = {1.5 * (i % 6), 0.0, -2.0 * row + 1.3 * frame * dt};
            check(world->setCharacterRoot(walkers[i], position, 0.0), "setCharacterRoot");
        }
        if (!pool) {
            check(world->step(dt), "step");
            continue;
        }
        check(world->beginStep(dt), "beginStep");
        const std::function<void(uint32_t)> task = [world](uint32_t i) {
            check(world->runStepTask(i), "runStepTask");
        };
        do {
            pool->run(world->stepTaskCount(), task); // returns when every task of the phase is done
        } while (world->nextStepPhase());
        check(world->endStep(), "endStep");
    }
    *msPerFrame =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        frames;
    const uint64_t hash = world->stateHash();
    cc::World::destroy(world);
    return hash;
}

} // namespace

int main(int argc, char** argv) {
    const int workers = argc > 1 ? std::atoi(argv[1]) : 3;
    const int characters = argc > 2 ? std::atoi(argv[2]) : 24;
    const int frames = argc > 3 ? std::atoi(argv[3]) : 120;
    if (workers < 0 || characters < 1 || frames < 1) {
        std::fprintf(stderr, "usage: %s [workers>=0] [characters>=1] [frames>=1]\n", argv[0]);
        return 2;
    }
    double stepMs = 0.0, poolMs = 0.0;
    const uint64_t stepHash = runCrowd(characters, frames, nullptr, &stepMs);
    ThreadPool pool(workers);
    const uint64_t poolHash = runCrowd(characters, frames, &pool, &poolMs);
    std::printf("World::step():              hash %016llx, %.2f ms/frame\n",
                (unsigned long long)stepHash, stepMs);
    std::printf("host pool (%d + 1 threads): hash %016llx, %.2f ms/frame\n", workers,
                (unsigned long long)poolHash, poolMs);
    if (poolHash != stepHash) {
        std::fprintf(stderr, "the host's job system gave another state than step()\n");
        return 1;
    }
    return 0;
}
