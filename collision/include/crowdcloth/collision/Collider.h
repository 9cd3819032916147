#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/collision/ContactQuery.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Which of a body's parts a ray counts (Collider::traceRays). A part is closed when every edge of
/// it joins two of its triangles, once each way round; imported characters are often built of open
/// pieces too (RobotExpressive: 39 of its 63 parts, plates and tubes without caps).
enum class RayParts : uint8_t {
    Closed, ///< closed parts only: partsInside is exact (an open part's hole lets a ray out
            ///< uncounted)
    All,    ///< open parts as well, each face's outside by its winding: a segment through a plate
            ///< or an open shell meets it (partsInside can then read a point outside as inside)
};

/// What a ray from a point meets on its way out of a body's parts (Collider::traceRays).
struct RayTrace {
    double firstExit = -1.0;  ///< [m] to the first crossing where it leaves a part; -1 = none
    int32_t partsInside = 0;  ///< counted parts its origin is inside: exits less entries along it
    double firstEntry = -1.0; ///< [m] to the first crossing where it enters a part; -1 = none
                              ///< (from outside: whether a segment along it meets the body)
};

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
    /// Each ray from origins[i] along the unit direction directions[i], to infinity, through the
    /// current surface's parts that `parts` names (RayTrace). Takes a point found inside out along
    /// a direction the caller knows, where the nearest surface may be a limb's far side. This
    /// default sees no surface: nothing inside, no exit.
    virtual Status traceRays(Span<const Vec3> origins, Span<const Vec3> directions,
                             RayParts /*parts*/, Span<RayTrace> outTraces) const {
        if (directions.size() != origins.size() || outTraces.size() != origins.size())
            return Status::invalidArgument("Collider::traceRays: one direction and one trace per origin");
        for (RayTrace& t : outTraces) t = RayTrace{};
        return Status::ok();
    }
};

} // namespace cc::collision
