#include "crowdcloth/cloth/ContactResponse.h"

#include <cmath>
#include <string>

namespace cc::cloth {

Status ContactResponse::validate() const {
    if (!(thickness > 0.0 && thickness <= 1.0)) {
        return Status::invalidArgument("ContactResponse.thickness = " + std::to_string(thickness) +
                                       " m is outside (0, 1]");
    }
    if (Status s = friction.validate(); !s) return Status::invalidArgument("ContactResponse." + s.message());
    return Status::ok();
}

namespace {
Status checkContact(const Contact& c, uint32_t vertexCount, const char* what) {
    if (c.vertex >= vertexCount) {
        return Status::invalidArgument(std::string(what) + ": contact names vertex " + std::to_string(c.vertex) +
                                       ", the garment has " + std::to_string(vertexCount));
    }
    if (!isFinite(c.point) || !isFinite(c.normal) || !isFinite(c.surfaceVelocity) || !std::isfinite(c.depth)) {
        return Status::invalidArgument(std::string(what) + ": contact of vertex " + std::to_string(c.vertex) +
                                       " is not finite");
    }
    return Status::ok();
}
} // namespace

Status applyContactPlanes(Span<const Contact> contacts, const ContactResponse& response, ConstraintSet& constraints) {
    if (Status s = response.validate(); !s) return s;
    for (const Contact& c : contacts) {
        if (Status s = checkContact(c, constraints.vertexCount(), "applyContactPlanes"); !s) return s;
        if (constraints.kind(c.vertex) == ConstraintKind::Target) continue;
        const Vec3 offset = c.point + response.thickness * c.normal;
        if (Status s = constraints.setContactPlane(c.vertex, offset, c.normal, c.surfaceVelocity, response.friction); !s) {
            return s;
        }
    }
    return Status::ok();
}

Status resolveContacts(Span<const Contact> contacts, const ContactResponse& response, const ConstraintSet& constraints,
                       ClothState& state, uint32_t* outCorrected) {
    if (Status s = response.validate(); !s) return s;
    uint32_t corrected = 0;
    for (const Contact& c : contacts) {
        if (Status s = checkContact(c, state.vertexCount(), "resolveContacts"); !s) return s;
        if (constraints.kind(c.vertex) == ConstraintKind::Target) continue;
        Vec3& x = state.positions[c.vertex];
        const double gap = (x - c.point).dot(c.normal) - response.thickness;
        if (gap >= 0.0) continue;
        x -= gap * c.normal;
        Vec3& v = state.velocities[c.vertex];
        const double approach = (v - c.surfaceVelocity).dot(c.normal);
        if (approach < 0.0) v -= approach * c.normal;
        ++corrected;
    }
    if (outCorrected) *outCorrected = corrected;
    return Status::ok();
}

} // namespace cc::cloth
