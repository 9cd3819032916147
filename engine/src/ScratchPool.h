#pragma once

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace cc::detail {

/// Scratch objects (solver workspaces, contact stages) for the tasks that run at once. A task
/// borrows one and gives it back, so the World keeps as many as ever ran together (about one per
/// thread), each grown to the largest job it met. Kept with each batch slot or each garment
/// instead, every one of them grew in turn to the largest job it ever had, and the live heap of a
/// long crowd run crept up by megabytes per camera loop (heaptrack, 20 s against 60 s). Which
/// object a task gets changes no result: their users size and write every entry before reading
/// it. Borrowing allocates only when more tasks run at once than ever before; thread-safe.
template <typename T>
class ScratchPool {
public:
    /// A borrowed object, given back when it goes out of scope.
    class Lease {
    public:
        Lease(ScratchPool& pool, std::unique_ptr<T> object) : mPool(&pool), mObject(std::move(object)) {}
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        ~Lease() { mPool->giveBack(std::move(mObject)); }
        T& operator*() const { return *mObject; }

    private:
        ScratchPool* mPool;
        std::unique_ptr<T> mObject;
    };

    Lease borrow() {
        std::unique_ptr<T> object;
        {
            const std::lock_guard<std::mutex> lock(mMutex);
            if (!mSpare.empty()) {
                object = std::move(mSpare.back());
                mSpare.pop_back();
            }
        }
        if (!object) object = std::make_unique<T>();
        return Lease(*this, std::move(object));
    }

private:
    void giveBack(std::unique_ptr<T> object) {
        const std::lock_guard<std::mutex> lock(mMutex);
        mSpare.push_back(std::move(object));
    }

    std::mutex mMutex;
    std::vector<std::unique_ptr<T>> mSpare;
};

} // namespace cc::detail
