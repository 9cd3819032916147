#include "CharacterBlob.h"

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace cc::detail {
namespace {

constexpr uint32_t kMagic = 0x43434348;  // "HCCC": crowdcloth character

class Writer {
public:
    template <typename T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        mOut.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    void text(const std::string& s) {
        pod(uint64_t(s.size()));
        mOut.append(s);
    }
    void vec(const Vec3& v) {
        for (int k = 0; k < 3; ++k) pod(v[k]);
    }
    void quat(const Quat& q) {
        for (double c : {q.w(), q.x(), q.y(), q.z()}) pod(c);
    }
    void mat(const Mat4& m) {
        for (int k = 0; k < 16; ++k) pod(m(k % 4, k / 4));
    }
    std::string take() { return std::move(mOut); }

private:
    std::string mOut;
};

class Reader {
public:
    explicit Reader(const std::string& in) : mIn(in) {}
    bool ok() const { return mOk; }
    template <typename T>
    T pod() {
        T v{};
        if (!mOk || mAt + sizeof(T) > mIn.size()) {
            mOk = false;
            return v;
        }
        std::memcpy(&v, mIn.data() + mAt, sizeof(T));
        mAt += sizeof(T);
        return v;
    }
    /// A count of elements of at least `elementBytes` each: never more than the bytes left.
    std::size_t count(std::size_t elementBytes) {
        const uint64_t n = pod<uint64_t>();
        if (!mOk || n > (mIn.size() - mAt) / std::max<std::size_t>(elementBytes, 1)) {
            mOk = false;
            return 0;
        }
        return std::size_t(n);
    }
    std::string text() {
        const std::size_t n = count(1);
        if (!mOk) return {};
        std::string s = mIn.substr(mAt, n);
        mAt += n;
        return s;
    }
    Vec3 vec() {
        const double x = pod<double>(), y = pod<double>(), z = pod<double>();
        return Vec3(x, y, z);
    }
    Quat quat() {
        const double w = pod<double>(), x = pod<double>(), y = pod<double>(), z = pod<double>();
        return Quat(w, x, y, z);
    }
    Mat4 mat() {
        Mat4 m;
        for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = pod<double>();
        return m;
    }
    bool atEnd() const { return mAt == mIn.size(); }

private:
    const std::string& mIn;
    std::size_t mAt = 0;
    bool mOk = true;
};

template <typename T, typename Put>
void list(Writer& w, const std::vector<T>& values, Put put) {
    w.pod(uint64_t(values.size()));
    for (const T& v : values) put(v);
}

template <typename T, typename Get>
void list(Reader& r, std::size_t elementBytes, std::vector<T>& out, Get get) {
    const std::size_t n = r.count(elementBytes);
    out.clear();
    out.reserve(n);
    for (std::size_t i = 0; i < n && r.ok(); ++i) out.push_back(get());
}

} // namespace

std::string serializeCharacter(const Character& c) {
    Writer w;
    w.pod(kMagic);
    w.text(c.name);
    list(w, c.skeleton.joints, [&](const Joint& j) {
        w.text(j.name);
        w.pod(j.parent);
        w.vec(j.restLocal.translation);
        w.quat(j.restLocal.rotation);
        w.vec(j.restLocal.scale);
    });
    const SkinnedMesh& b = c.body;
    list(w, b.bindPositions, [&](const Vec3& p) { w.vec(p); });
    list(w, b.bindNormals, [&](const Vec3& n) { w.vec(n); });
    list(w, b.triangles, [&](const std::array<uint32_t, 3>& t) { w.pod(t); });
    list(w, b.jointIndices, [&](const std::array<uint16_t, kMaxInfluences>& j) { w.pod(j); });
    list(w, b.jointWeights, [&](const std::array<double, kMaxInfluences>& wt) { w.pod(wt); });
    list(w, b.inverseBindMatrices, [&](const Mat4& m) { w.mat(m); });
    list(w, c.clips, [&](const AnimationClip& clip) {
        w.text(clip.name);
        w.pod(clip.duration);
        w.vec(clip.rootVelocity);
        list(w, clip.channels, [&](const JointChannel& ch) {
            w.pod(ch.joint);
            list(w, ch.translationTimes, [&](double t) { w.pod(t); });
            list(w, ch.translations, [&](const Vec3& v) { w.vec(v); });
            list(w, ch.rotationTimes, [&](double t) { w.pod(t); });
            list(w, ch.rotations, [&](const Quat& q) { w.quat(q); });
            list(w, ch.scaleTimes, [&](double t) { w.pod(t); });
            list(w, ch.scales, [&](const Vec3& v) { w.vec(v); });
        });
    });
    return w.take();
}

Result<Character> deserializeCharacter(const std::string& bytes) {
    Reader r(bytes);
    if (r.pod<uint32_t>() != kMagic) return Status::invalidArgument("not a character blob");
    Character c;
    c.name = r.text();
    list(r, 8 + 4 + 80, c.skeleton.joints, [&] {
        Joint j;
        j.name = r.text();
        j.parent = r.pod<int32_t>();
        j.restLocal.translation = r.vec();
        j.restLocal.rotation = r.quat();
        j.restLocal.scale = r.vec();
        return j;
    });
    SkinnedMesh& b = c.body;
    list(r, 24, b.bindPositions, [&] { return r.vec(); });
    list(r, 24, b.bindNormals, [&] { return r.vec(); });
    list(r, 12, b.triangles, [&] { return r.pod<std::array<uint32_t, 3>>(); });
    list(r, 8, b.jointIndices, [&] { return r.pod<std::array<uint16_t, kMaxInfluences>>(); });
    list(r, 32, b.jointWeights, [&] { return r.pod<std::array<double, kMaxInfluences>>(); });
    list(r, 128, b.inverseBindMatrices, [&] { return r.mat(); });
    list(r, 8 + 8 + 24 + 8, c.clips, [&] {
        AnimationClip clip;
        clip.name = r.text();
        clip.duration = r.pod<double>();
        clip.rootVelocity = r.vec();
        list(r, 4 + 6 * 8, clip.channels, [&] {
            JointChannel ch;
            ch.joint = r.pod<int32_t>();
            list(r, 8, ch.translationTimes, [&] { return r.pod<double>(); });
            list(r, 24, ch.translations, [&] { return r.vec(); });
            list(r, 8, ch.rotationTimes, [&] { return r.pod<double>(); });
            list(r, 32, ch.rotations, [&] { return r.quat(); });
            list(r, 8, ch.scaleTimes, [&] { return r.pod<double>(); });
            list(r, 24, ch.scales, [&] { return r.vec(); });
            return ch;
        });
        return clip;
    });
    if (!r.ok() || !r.atEnd()) return Status::invalidArgument("the character blob is cut short or corrupt");
    return c;
}

} // namespace cc::detail
