#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// How a vertex's velocity is restricted during a step.
enum class ConstraintKind : uint8_t {
    Free,          ///< moves with the forces
    Target,        ///< must reach a given position at the end of the step (pins, attachments)
    ContactPlane,  ///< may slide along a plane but not move into it (contacts from collision/)
};

/// The velocity filter of one vertex (Baraff & Witkin 1998, section 5): the solver's velocity
/// change is dv = z + S y, where S projects onto the free directions and z fixes the rest.
struct VertexFilter {
    ConstraintKind kind = ConstraintKind::Free;
    Vec3 normal = Vec3::Zero();  ///< plane normal, for ContactPlane

    /// S * v: the part of v in the free directions.
    Vec3 project(const Vec3& v) const {
        switch (kind) {
        case ConstraintKind::Free: return v;
        case ConstraintKind::Target: return Vec3::Zero();
        case ConstraintKind::ContactPlane: return v - normal * normal.dot(v);
        }
        return v;
    }
    /// The matrix S.
    Mat3 matrix() const {
        switch (kind) {
        case ConstraintKind::Free: return Mat3::Identity();
        case ConstraintKind::Target: return Mat3::Zero();
        case ConstraintKind::ContactPlane: return Mat3::Identity() - normal * normal.transpose();
        }
        return Mat3::Identity();
    }
};

/// Per-vertex constraints of one garment: pins, moving targets (what a skinned attachment drives)
/// and contact planes handed in from outside. Set between steps; the integrators read them.
class ConstraintSet {
public:
    explicit ConstraintSet(uint32_t vertexCount = 0);

    /// Holds vertex v at `position` [m] until released.
    Status pin(uint32_t v, const Vec3& position);
    /// Drives vertex v to `position` [m] at the end of every following step until moved or
    /// released; a skinned attachment updates it each frame.
    Status setTarget(uint32_t v, const Vec3& position) { return pin(v, position); }
    /// Keeps vertex v on the side of the plane (point, normal) that the unit normal points to; it
    /// may slide along the plane and leave it. A vertex inside is pushed out within the step; one
    /// outside whose velocity would cross the plane lands on it. (Forces within the step, such as
    /// gravity, can still carry a free vertex in by about h^2 |a|; the next step pushes it out.)
    /// Replaces any target. Cleared by clearContactPlanes().
    Status setContactPlane(uint32_t v, const Vec3& point, const Vec3& normal);
    void release(uint32_t v);
    void clearContactPlanes();

    uint32_t vertexCount() const { return static_cast<uint32_t>(mKind.size()); }
    ConstraintKind kind(uint32_t v) const { return mKind[v]; }
    const Vec3& target(uint32_t v) const { return mPoint[v]; }

    /// The filter for a step of length h from (x0, v0), and z (the fixed part of dv). A Target
    /// vertex must reach `goal` (its target, or a point on the way there when a step is split).
    /// A contact plane the vertex does not reach within the step leaves it free.
    VertexFilter filter(uint32_t v, const Vec3& x0, const Vec3& v0, double h, const Vec3& goal, Vec3& outZ) const;

private:
    Status checkVertex(uint32_t v, const char* what) const;
    std::vector<ConstraintKind> mKind;
    std::vector<Vec3> mPoint;
    std::vector<Vec3> mNormal;
};

} // namespace cc::cloth
