#include "GarmentVisibility.h"

#include <Eigen/Core>

namespace crowd {

cc::Result<std::vector<bool>> garmentsInView(const cc::World& world, const Plaza& plaza) {
    // Frustum planes from the rows of the view-projection matrix (Gribb & Hartmann 2001).
    const Eigen::Map<const Eigen::Matrix4d> m(plaza.viewProjection());  // column-major, as OpenGL
    std::vector<Eigen::Vector4d> planes;
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {1.0, -1.0}) {
            Eigen::Vector4d plane = m.row(3).transpose() + sign * m.row(axis).transpose();
            const double norm = plane.head<3>().norm();
            if (norm > 0.0) planes.push_back(plane / norm);
        }
    std::vector<bool> inView;
    for (cc::GarmentId id : plaza.garments()) {
        auto mesh = world.renderMesh(id);
        if (!mesh.isOk()) return mesh.status();
        const cc::RenderMeshView& g = mesh.value();
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
        for (uint32_t v = 0; v < g.vertexCount; ++v) {
            const Eigen::Vector3d p(g.positions[3 * v], g.positions[3 * v + 1], g.positions[3 * v + 2]);
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        const Eigen::Vector4d centre(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), 0.5 * (lo.z() + hi.z()), 1.0);
        const double radius = 0.5 * (hi - lo).norm();
        bool visible = g.vertexCount > 0;
        for (const Eigen::Vector4d& plane : planes) visible = visible && plane.dot(centre) >= -radius;
        inView.push_back(visible);
    }
    return inView;
}

} // namespace crowd
