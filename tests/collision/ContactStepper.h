#pragma once

#include <vector>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/cloth/ContactResponse.h"
#include "crowdcloth/collision/BodyContactStage.h"

namespace cc::test {

/// One garment step with body contacts, the way the engine wires it: the colliders are already at
/// the end-of-step pose; contacts of the still cloth against the moving body become contact planes
/// (with friction); after the solve the swept and proximity contacts correct positions.
struct ContactStepper {
    collision::BodyContactStage stage;
    collision::BodyContactSettings settings;
    cloth::ContactResponse response;
    std::vector<Contact> contacts;
    std::vector<Vec3> start;
    uint32_t corrected = 0;  ///< vertices moved by the last position correction

    Status step(cloth::ClothSimulation& sim, Span<const collision::Collider* const> colliders, double dt) {
        response.thickness = settings.query.thickness;
        start = sim.state().positions;
        if (Status s = stage.gather(colliders, start, start, settings, contacts); !s) return s;
        sim.constraints().clearContactPlanes();
        if (Status s = cloth::applyContactPlanes(contacts, response, sim.constraints()); !s) return s;
        if (Status s = sim.step(dt); !s) return s;
        if (Status s = stage.gather(colliders, start, sim.state().positions, settings, contacts); !s) return s;
        return cloth::resolveContacts(contacts, response, sim.constraints(), sim.state(), &corrected);
    }
};

} // namespace cc::test
