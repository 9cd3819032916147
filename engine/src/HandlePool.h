#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace cc::detail {

/// Objects addressed by (index + 1, generation) handles: a removed slot bumps its generation, so
/// an old handle to it is recognised as stale after the slot is reused (Box2D's id scheme).
/// Iteration order is slot order, which is deterministic for a given call sequence.
template <typename T>
class HandlePool {
public:
    struct Handle {
        uint32_t index1 = 0;
        uint32_t generation = 0;
    };

    template <typename Id>
    T* get(const Id& id) const {
        if (id.index1 == 0 || id.index1 > mSlots.size()) return nullptr;
        const Slot& slot = mSlots[id.index1 - 1];
        return slot.object && slot.generation == id.generation ? slot.object.get() : nullptr;
    }

    Handle add(std::unique_ptr<T> object) {
        uint32_t index;
        if (!mFree.empty()) {
            index = mFree.back();
            mFree.pop_back();
        } else {
            index = static_cast<uint32_t>(mSlots.size());
            mSlots.push_back({});
        }
        mSlots[index].object = std::move(object);
        return {index + 1, mSlots[index].generation};
    }

    template <typename Id>
    bool remove(const Id& id) {
        if (!get(id)) return false;
        Slot& slot = mSlots[id.index1 - 1];
        slot.object.reset();
        ++slot.generation;
        mFree.push_back(id.index1 - 1);
        return true;
    }

    /// Calls f(handle, object) for every live object, in slot order.
    template <typename F>
    void forEach(F&& f) const {
        for (uint32_t i = 0; i < mSlots.size(); ++i)
            if (mSlots[i].object) f(Handle{i + 1, mSlots[i].generation}, *mSlots[i].object);
    }

    std::size_t size() const { return mSlots.size() - mFree.size(); }

    // The layout (every slot's generation, the free slots in reuse order), for snapshots: a pool
    // rebuilt with it hands out the same handles from then on.
    uint32_t slotCount() const { return static_cast<uint32_t>(mSlots.size()); }
    uint32_t generationAt(uint32_t slot) const { return mSlots[slot].generation; }
    const std::vector<uint32_t>& freeSlots() const { return mFree; }
    /// Empties the pool into `generations.size()` slots, `free` of them free (in reuse order); the
    /// others are filled by put(). False when `free` repeats or names a slot out of range.
    bool resetLayout(const std::vector<uint32_t>& generations, const std::vector<uint32_t>& free) {
        std::vector<uint8_t> isFree(generations.size(), 0);
        for (uint32_t f : free) {
            if (f >= generations.size() || isFree[f]) return false;
            isFree[f] = 1;
        }
        mSlots.clear();
        mSlots.resize(generations.size());
        for (std::size_t i = 0; i < generations.size(); ++i) mSlots[i].generation = generations[i];
        mFree = free;
        return true;
    }
    /// Fills a slot resetLayout() left live; false when it is free, filled or out of range.
    bool put(uint32_t slot, std::unique_ptr<T> object) {
        if (slot >= mSlots.size() || mSlots[slot].object) return false;
        for (uint32_t f : mFree)
            if (f == slot) return false;
        mSlots[slot].object = std::move(object);
        return true;
    }
    /// Every slot that is not free holds an object (after resetLayout() and put()).
    bool complete() const {
        std::size_t live = 0;
        for (const Slot& s : mSlots) live += s.object != nullptr;
        return live + mFree.size() == mSlots.size();
    }

private:
    struct Slot {
        std::unique_ptr<T> object;
        uint32_t generation = 1;
    };
    std::vector<Slot> mSlots;
    std::vector<uint32_t> mFree;
};

} // namespace cc::detail
