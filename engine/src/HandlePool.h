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

private:
    struct Slot {
        std::unique_ptr<T> object;
        uint32_t generation = 1;
    };
    std::vector<Slot> mSlots;
    std::vector<uint32_t> mFree;
};

} // namespace cc::detail
