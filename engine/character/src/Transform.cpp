#include "crowdcloth/character/Transform.h"

#include <cmath>

namespace cc {

Mat4 Transform::matrix() const {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = rotation.normalized().toRotationMatrix() * scale.asDiagonal();
    m.topRightCorner<3, 1>() = translation;
    return m;
}

bool Transform::isFinite() const {
    return cc::isFinite(translation) && cc::isFinite(scale) && std::isfinite(rotation.w()) &&
           cc::isFinite(Vec3(rotation.vec()));
}

Quat slerpShortest(const Quat& a, const Quat& b, double t) {
    // Eigen's slerp already takes the shorter arc (it flips b when a.b < 0) and falls back to a
    // normalised lerp for nearly parallel quaternions.
    return a.slerp(t, b).normalized();
}

Transform interpolate(const Transform& a, const Transform& b, double t) {
    Transform r;
    r.translation = a.translation + t * (b.translation - a.translation);
    r.rotation = slerpShortest(a.rotation, b.rotation, t);
    r.scale = a.scale + t * (b.scale - a.scale);
    return r;
}

Mat4 affineInverse(const Mat4& m) {
    Mat4 r = Mat4::Identity();
    const Mat3 a = m.topLeftCorner<3, 3>().inverse();
    r.topLeftCorner<3, 3>() = a;
    r.topRightCorner<3, 1>() = -a * m.topRightCorner<3, 1>();
    return r;
}

bool isFinite(const Mat4& m) {
    return m.allFinite();
}

} // namespace cc
