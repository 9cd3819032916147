#include "crowdcloth/cloth/ConstraintSet.h"

#include <cmath>
#include <string>

namespace cc::cloth {

ConstraintSet::ConstraintSet(uint32_t n)
    : mKind(n, ConstraintKind::Free), mPoint(n, Vec3::Zero()), mNormal(n, Vec3::Zero()) {}

Status ConstraintSet::checkVertex(uint32_t v, const char* what) const {
    if (v >= vertexCount()) {
        return Status::invalidArgument(std::string(what) + ": vertex " + std::to_string(v) +
                                       " out of range (garment has " + std::to_string(vertexCount()) + ")");
    }
    return Status::ok();
}

Status ConstraintSet::pin(uint32_t v, const Vec3& position) {
    if (Status s = checkVertex(v, "pin/setTarget"); !s) return s;
    if (!isFinite(position)) {
        return Status::invalidArgument("pin/setTarget: vertex " + std::to_string(v) + " given a non-finite position");
    }
    mKind[v] = ConstraintKind::Target;
    mPoint[v] = position;
    return Status::ok();
}

Status ConstraintSet::setContactPlane(uint32_t v, const Vec3& point, const Vec3& normal) {
    if (Status s = checkVertex(v, "setContactPlane"); !s) return s;
    if (!isFinite(point) || !isFinite(normal) || std::abs(normal.norm() - 1.0) > 1e-6) {
        return Status::invalidArgument("setContactPlane: vertex " + std::to_string(v) +
                                       " needs a finite point and a unit normal");
    }
    mKind[v] = ConstraintKind::ContactPlane;
    mPoint[v] = point;
    mNormal[v] = normal;
    return Status::ok();
}

void ConstraintSet::release(uint32_t v) {
    if (v < vertexCount()) mKind[v] = ConstraintKind::Free;
}

void ConstraintSet::clearContactPlanes() {
    for (auto& k : mKind) {
        if (k == ConstraintKind::ContactPlane) k = ConstraintKind::Free;
    }
}

VertexFilter ConstraintSet::filter(uint32_t v, const Vec3& x0, const Vec3& v0, double h, Vec3& outZ) const {
    VertexFilter f;
    f.kind = mKind[v];
    outZ.setZero();
    if (f.kind == ConstraintKind::Target) {
        outZ = (mPoint[v] - x0) / h - v0;
    } else if (f.kind == ConstraintKind::ContactPlane) {
        const Vec3& n = mNormal[v];
        const double depth = -(x0 - mPoint[v]).dot(n);  // > 0 when the vertex is inside
        const double vn = v0.dot(n);
        if (depth <= 0.0 && vn >= 0.0) {
            f.kind = ConstraintKind::Free;  // outside and leaving: no contact this step
        } else {
            f.normal = n;
            // The normal velocity after the step just removes the penetration (0 when touching).
            outZ = n * (std::max(depth, 0.0) / h - vn);
        }
    }
    return f;
}

} // namespace cc::cloth
