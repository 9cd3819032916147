#include "crowdcloth/cloth/ConstraintSet.h"

#include <cmath>
#include <string>

namespace cc::cloth {

Status Friction::validate() const {
    if (!(staticCoefficient >= 0.0 && staticCoefficient <= 10.0)) {
        return Status::invalidArgument("Friction.staticCoefficient = " + std::to_string(staticCoefficient) +
                                       " is outside [0, 10]");
    }
    if (!(kineticCoefficient >= 0.0 && kineticCoefficient <= staticCoefficient)) {
        return Status::invalidArgument("Friction.kineticCoefficient = " + std::to_string(kineticCoefficient) +
                                       " is outside [0, staticCoefficient = " + std::to_string(staticCoefficient) + "]");
    }
    return Status::ok();
}

ConstraintSet::ConstraintSet(uint32_t n)
    : mKind(n, ConstraintKind::Free), mPoint(n, Vec3::Zero()), mNormal(n, Vec3::Zero()),
      mSurfaceVelocity(n, Vec3::Zero()), mFriction(n) {}

namespace {
bool hasCoefficient(const Friction& f) { return f.staticCoefficient > 0.0 || f.kineticCoefficient > 0.0; }
} // namespace

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
    if (mKind[v] == ConstraintKind::ContactPlane && hasCoefficient(mFriction[v])) --mFrictionCount;
    mKind[v] = ConstraintKind::Target;
    mPoint[v] = position;
    return Status::ok();
}

Status ConstraintSet::setContactPlane(uint32_t v, const Vec3& point, const Vec3& normal, const Vec3& surfaceVelocity,
                                      const Friction& friction) {
    if (Status s = checkVertex(v, "setContactPlane"); !s) return s;
    if (!isFinite(point) || !isFinite(normal) || std::abs(normal.norm() - 1.0) > 1e-6) {
        return Status::invalidArgument("setContactPlane: vertex " + std::to_string(v) +
                                       " needs a finite point and a unit normal");
    }
    if (!isFinite(surfaceVelocity)) {
        return Status::invalidArgument("setContactPlane: vertex " + std::to_string(v) +
                                       " given a non-finite surface velocity");
    }
    if (Status s = friction.validate(); !s) {
        return Status::invalidArgument("setContactPlane: vertex " + std::to_string(v) + ": " + s.message());
    }
    if (mKind[v] == ConstraintKind::ContactPlane && hasCoefficient(mFriction[v])) --mFrictionCount;
    mKind[v] = ConstraintKind::ContactPlane;
    mPoint[v] = point;
    mNormal[v] = normal;
    mSurfaceVelocity[v] = surfaceVelocity;
    mFriction[v] = friction;
    if (hasCoefficient(friction)) ++mFrictionCount;
    return Status::ok();
}

void ConstraintSet::release(uint32_t v) {
    if (v >= vertexCount()) return;
    if (mKind[v] == ConstraintKind::ContactPlane && hasCoefficient(mFriction[v])) --mFrictionCount;
    mKind[v] = ConstraintKind::Free;
}

void ConstraintSet::clearContactPlanes() {
    for (auto& k : mKind) {
        if (k == ConstraintKind::ContactPlane) k = ConstraintKind::Free;
    }
    mFrictionCount = 0;
}

void ConstraintSet::applyFriction(uint32_t v, double normalDv, Vec3& velocity) const {
    if (mKind[v] != ConstraintKind::ContactPlane || !(normalDv > 0.0)) return;
    const Friction& f = mFriction[v];
    const Vec3& n = mNormal[v];
    const Vec3 relative = velocity - mSurfaceVelocity[v];
    const Vec3 tangential = relative - n * n.dot(relative);
    const double speed = tangential.norm();
    if (speed <= f.staticCoefficient * normalDv) {
        velocity -= tangential;  // static: moves with the surface
    } else {
        velocity -= tangential * (f.kineticCoefficient * normalDv / speed);
    }
}

VertexFilter ConstraintSet::filter(uint32_t v, const Vec3& x0, const Vec3& v0, double h, const Vec3& goal,
                                   const Vec3& freeDv, double timeToStepEnd, Vec3& outZ) const {
    VertexFilter f;
    f.kind = mKind[v];
    outZ.setZero();
    if (f.kind == ConstraintKind::Target) {
        outZ = (goal - x0) / h - v0;
    } else if (f.kind == ConstraintKind::ContactPlane) {
        const Vec3& n = mNormal[v];
        const Vec3 point = mPoint[v] - timeToStepEnd * mSurfaceVelocity[v];
        const double gap = (x0 - point).dot(n);  // < 0 when the vertex is inside
        const double vn = v0.dot(n);
        // Free when outside and not reaching the plane within the step. Including the forces'
        // velocity change keeps a vertex resting on the plane under gravity constrained every step
        // (instead of alternating free/pushed-out, which would halve its friction), while one
        // that its neighbours lift off is let go.
        if (gap >= 0.0 && gap + h * (vn + n.dot(freeDv)) >= 0.0) {
            f.kind = ConstraintKind::Free;
        } else {
            // Inside: leave by the end of the step. Outside but crossing: land exactly on it.
            f.normal = n;
            outZ = n * (-gap / h - vn);
        }
    }
    return f;
}

} // namespace cc::cloth
