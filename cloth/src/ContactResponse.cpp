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

namespace {

// Pushes every too-close vertex onto the offset surface and stops it moving in; `fixed(v)` names
// the vertices that follow targets instead. A vertex near several parts of the body has one contact
// per part: the pushes are repeated (Gauss-Seidel over the half-spaces) until none is needed.
template <typename Fixed>
Status resolve(Span<const Contact> contacts, const ContactResponse& response, Fixed&& fixed, Span<Vec3> positions,
               Span<Vec3> velocities, uint32_t* outCorrected, Span<uint8_t> outMoved) {
    if (Status s = response.validate(); !s) return s;
    for (const Contact& c : contacts)
        if (Status s = checkContact(c, uint32_t(positions.size()), "resolveContacts"); !s) return s;
    constexpr int kSweeps = 4;
    uint32_t corrected = 0;
    for (int sweep = 0; sweep < kSweeps; ++sweep) {
        uint32_t pushes = 0;
        for (std::size_t i = 0; i < contacts.size(); ++i) {
            const Contact& c = contacts[i];
            // A vertex with one contact is done after the first sweep.
            const bool alone = (i == 0 || contacts[i - 1].vertex != c.vertex) &&
                               (i + 1 == contacts.size() || contacts[i + 1].vertex != c.vertex);
            if ((sweep > 0 && alone) || fixed(c.vertex)) continue;
            Vec3& x = positions[c.vertex];
            const double gap = (x - c.point).dot(c.normal) - response.thickness;
            if (gap >= 0.0) continue;
            x -= gap * c.normal;
            Vec3& v = velocities[c.vertex];
            const double approach = (v - c.surfaceVelocity).dot(c.normal);
            if (approach < 0.0) v -= approach * c.normal;
            if (!outMoved.empty()) outMoved[c.vertex] = 1;
            ++pushes;
        }
        if (sweep == 0) corrected = pushes;
        if (pushes == 0) break;
    }
    if (outCorrected) *outCorrected = corrected;
    return Status::ok();
}

} // namespace

Status resolveContacts(Span<const Contact> contacts, const ContactResponse& response, const ConstraintSet& constraints,
                       ClothState& state, uint32_t* outCorrected) {
    if (state.velocities.size() != state.positions.size())
        return Status::invalidArgument("resolveContacts: positions and velocities differ in size");
    return resolve(
        contacts, response, [&](uint32_t v) { return v < constraints.vertexCount() && constraints.kind(v) == ConstraintKind::Target; },
        state.positions, state.velocities, outCorrected, {});
}

Status resolveContacts(Span<const Contact> contacts, const ContactResponse& response, const ClothLevel& level,
                       Span<Vec3> positions, Span<Vec3> velocities, uint32_t* outCorrected, Span<uint8_t> outMoved) {
    if (positions.size() != level.vertexCount() || velocities.size() != level.vertexCount())
        return Status::invalidArgument("resolveContacts: the state does not match the level's " +
                                       std::to_string(level.vertexCount()) + " vertices");
    if (!outMoved.empty() && outMoved.size() != level.vertexCount())
        return Status::invalidArgument("resolveContacts: outMoved needs one flag per vertex");
    return resolve(
        contacts, response, [&](uint32_t v) { return level.nodeOfVertex()[v] >= level.freeNodeCount(); }, positions,
        velocities, outCorrected, outMoved);
}

} // namespace cc::cloth
