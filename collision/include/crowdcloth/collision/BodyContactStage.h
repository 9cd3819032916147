#pragma once

#include <vector>

#include "crowdcloth/collision/Collider.h"

namespace cc::collision {

/// What the contact stage of a garment step asks for.
struct BodyContactSettings {
    ContactQuery query;      ///< thickness and margin
    bool continuous = true;  ///< also run the swept tests (fast limbs); false = proximity only,
                             ///< which lets a limb moving more than about thickness + margin per
                             ///< step pass through the cloth
    /// Names the first invalid field.
    Status validate() const { return query.validate(); }
};

/// Gathers one garment's body contacts for a step: proximity at `end` plus, when enabled, the
/// swept test from `start` to `end`, over every collider of the character (a mesh, proxies or
/// both), reduced to one contact per vertex and body part (reduceContactsPerVertex), sorted by vertex.
///
/// Used twice per step: before the solve with start = end = the cloth's positions (the body sweeps
/// past still cloth), giving the contact planes; after the solve with (positions before, positions
/// after), giving the position corrections. Owns its scratch so a warm stage does not allocate.
/// A stage holds only scratch: one per concurrent task (the World borrows them per call), and
/// distinct stages may run concurrently on shared colliders.
///
///   BodyContactStage stage;
///   const std::vector<const Collider*> bodies{body.get()};
///   stage.gather(bodies, x0, x0, settings, contacts);
class BodyContactStage {
public:
    Status gather(Span<const Collider* const> colliders, Span<const Vec3> start, Span<const Vec3> end,
                  const BodyContactSettings& settings, std::vector<Contact>& outContacts);

private:
    std::vector<Contact> mScratch;
};

} // namespace cc::collision
