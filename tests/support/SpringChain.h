#pragma once
// A vertical chain of masses on springs for the substepped solver's closed-form tests.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "crowdcloth/cloth/SubstepSimulation.h"

namespace cc::test {

/// Vertex 0 attached at the origin, `masses` masses of `mass` [kg] below it at rest-length spacing
/// (the lowest `lastMass`, when given), springs of stiffness k [N/m] and rest length `rest` [m].
inline std::unique_ptr<cloth::SubstepSimulation> hangingChain(int masses, double mass, double k, double rest,
                                                              double lastMass = 0.0) {
    std::vector<cloth::Spring> springs;
    std::vector<Vec3> positions;
    std::vector<double> m;
    for (int i = 0; i <= masses; ++i) {
        positions.push_back(Vec3(0.0, -rest * i, 0.0));
        m.push_back(i == masses && lastMass > 0.0 ? lastMass : mass);
        if (i > 0) springs.push_back({uint32_t(i - 1), uint32_t(i), k, rest, cloth::SpringKind::Structural});
    }
    const uint32_t attached[] = {0};
    cloth::ClothLevelDesc desc;
    desc.vertexCount = uint32_t(positions.size());
    desc.springs = springs;
    desc.masses = m;
    desc.attachedVertices = attached;
    auto sim = cloth::SubstepSimulation::create(desc, positions);
    EXPECT_TRUE(sim.isOk()) << sim.status().message();
    return std::move(sim).value();
}

} // namespace cc::test
