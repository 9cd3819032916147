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

/// Coulomb friction between a cloth vertex and the surface it touches.
struct Friction {
    double staticCoefficient = 0.0;   ///< [-] mu_s: a sliding-free contact stays put while the
                                      ///< tangential impulse it needs is <= mu_s times the normal
                                      ///< impulse; [0, 10] (0 = frictionless)
    double kineticCoefficient = 0.0;  ///< [-] mu_k: a sliding contact loses tangential speed
                                      ///< mu_k times its normal velocity change; [0, mu_s]

    /// Names the first invalid field.
    Status validate() const;
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
    /// may slide along the plane and leave it. The plane is where it will be at the end of the step
    /// (a moving body's surface), moving at `surfaceVelocity` [m/s]. A vertex inside is pushed out
    /// within the step; one outside that would cross the plane (by its velocity and the forces'
    /// first-order velocity change) lands on it. Friction acts on the velocity relative to the
    /// surface (Bridson et al. 2002, section 7.2): after the solve, a contact whose tangential
    /// relative speed is at most mu_s times the normal velocity change the plane applied sticks
    /// (moves with the surface); otherwise that speed drops by mu_k times the normal change.
    /// Replaces any target. Cleared by clearContactPlanes().
    Status setContactPlane(uint32_t v, const Vec3& point, const Vec3& normal,
                           const Vec3& surfaceVelocity = Vec3::Zero(), const Friction& friction = {});
    void release(uint32_t v);
    void clearContactPlanes();

    uint32_t vertexCount() const { return static_cast<uint32_t>(mKind.size()); }
    ConstraintKind kind(uint32_t v) const { return mKind[v]; }
    const Vec3& target(uint32_t v) const { return mPoint[v]; }

    /// The filter for a step of length h from (x0, v0), and z (the fixed part of dv). A Target
    /// vertex must reach `goal` (its target, or a point on the way there when a step is split).
    /// A contact plane the vertex does not reach within the step, moving at v0 + freeDv (freeDv:
    /// the velocity change the forces alone would give, to first order), leaves it free. When a
    /// step is split, `timeToStepEnd` [s] is how long after this part the full step ends: a moving
    /// plane is taken back along its surface velocity by that time.
    VertexFilter filter(uint32_t v, const Vec3& x0, const Vec3& v0, double h, const Vec3& goal, const Vec3& freeDv,
                        double timeToStepEnd, Vec3& outZ) const;

    /// True when some contact plane has friction (integrators skip the friction pass otherwise).
    bool hasFriction() const { return mFrictionCount > 0; }
    /// Coulomb friction on vertex v's velocity [m/s] after a step in which its contact plane
    /// applied the normal velocity change normalDv [m/s] (> 0 pushes out); no-op when v has no
    /// contact plane or normalDv <= 0 (the plane did not push, so it cannot hold).
    void applyFriction(uint32_t v, double normalDv, Vec3& velocity) const;
    const Vec3& contactNormal(uint32_t v) const { return mNormal[v]; }

private:
    Status checkVertex(uint32_t v, const char* what) const;
    std::vector<ConstraintKind> mKind;
    std::vector<Vec3> mPoint;
    std::vector<Vec3> mNormal;
    std::vector<Vec3> mSurfaceVelocity;
    std::vector<Friction> mFriction;
    uint32_t mFrictionCount = 0;  // contact planes with a non-zero coefficient
};

} // namespace cc::cloth
