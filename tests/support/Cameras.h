#pragma once

#include <cmath>

#include "crowdcloth/core/Math.h"

namespace cc::test {

/// OpenGL-style perspective projection (column vectors, camera looks down -Z).
inline Mat4 perspective(double verticalFov, double aspect, double nearPlane, double farPlane) {
    const double f = 1.0 / std::tan(0.5 * verticalFov);
    Mat4 p = Mat4::Zero();
    p(0, 0) = f / aspect;
    p(1, 1) = f;
    p(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
    p(2, 3) = 2.0 * farPlane * nearPlane / (nearPlane - farPlane);
    p(3, 2) = -1.0;
    return p;
}

/// World -> view transform of a camera at `eye` looking at `target`, Y up.
inline Mat4 lookAt(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitY()) {
    const Vec3 forward = (target - eye).normalized();
    const Vec3 right = forward.cross(up).normalized();
    const Vec3 trueUp = right.cross(forward);
    Mat4 v = Mat4::Identity();
    v.block<1, 3>(0, 0) = right.transpose();
    v.block<1, 3>(1, 0) = trueUp.transpose();
    v.block<1, 3>(2, 0) = -forward.transpose();
    v(0, 3) = -right.dot(eye);
    v(1, 3) = -trueUp.dot(eye);
    v(2, 3) = forward.dot(eye);
    return v;
}

} // namespace cc::test
