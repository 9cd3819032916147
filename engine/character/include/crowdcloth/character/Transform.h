#pragma once

#include "crowdcloth/core/Math.h"

namespace cc {

using Quat = Eigen::Quaterniond;
using Mat4 = Eigen::Matrix4d;

/// A joint's local transform as translation * rotation * scale (the glTF/assimp TRS order).
struct Transform {
    Vec3 translation = Vec3::Zero();  ///< [m]
    Quat rotation = Quat::Identity(); ///< unit quaternion
    Vec3 scale = Vec3::Ones();        ///< [-] per axis; > 0

    /// The 4x4 affine matrix T * R * S.
    Mat4 matrix() const;
    bool isFinite() const;
};

/// Spherical linear interpolation along the shorter arc; t in [0, 1]. Returns a unit quaternion.
Quat slerpShortest(const Quat& a, const Quat& b, double t);

/// Componentwise blend: linear for translation and scale, slerp for rotation.
Transform interpolate(const Transform& a, const Transform& b, double t);

/// Inverse of an affine matrix (bottom row 0 0 0 1), keeping that bottom row exact.
Mat4 affineInverse(const Mat4& m);

/// True when every entry of m is finite.
bool isFinite(const Mat4& m);

} // namespace cc
