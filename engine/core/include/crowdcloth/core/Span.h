#pragma once

#include <cstddef>
#include <vector>

namespace cc {

/// Non-owning view of a contiguous array; mirrors C++20 std::span for a C++17 code base.
template <typename T>
class Span {
public:
    constexpr Span() = default;
    constexpr Span(T* data, std::size_t size) : mData(data), mSize(size) {}
    template <std::size_t N>
    constexpr Span(T (&array)[N]) : mData(array), mSize(N) {}
    template <typename U>
    Span(std::vector<U>& v) : mData(v.data()), mSize(v.size()) {}
    template <typename U>
    Span(const std::vector<U>& v) : mData(v.data()), mSize(v.size()) {}

    constexpr T* data() const { return mData; }
    constexpr std::size_t size() const { return mSize; }
    constexpr bool empty() const { return mSize == 0; }
    constexpr T& operator[](std::size_t i) const { return mData[i]; }
    constexpr T* begin() const { return mData; }
    constexpr T* end() const { return mData + mSize; }

private:
    T* mData = nullptr;
    std::size_t mSize = 0;
};

} // namespace cc
