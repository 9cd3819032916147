#pragma once

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "crowdcloth/cloth/SubstepSolver.h"

namespace cc::detail {

/// Solver scratch for the batches that run at once. A batch borrows a workspace for its solve and
/// gives it back, so the World keeps as many as ever ran together (about one per thread), each
/// grown to the largest level it met. Kept with each batch slot instead, every one of a frame's
/// 70-odd slots grew in turn to the largest level any of its batches ever had, and the live heap
/// of a long crowd run crept up by megabytes per camera loop (heaptrack: the solver's arrays and
/// contact lists, 20 s against 60 s). Which workspace a batch gets changes no result: the solver
/// sizes and writes every entry before reading it (stepSubsteps). Borrowing allocates only when
/// more batches run at once than ever before; thread-safe.
class WorkspacePool {
public:
    /// A borrowed workspace, given back when it goes out of scope.
    class Lease {
    public:
        Lease(WorkspacePool& pool, std::unique_ptr<cloth::SubstepWorkspace> workspace)
            : mPool(&pool), mWorkspace(std::move(workspace)) {}
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        ~Lease() { mPool->giveBack(std::move(mWorkspace)); }
        cloth::SubstepWorkspace& operator*() const { return *mWorkspace; }

    private:
        WorkspacePool* mPool;
        std::unique_ptr<cloth::SubstepWorkspace> mWorkspace;
    };

    Lease borrow() {
        std::unique_ptr<cloth::SubstepWorkspace> workspace;
        {
            const std::lock_guard<std::mutex> lock(mMutex);
            if (!mSpare.empty()) {
                workspace = std::move(mSpare.back());
                mSpare.pop_back();
            }
        }
        if (!workspace) workspace = std::make_unique<cloth::SubstepWorkspace>();
        return Lease(*this, std::move(workspace));
    }

private:
    void giveBack(std::unique_ptr<cloth::SubstepWorkspace> workspace) {
        const std::lock_guard<std::mutex> lock(mMutex);
        mSpare.push_back(std::move(workspace));
    }

    std::mutex mMutex;
    std::vector<std::unique_ptr<cloth::SubstepWorkspace>> mSpare;
};

} // namespace cc::detail
