#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/lod/GarmentHierarchy.h"

namespace cc::test {

/// A garment hierarchy driving a ClothSimulation: the solver is rebuilt from the active mesh after
/// every level change (cloth/ has no incremental rebuild), pins follow their hierarchy vertices.
struct LodSimulation {
    lod::GarmentHierarchy* hierarchy = nullptr;
    cloth::ClothMaterial material;
    cloth::SimulationSettings settings;
    std::vector<std::pair<uint32_t, Vec3>> pins;  ///< (hierarchy vertex, position)
    lod::ActiveMesh active;
    std::unique_ptr<cloth::ClothSimulation> sim;

    Status rebuild() {
        active = hierarchy->activeMesh();
        auto created = cloth::ClothSimulation::create(active.mesh, material, settings);
        if (!created.isOk()) return created.status();
        sim = std::move(created.value());
        sim->state().velocities = active.velocities;
        for (const auto& [v, p] : pins) {
            if (Status s = sim->constraints().pin(active.vertexToSim[v], p); !s) return s;
        }
        return Status::ok();
    }
    Status step(double dt) {
        if (Status s = sim->step(dt); !s) return s;
        return hierarchy->readState(active, sim->state().positions, sim->state().velocities);
    }
    /// Zeroes all velocities (quasi-static relaxation towards the static drape).
    void stopMotion() {
        for (Vec3& v : sim->state().velocities) v.setZero();
        (void)hierarchy->readState(active, sim->state().positions, sim->state().velocities);
    }
    double maxSpeed() const {
        double s = 0.0;
        for (const Vec3& v : sim->state().velocities) s = std::max(s, v.norm());
        return s;
    }
};

/// RMS and max distance between two render position sets [m].
inline std::pair<double, double> renderDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double sum = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = (a[i] - b[i]).norm();
        sum += d * d;
        worst = std::max(worst, d);
    }
    return {std::sqrt(sum / double(a.size())), worst};
}

} // namespace cc::test
