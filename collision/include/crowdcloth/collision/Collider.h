#pragma once

#include <vector>

#include "crowdcloth/collision/ContactQuery.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Something cloth collides with that moves from a previous pose to the current one over each
/// step: a body mesh (BodyCollider) or a set of capsule/sphere proxies (CapsuleCollider). The
/// scheduler picks which one a garment uses; the contact stage treats them alike.
///
/// Queries are const and may run concurrently with each other; contacts come back sorted by
/// vertex, at most one per vertex per collider, and outContacts is cleared first.
class Collider {
public:
    virtual ~Collider() = default;

    /// Points within query.reach() of the current surface: closest point, outward normal, depth.
    virtual Status queryProximity(Span<const Vec3> points, const ContactQuery& query,
                                  std::vector<Contact>& outContacts) const = 0;
    /// Points moving linearly start[i] -> end[i] that come within a quarter of query.thickness of
    /// the surface as it moves from its previous to its current pose, starting farther than that
    /// and on the outer side: a contact at the first time of impact, with the surface point and
    /// normal at the end of the step.
    virtual Status queryContinuous(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                                   std::vector<Contact>& outContacts) const = 0;
};

} // namespace cc::collision
