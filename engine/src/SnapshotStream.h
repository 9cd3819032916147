#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "crowdcloth/core/Hash.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc::detail {

/// A snapshot's header: magic (8 bytes), format version and byte-order mark (4 each), payload size
/// and the payload's FNV-1a checksum (8 each); the payload follows.
constexpr std::size_t kSnapshotHeaderBytes = 32;
constexpr std::size_t kSnapshotChecksumOffset = 24;

/// Writes the checksum of the payload into the header (tests and fuzzers that damage a payload
/// on purpose reseal it, so the reader meets the damage rather than the checksum).
inline void sealSnapshot(std::vector<uint8_t>& bytes) {
    if (bytes.size() < kSnapshotHeaderBytes) return;
    const uint64_t sum = hashBytes(bytes.data() + kSnapshotHeaderBytes, bytes.size() - kSnapshotHeaderBytes);
    std::memcpy(bytes.data() + kSnapshotChecksumOffset, &sum, sizeof sum);
}

/// Bytes of a World snapshot, written in the host's byte order (the header records it): scalars
/// as their bytes, vectors as a u64 count then the elements, sections as a four-letter tag.
class SnapshotWriter {
public:
    template <typename T>
    void put(const T& value) {
        static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>, "scalars only");
        const auto* p = reinterpret_cast<const uint8_t*>(&value);
        mBytes.insert(mBytes.end(), p, p + sizeof(T));
    }
    void put(const Vec3& v) { put(v.x()), put(v.y()), put(v.z()); }
    void put(const std::string& s) {
        put(uint64_t(s.size()));
        mBytes.insert(mBytes.end(), s.begin(), s.end());
    }
    template <typename T>
    void putVector(const std::vector<T>& values) {
        put(uint64_t(values.size()));
        if constexpr (std::is_same_v<T, Vec3> || std::is_arithmetic_v<T>) {  // contiguous: one copy
            static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
            const auto* p = reinterpret_cast<const uint8_t*>(values.data());
            mBytes.insert(mBytes.end(), p, p + values.size() * sizeof(T));
        } else {
            for (const T& v : values) put(v);
        }
    }
    /// A section's tag: a reader that meets another one names both.
    void tag(const char (&name)[5]) { mBytes.insert(mBytes.end(), name, name + 4); }

    void reserve(std::size_t bytes) { mBytes.reserve(bytes); }
    std::vector<uint8_t>& bytes() { return mBytes; }

private:
    std::vector<uint8_t> mBytes;
};

/// Reads what SnapshotWriter wrote. Every read is bounds-checked; the first failure sticks and
/// names the section and the byte offset, later reads return zeros. A count is checked against
/// the bytes left before anything is allocated, so a forged count cannot ask for gigabytes.
class SnapshotReader {
public:
    SnapshotReader(const uint8_t* data, std::size_t size) : mData(data), mSize(size) {}

    template <typename T>
    T get() {
        static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>, "scalars only");
        T value{};
        if (take(sizeof(T))) std::memcpy(&value, mData + mOffset - sizeof(T), sizeof(T));
        return value;
    }
    Vec3 getVec3() {
        const double x = get<double>(), y = get<double>(), z = get<double>();
        return Vec3(x, y, z);
    }
    /// A finite double (else the read fails naming `what`).
    double getFinite(const char* what) {
        const double v = get<double>();
        if (!std::isfinite(v)) fail(std::string(what) + " is not finite");
        return std::isfinite(v) ? v : 0.0;
    }
    Vec3 getFiniteVec3(const char* what) {
        const Vec3 v = getVec3();
        if (!isFinite(v)) fail(std::string(what) + " is not finite");
        return isFinite(v) ? v : Vec3::Zero();
    }
    std::string getString() {
        const uint64_t n = count(1);
        std::string s;
        if (take(n)) s.assign(reinterpret_cast<const char*>(mData + mOffset - n), n);
        return s;
    }
    /// A count of elements of at least `elementBytes` each, which must fit in what is left.
    uint64_t count(std::size_t elementBytes) {
        const uint64_t n = get<uint64_t>();
        if (ok() && elementBytes > 0 && n > (mSize - mOffset) / elementBytes) {
            fail("a count of " + std::to_string(n) + " elements runs past the end");
            return 0;
        }
        return n;
    }
    template <typename T>
    std::vector<T> getVector() {
        static_assert(std::is_arithmetic_v<T>, "scalars only");
        std::vector<T> values(count(sizeof(T)));
        if (!take(values.size() * sizeof(T))) return {};
        if (!values.empty())
            std::memcpy(values.data(), mData + mOffset - values.size() * sizeof(T), values.size() * sizeof(T));
        return values;
    }
    std::vector<Vec3> getFiniteVec3s(const char* what) {
        std::vector<Vec3> values(count(sizeof(Vec3)));
        if (!take(values.size() * sizeof(Vec3))) return {};
        const std::size_t bytes = values.size() * sizeof(Vec3);
        if (!values.empty()) std::memcpy(static_cast<void*>(values.data()), mData + mOffset - bytes, bytes);
        for (const Vec3& v : values)
            if (!isFinite(v)) {
                fail(std::string(what) + " is not finite");
                return {};
            }
        return values;
    }
    /// Expects the section `name` next.
    void expectTag(const char (&name)[5]) {
        mSection = name;
        if (!take(4)) return;
        if (std::memcmp(mData + mOffset - 4, name, 4) != 0)
            fail("expected the section '" + std::string(name) + "', found '" +
                 std::string(reinterpret_cast<const char*>(mData + mOffset - 4), 4) + "'");
    }

    /// Fails the read (the first failure is kept).
    void fail(const std::string& why) {
        if (!mError.empty()) return;
        mError = "section '" + mSection + "', byte " + std::to_string(mOffset) + ": " + why;
    }
    bool ok() const { return mError.empty(); }
    const std::string& error() const { return mError; }
    bool atEnd() const { return mOffset == mSize; }
    std::size_t offset() const { return mOffset; }

private:
    bool take(std::size_t n) {
        if (!ok()) return false;
        if (n > mSize - mOffset) {
            fail("truncated: " + std::to_string(n) + " more bytes needed, " + std::to_string(mSize - mOffset) + " left");
            return false;
        }
        mOffset += n;
        return true;
    }
    const uint8_t* mData;
    std::size_t mSize;
    std::size_t mOffset = 0;
    std::string mSection = "header";
    std::string mError;
};

} // namespace cc::detail
