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

VertexFilter ConstraintSet::filter(uint32_t v, const Vec3& x0, const Vec3& v0, double h, const Vec3& goal,
                                   Vec3& outZ) const {
    VertexFilter f;
    f.kind = mKind[v];
    outZ.setZero();
    if (f.kind == ConstraintKind::Target) {
        outZ = (goal - x0) / h - v0;
    } else if (f.kind == ConstraintKind::ContactPlane) {
        const Vec3& n = mNormal[v];
        const double gap = (x0 - mPoint[v]).dot(n);  // < 0 when the vertex is inside
        const double vn = v0.dot(n);
        if (gap > 0.0 && gap + h * vn >= 0.0) {
            f.kind = ConstraintKind::Free;  // outside and not reaching the plane at its velocity
        } else {
            // Inside: leave by the end of the step. Outside but crossing: land exactly on it.
            f.normal = n;
            outZ = n * (-gap / h - vn);
        }
    }
    return f;
}

} // namespace cc::cloth
