#include "crowdcloth/core/RectanglePanel.h"

#include <cmath>
#include <string>

namespace cc {

Status RectanglePanel::validate() const {
    if (!(width > 0.0) || !std::isfinite(width)) {
        return Status::invalidArgument("RectanglePanel.width must be finite and > 0, got " +
                                       std::to_string(width));
    }
    if (!(height > 0.0) || !std::isfinite(height)) {
        return Status::invalidArgument("RectanglePanel.height must be finite and > 0, got " +
                                       std::to_string(height));
    }
    if (columns < 1 || rows < 1) return Status::invalidArgument("RectanglePanel.columns and rows must be >= 1");
    if (uint64_t(columns + 1) * uint64_t(rows + 1) > (1ull << 24)) {
        return Status::invalidArgument("RectanglePanel resolution exceeds 16M vertices");
    }
    if (!isFinite(origin)) return Status::invalidArgument("RectanglePanel.origin is not finite");
    if (!isFinite(vAxis) || std::abs(vAxis.norm() - 1.0) > 1e-9 || std::abs(vAxis.x()) > 1e-9) {
        return Status::invalidArgument("RectanglePanel.vAxis must be a unit vector orthogonal to X");
    }
    return Status::ok();
}

Result<ClothMesh> RectanglePanel::build() const {
    if (Status s = validate(); !s) return s;
    ClothMesh mesh;
    const uint32_t nu = columns + 1, nv = rows + 1;
    mesh.restPositions.reserve(nu * nv);
    mesh.positions.reserve(nu * nv);
    for (uint32_t j = 0; j < nv; ++j) {
        for (uint32_t i = 0; i < nu; ++i) {
            const Vec2 uv(width * i / columns, height * j / rows);
            mesh.restPositions.push_back(uv);
            mesh.positions.push_back(origin + uv.x() * Vec3::UnitX() + uv.y() * vAxis);
        }
    }
    mesh.triangles.reserve(2 * columns * rows);
    for (uint32_t j = 0; j < rows; ++j) {
        for (uint32_t i = 0; i < columns; ++i) {
            const uint32_t a = vertexIndex(i, j), b = vertexIndex(i + 1, j);
            const uint32_t c = vertexIndex(i, j + 1), d = vertexIndex(i + 1, j + 1);
            // Diagonals alternate like a checkerboard, giving the 4-8 (Union Jack) pattern.
            if ((i + j) % 2 == 0) {
                mesh.triangles.push_back({a, b, d});
                mesh.triangles.push_back({a, d, c});
            } else {
                mesh.triangles.push_back({a, b, c});
                mesh.triangles.push_back({b, d, c});
            }
        }
    }
    return mesh;
}

} // namespace cc
