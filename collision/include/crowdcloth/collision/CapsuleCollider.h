#pragma once

#include <vector>

#include "crowdcloth/collision/Collider.h"
#include "crowdcloth/core/Math.h"

namespace cc::collision {

/// A capsule: the points within `radius` of segment ab. A sphere is a capsule with a == b.
struct Capsule {
    Vec3 a = Vec3::Zero();  ///< [m] first end of the axis
    Vec3 b = Vec3::Zero();  ///< [m] second end (== a for a sphere)
    double radius = 0.0;    ///< [m] (0, 100]
};

/// Cheap body proxies: capsules and spheres (one per bone, say) given per frame, tested
/// analytically, usable instead of the body mesh at coarse levels. Each capsule moves linearly
/// (both ends and the radius) from its previous to its current pose over a step; surface
/// velocities follow from that motion. Cost is O(points x capsules): meant for the tens of
/// capsules of a skeleton.
///
/// Continuous test: conservative advancement (Mirtich 1996) on the gap
/// g(t) = |p(t) - closest(segment(t))| - radius(t), whose rate of change is bounded by
/// L = |dp| + max(|da|, |db|) + |dr| per step, so stepping t by g / L never passes the first
/// contact (no false negatives). Thread-safety: as Collider.
///
///   auto proxies = CapsuleCollider::create(capsules).value();
///   proxies.update(nextCapsules, dt);
///   proxies.queryProximity(cloth.positions, query, contacts);
class CapsuleCollider final : public Collider {
public:
    static Result<CapsuleCollider> create(Span<const Capsule> capsules);
    CapsuleCollider() = default;

    /// The capsules at the end of a step of dt [s] (> 0); the current ones become the previous.
    /// The count must not change. On error nothing changes.
    Status update(Span<const Capsule> capsules, double dt);
    /// Teleport: previous = current = capsules, zero velocity.
    Status reset(Span<const Capsule> capsules);

    Status queryProximity(Span<const Vec3> points, const ContactQuery& query,
                          std::vector<Contact>& outContacts) const override;
    Status queryContinuous(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                           std::vector<Contact>& outContacts) const override;

    uint32_t capsuleCount() const { return static_cast<uint32_t>(mCurrent.size()); }
    const std::vector<Capsule>& current() const { return mCurrent; }

private:
    Status check(Span<const Capsule> capsules, const char* what) const;
    std::vector<Capsule> mCurrent, mPrevious;
    double mDt = 1.0;  // [s] of the last update, for surface velocities
};

} // namespace cc::collision
