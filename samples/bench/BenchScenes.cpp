#include "BenchScenes.h"

#include <algorithm>
#include <limits>

namespace cc::bench {

using cloth::ForceModelKind;
using cloth::IntegratorKind;

std::vector<OurSetup> allOurSetups() {
    std::vector<OurSetup> setups;
    for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
        for (IntegratorKind integrator :
             {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitPcg,
              IntegratorKind::ImplicitCholmod}) {
            setups.push_back({model, integrator, 0});
        }
    }
    return setups;
}

const char* forceModelName(ForceModelKind kind) {
    switch (kind) {
    case ForceModelKind::MassSpring: return "MassSpring";
    case ForceModelKind::Continuum: return "Continuum";
    }
    return "?";
}

const char* integratorName(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::SymplecticEuler: return "Explicit";
    case IntegratorKind::ImplicitPcg: return "ImplicitPcg";
    case IntegratorKind::ImplicitCholmod: return "ImplicitCholmod";
    case IntegratorKind::ImplicitMultigrid: return "ImplicitMultigrid";
    }
    return "?";
}

std::string setupName(const OurSetup& setup) {
    std::string name =
        std::string(forceModelName(setup.forceModel)) + "/" + integratorName(setup.integrator);
    if (setup.maxThreads == 1) name += "/1thread";
    return name;
}

RectanglePanel patchPanel(int vertices) {
    RectanglePanel panel;
    panel.width = panel.height = 1.0;
    panel.columns = panel.rows = static_cast<uint32_t>(vertices - 1);
    panel.origin = Vec3(-0.5, kPatchHeight, 0.0);
    panel.vAxis = Vec3(0.0, 0.0, 1.0);  // horizontal: the patch starts flat and falls
    return panel;
}

cloth::ClothMaterial patchMaterial(IntegratorKind integrator) {
    cloth::ClothMaterial material;
    material.damping = integrator == IntegratorKind::SymplecticEuler ? 0.0 : 0.01;
    return material;
}

Result<std::unique_ptr<cloth::ClothSimulation>> createPatchSimulation(const OurSetup& setup,
                                                                      int vertices) {
    const RectanglePanel panel = patchPanel(vertices);
    Result<ClothMesh> mesh = panel.build();
    if (!mesh.isOk()) return mesh.status();

    cloth::SimulationSettings settings;
    settings.forceModel = setup.forceModel;
    settings.integrator = setup.integrator;
    settings.gravity = Vec3(0.0, kGravity, 0.0);
    settings.parallel.maxThreads = setup.maxThreads;
    auto sim =
        cloth::ClothSimulation::create(mesh.value(), patchMaterial(setup.integrator), settings);
    if (!sim.isOk()) return sim;

    const uint32_t corners[] = {panel.vertexIndex(0, panel.rows),
                                panel.vertexIndex(panel.columns, panel.rows)};
    for (uint32_t corner : corners) {
        const Status pinned =
            sim.value()->constraints().pin(corner, mesh.value().positions[corner]);
        if (!pinned) return pinned;
    }
    return sim;
}

Status warmUp(cloth::ClothSimulation& sim) {
    for (int i = 0; i < kWarmupSteps; ++i) {
        if (Status s = sim.step(kDt); !s) return s;
    }
    return Status::ok();
}

double lowestY(const std::vector<Vec3>& positions) {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& p : positions) lowest = std::min(lowest, p.y());
    return lowest;
}

} // namespace cc::bench
