#pragma once

#include "crowdcloth/cloth/ClothLevel.h"
#include "crowdcloth/cloth/ClothState.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Span.h"

namespace cc::cloth {

/// How a garment responds to body contacts (collision/ finds them; see core/Contact.h).
struct ContactResponse {
    double thickness = 0.004;   ///< [m] distance kept from the body surface; (0, 1]. Must match
                                ///< the thickness the contacts were queried with
    Friction friction{0.5, 0.4}; ///< Coulomb coefficients against the body

    /// Names the first invalid field.
    Status validate() const;
};

/// Turns contacts into contact planes for the next solve: vertex c.vertex must stay on the outer
/// side of the plane through c.point + thickness * c.normal, which moves with c.surfaceVelocity,
/// with the response's friction. Pinned and driven (Target) vertices are left alone; contact
/// planes set by a previous call should be cleared first (ConstraintSet::clearContactPlanes).
/// Contacts must name vertices of the garment.
Status applyContactPlanes(Span<const Contact> contacts, const ContactResponse& response, ConstraintSet& constraints);

/// Position correction after a solve: every contact with depth > 0 (closer than the thickness, or
/// inside) moves its vertex along the normal onto the offset surface, and the velocity's normal
/// component relative to the surface is clamped to >= 0 (no longer moving in). Target vertices are
/// left alone. Returns how many vertices moved through outCorrected when non-null.
Status resolveContacts(Span<const Contact> contacts, const ContactResponse& response, const ConstraintSet& constraints,
                       ClothState& state, uint32_t* outCorrected = nullptr);
/// The same for a substepped garment: the level's attached vertices are left alone. `outMoved`,
/// when given (one flag per vertex), gets 1 for every vertex that was pushed.
Status resolveContacts(Span<const Contact> contacts, const ContactResponse& response, const ClothLevel& level,
                       Span<Vec3> positions, Span<Vec3> velocities, uint32_t* outCorrected = nullptr,
                       Span<uint8_t> outMoved = {});

} // namespace cc::cloth
