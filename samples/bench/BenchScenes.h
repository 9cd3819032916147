#pragma once

// The one scene every benchmark and the solver front share, for crowdcloth and for Bullet:
// a 1 m x 1 m patch of N x N vertices lying flat at 1 m height, pinned at the two corners of its
// far edge (v = max), falling under gravity in 1/60 s steps.
//
//   z (v) ^  pin (0, N-1) o-------------o pin (N-1, N-1)
//         |               |             |
//         |               |   y = 1 m   |
//         |               |             |
//         |        (0, 0) +-------------+ (N-1, 0)   -> x (u), from -0.5 m to 0.5 m

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/core/RectanglePanel.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace cc::bench {

constexpr double kDt = 1.0 / 60.0;    ///< [s] one step
constexpr int kWarmupSteps = 30;      ///< steps (0.5 s) before timing, so the cloth is in motion
constexpr double kGravity = -9.81;    ///< [m/s^2] along y
constexpr double kPatchHeight = 1.0;  ///< [m] initial y of the patch
constexpr double kPatchMass = 0.15;   ///< [kg] default areal density 0.15 kg/m^2 times 1 m^2
constexpr int kResolutions[] = {17, 33, 65, 129};  ///< vertices per side

/// One of our force model x integrator combinations.
struct OurSetup {
    cloth::ForceModelKind forceModel = cloth::ForceModelKind::Continuum;
    cloth::IntegratorKind integrator = cloth::IntegratorKind::ImplicitPcg;
    int maxThreads = 0;  ///< [-] ParallelSettings::maxThreads; 0 = OpenMP default
};

/// All six combinations, at the default thread count.
std::vector<OurSetup> allOurSetups();

const char* forceModelName(cloth::ForceModelKind kind);
const char* integratorName(cloth::IntegratorKind kind);
/// "Continuum/ImplicitPcg", with "/1thread" appended when maxThreads == 1.
std::string setupName(const OurSetup& setup);

/// The panel of the scene at `vertices` per side (>= 2).
RectanglePanel patchPanel(int vertices);

/// ClothMaterial defaults, with 0.01 s Rayleigh damping for the implicit integrators and none for
/// the explicit one: stiffness-proportional damping raises the stiffest mode's stability demand so
/// much that symplectic Euler would need tens of thousands of substeps per 1/60 s step.
cloth::ClothMaterial patchMaterial(cloth::IntegratorKind integrator);

/// Our simulation of the scene, pinned, at rest (not yet stepped).
Result<std::unique_ptr<cloth::ClothSimulation>> createPatchSimulation(const OurSetup& setup,
                                                                      int vertices);

/// Steps `sim` kWarmupSteps times; the first failure is returned.
Status warmUp(cloth::ClothSimulation& sim);

/// [m] lowest y over the vertices.
double lowestY(const std::vector<Vec3>& positions);

} // namespace cc::bench
