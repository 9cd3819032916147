#pragma once
// A perspective camera at `eye` looking at `target`, Y up (the samples' views, the error studies'
// cameras).

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace cc {

/// Column-major OpenGL view-projection of a camera with vertical field of view fovDegrees.
inline void lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double aspect, double out[16],
                   double fovDegrees = 60.0, double nearM = 0.1, double farM = 1000.0) {
    const Eigen::Vector3d f = (target - eye).normalized();
    const Eigen::Vector3d s = f.cross(Eigen::Vector3d::UnitY()).normalized();
    const Eigen::Vector3d u = s.cross(f);
    Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
    view.block<1, 3>(0, 0) = s.transpose();
    view.block<1, 3>(1, 0) = u.transpose();
    view.block<1, 3>(2, 0) = -f.transpose();
    view(0, 3) = -s.dot(eye);
    view(1, 3) = -u.dot(eye);
    view(2, 3) = f.dot(eye);
    const double fy = 1.0 / std::tan(0.5 * fovDegrees * M_PI / 180.0);
    Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
    proj(0, 0) = fy / aspect;
    proj(1, 1) = fy;
    proj(2, 2) = (farM + nearM) / (nearM - farM);
    proj(2, 3) = 2.0 * farM * nearM / (nearM - farM);
    proj(3, 2) = -1.0;
    const Eigen::Matrix4d vp = proj * view;
    for (int k = 0; k < 16; ++k) out[k] = vp(k % 4, k / 4);
}

} // namespace cc
