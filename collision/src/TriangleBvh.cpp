#include "crowdcloth/collision/TriangleBvh.h"

#include <algorithm>

namespace cc::collision {

namespace {
constexpr uint32_t kLeafSize = 4;
}

void TriangleBvh::build(Span<const Aabb> boxes) {
    mNodes.clear();
    mBoxes.assign(boxes.begin(), boxes.end());
    mOrder.resize(boxes.size());
    for (uint32_t i = 0; i < mOrder.size(); ++i) mOrder[i] = i;
    if (boxes.empty()) return;
    std::vector<Vec3> centres(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i) centres[i] = 0.5 * (boxes[i].lo + boxes[i].hi);
    mNodes.reserve(2 * boxes.size() / kLeafSize + 2);
    mNodes.emplace_back();
    buildNode(boxes, centres, 0, 0, static_cast<uint32_t>(boxes.size()));
}

void TriangleBvh::buildNode(Span<const Aabb> boxes, const std::vector<Vec3>& centres, uint32_t node,
                            uint32_t begin, uint32_t end) {
    Aabb box, centreBox;
    for (uint32_t i = begin; i < end; ++i) {
        box.grow(boxes[mOrder[i]].lo);
        box.grow(boxes[mOrder[i]].hi);
        centreBox.grow(centres[mOrder[i]]);
    }
    mNodes[node].box = box;
    if (end - begin <= kLeafSize) {
        mNodes[node].first = begin;
        mNodes[node].count = end - begin;
        return;
    }
    int axis = 0;
    const Vec3 extent = centreBox.hi - centreBox.lo;
    if (extent.y() > extent[axis]) axis = 1;
    if (extent.z() > extent[axis]) axis = 2;
    const uint32_t mid = begin + (end - begin) / 2;
    // Median split with the primitive index as tie-break: the tree depends only on the input.
    std::nth_element(mOrder.begin() + begin, mOrder.begin() + mid, mOrder.begin() + end,
                     [&](uint32_t a, uint32_t b) {
                         if (centres[a][axis] != centres[b][axis]) return centres[a][axis] < centres[b][axis];
                         return a < b;
                     });
    // Children are appended in pairs after their parent, so refit() can sweep the array backwards.
    const uint32_t left = static_cast<uint32_t>(mNodes.size());
    mNodes.emplace_back();
    mNodes.emplace_back();
    mNodes[node].first = left;
    mNodes[node].count = 0;
    buildNode(boxes, centres, left, begin, mid);
    buildNode(boxes, centres, left + 1, mid, end);
}

void TriangleBvh::refit(Span<const Aabb> boxes) {
    mBoxes.assign(boxes.begin(), boxes.end());
    for (std::size_t n = mNodes.size(); n-- > 0;) {
        Node& node = mNodes[n];
        Aabb box;
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                box.grow(boxes[mOrder[i]].lo);
                box.grow(boxes[mOrder[i]].hi);
            }
        } else {
            for (uint32_t c = node.first; c < node.first + 2; ++c) {
                box.grow(mNodes[c].box.lo);
                box.grow(mNodes[c].box.hi);
            }
        }
        node.box = box;
    }
}

void TriangleBvh::query(const Aabb& query, std::vector<uint32_t>& outHits) const {
    if (mNodes.empty()) return;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = mNodes[stack[--top]];
        if (!node.box.overlaps(query)) continue;
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                if (mBoxes[mOrder[i]].overlaps(query)) outHits.push_back(mOrder[i]);
            }
        } else {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
}

bool TriangleBvh::overlappingPairs(std::vector<std::array<uint32_t, 2>>& outPairs, std::size_t maxPairs) {
    return descend({}, outPairs, maxPairs);
}

bool TriangleBvh::overlappingPairs(Span<const uint8_t> marked, std::vector<std::array<uint32_t, 2>>& outPairs,
                                   std::size_t maxPairs) {
    if (marked.size() != mOrder.size()) return true;
    // Which nodes hold a marked primitive: children follow their parents, so sweep backwards.
    mNodeMarked.assign(mNodes.size(), 0);
    for (std::size_t n = mNodes.size(); n-- > 0;) {
        const Node& node = mNodes[n];
        uint8_t any = 0;
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) any |= marked[mOrder[i]] != 0;
        } else {
            any = mNodeMarked[node.first] | mNodeMarked[node.first + 1];
        }
        mNodeMarked[n] = any;
    }
    return descend(marked, outPairs, maxPairs);
}

bool TriangleBvh::descend(Span<const uint8_t> marked, std::vector<std::array<uint32_t, 2>>& outPairs,
                          std::size_t maxPairs) {
    if (mNodes.empty()) return true;
    const std::size_t limit = maxPairs > SIZE_MAX - outPairs.size() ? SIZE_MAX : outPairs.size() + maxPairs;
    const bool all = marked.empty();
    auto wanted = [&](uint32_t i, uint32_t j) { return all || marked[i] || marked[j]; };
    std::vector<std::array<uint32_t, 2>>& stack = mPairStack;
    stack.clear();
    stack.push_back({0, 0});
    while (!stack.empty()) {
        if (outPairs.size() > limit) return false;
        const auto [ia, ib] = stack.back();
        stack.pop_back();
        if (!all && !mNodeMarked[ia] && !mNodeMarked[ib]) continue;
        const Node& a = mNodes[ia];
        const Node& b = mNodes[ib];
        if (ia == ib) {
            if (a.count > 0) {
                for (uint32_t i = a.first; i < a.first + a.count; ++i)
                    for (uint32_t j = i + 1; j < a.first + a.count; ++j)
                        if (wanted(mOrder[i], mOrder[j]) && mBoxes[mOrder[i]].overlaps(mBoxes[mOrder[j]]))
                            outPairs.push_back({std::min(mOrder[i], mOrder[j]), std::max(mOrder[i], mOrder[j])});
            } else {
                stack.push_back({a.first, a.first});
                stack.push_back({a.first + 1, a.first + 1});
                stack.push_back({a.first, a.first + 1});
            }
            continue;
        }
        if (!a.box.overlaps(b.box)) continue;
        if (a.count > 0 && b.count > 0) {
            for (uint32_t i = a.first; i < a.first + a.count; ++i)
                for (uint32_t j = b.first; j < b.first + b.count; ++j)
                    if (wanted(mOrder[i], mOrder[j]) && mBoxes[mOrder[i]].overlaps(mBoxes[mOrder[j]]))
                        outPairs.push_back({std::min(mOrder[i], mOrder[j]), std::max(mOrder[i], mOrder[j])});
        } else if (b.count > 0 || (a.count == 0 && ia < ib)) {
            // Descend the inner node (the earlier one when both are inner: it is the larger).
            stack.push_back({a.first, ib});
            stack.push_back({a.first + 1, ib});
        } else {
            stack.push_back({ia, b.first});
            stack.push_back({ia, b.first + 1});
        }
    }
    return outPairs.size() <= limit;
}

} // namespace cc::collision
