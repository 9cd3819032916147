#pragma once

#include <memory>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/core/RectanglePanel.h"

namespace cc::test {

/// Every integrator, for tests that must hold for all of them.
constexpr cloth::IntegratorKind kAllIntegrators[] = {cloth::IntegratorKind::SymplecticEuler,
                                                     cloth::IntegratorKind::ImplicitPcg,
                                                     cloth::IntegratorKind::ImplicitCholmod,
                                                     cloth::IntegratorKind::ImplicitMultigrid};

/// A square sheet of side 1 m with `squares` grid squares per side, lying horizontal at height 1 m
/// (pattern v along +Z), ready to be pinned.
inline RectanglePanel horizontalSheet(uint32_t squares) {
    RectanglePanel panel;
    panel.columns = panel.rows = squares;
    panel.origin = Vec3(-0.5, 1.0, 0.0);
    panel.vAxis = Vec3(0.0, 0.0, 1.0);
    return panel;
}

/// A square sheet of side 1 m hanging in the XY plane from y = 1 m down to y = 0.
inline RectanglePanel verticalSheet(uint32_t squares) {
    RectanglePanel panel;
    panel.columns = panel.rows = squares;
    panel.origin = Vec3(-0.5, 0.0, 0.0);
    return panel;
}

/// Creates a simulation of `panel` and pins the vertices of its far (v = max) corners.
inline std::unique_ptr<cloth::ClothSimulation> cornerPinnedSheet(const RectanglePanel& panel,
                                                                 const cloth::ClothMaterial& material,
                                                                 const cloth::SimulationSettings& settings) {
    const ClothMesh mesh = panel.build().value();
    auto sim = cloth::ClothSimulation::create(mesh, material, settings);
    if (!sim.isOk()) return nullptr;
    for (uint32_t corner : {panel.vertexIndex(0, panel.rows), panel.vertexIndex(panel.columns, panel.rows)}) {
        (void)sim.value()->constraints().pin(corner, mesh.positions[corner]);
    }
    return std::move(sim.value());
}

/// Lowest y over all vertices [m].
inline double lowestY(const cloth::ClothState& state) {
    double lowest = 1e300;
    for (const Vec3& p : state.positions) lowest = std::min(lowest, p.y());
    return lowest;
}

} // namespace cc::test
