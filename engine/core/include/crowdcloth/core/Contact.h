#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"

namespace cc {

/// Where a contact came from: the closest-point test at the end of the step, or a continuous
/// (swept) test that found the vertex meeting the moving surface within the step.
enum class ContactSource : uint8_t {
    Proximity,
    Continuous,
};

/// One cloth vertex touching (or within reach of) a body surface. collision/ writes these,
/// cloth/ turns them into per-vertex contact constraints; the type is shared vocabulary so neither
/// module includes the other.
///
/// Geometry is given at the end of the step (the body's current pose): `point` is the body surface
/// point, `normal` points out of the body towards the side the cloth belongs to, and the signed
/// distance of the vertex from the surface is (x - point) . normal. `depth` = thickness - that
/// distance, so depth > 0 means the vertex is closer than the collision thickness (or inside).
struct Contact {
    uint32_t vertex = 0;                ///< cloth vertex index
    uint32_t primitive = 0;             ///< body triangle (mesh) or proxy index that was hit
    uint32_t part = 0;                  ///< connected surface of the body the primitive belongs to: a
                                        ///< body of overlapping parts (a thigh into the pelvis) gives a
                                        ///< vertex one contact per part within reach
    Vec3 point = Vec3::Zero();          ///< [m] surface point at the end of the step
    Vec3 normal = Vec3::Zero();         ///< [-] unit outward normal at `point`
    Vec3 surfaceVelocity = Vec3::Zero();///< [m/s] velocity of the body surface at `point`
    double depth = 0.0;                 ///< [m] thickness - signed distance; > 0 = too close
    double time = 1.0;                  ///< [-] fraction of the step at first touch (1 = proximity)
    ContactSource source = ContactSource::Proximity;
};

/// Full tie-break order for contact lists (STYLE.md §6): vertex, part, primitive, source.
inline bool contactLess(const Contact& a, const Contact& b) {
    if (a.vertex != b.vertex) return a.vertex < b.vertex;
    if (a.part != b.part) return a.part < b.part;
    if (a.primitive != b.primitive) return a.primitive < b.primitive;
    return a.source < b.source;
}

/// Sorts by contactLess and keeps one contact per vertex and body part: a continuous contact wins
/// over a proximity one (it knows which side the vertex came from); among continuous ones the
/// earliest, among proximity ones the deepest; remaining ties keep the lower primitive. The result
/// does not depend on the input order.
inline void reduceContactsPerVertex(std::vector<Contact>& contacts) {
    std::sort(contacts.begin(), contacts.end(), contactLess);
    std::size_t out = 0;
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        if (out > 0 && contacts[out - 1].vertex == contacts[i].vertex && contacts[out - 1].part == contacts[i].part) {
            const Contact& kept = contacts[out - 1];
            const Contact& c = contacts[i];
            bool better = false;
            if (c.source != kept.source) {
                better = c.source == ContactSource::Continuous;
            } else if (c.source == ContactSource::Continuous) {
                better = c.time < kept.time;
            } else {
                better = c.depth > kept.depth;
            }
            if (better) contacts[out - 1] = c;
        } else {
            contacts[out++] = contacts[i];
        }
    }
    contacts.resize(out);
}

} // namespace cc
