#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "crowdcloth/World.h"

namespace crowd {

inline double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t k = std::min(v.size() - 1, std::size_t(std::ceil(p * double(v.size())) - 1));
    return v[k];
}

struct WorldDeleter {
    void operator()(cc::World* w) const { cc::World::destroy(w); }
};
using WorldPtr = std::unique_ptr<cc::World, WorldDeleter>;

/// Column-major OpenGL view-projection of a 60-degree camera at `eye` looking at `target`, Y up.
inline void lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double aspect, double out[16]) {
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
    const double fy = 1.0 / std::tan(0.5 * 60.0 * M_PI / 180.0), n = 0.1, fz = 1000.0;
    Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
    proj(0, 0) = fy / aspect;
    proj(1, 1) = fy;
    proj(2, 2) = (fz + n) / (n - fz);
    proj(2, 3) = 2.0 * fz * n / (n - fz);
    proj(3, 2) = -1.0;
    const Eigen::Matrix4d vp = proj * view;
    for (int k = 0; k < 16; ++k) out[k] = vp(k % 4, k / 4);
}

/// Crowd scaling: 10 -> 1000 characters with LOD and at full resolution, and 1 -> 2 threads.
int runScaling(double budgetMs, int threads);
/// A cape on a walking mannequin at each uniform level against the finest one.
int runTradeoff();
/// 256 capes at level 3 on walking mannequins stepped one by one and in batches (BAR batch).
int runBatchBench();

} // namespace crowd
