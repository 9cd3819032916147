#pragma once

#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// A fabric in physical units. The force models derive every per-element constant from these
/// moduli and the element's rest geometry, so one material drapes alike at every resolution.
struct ClothMaterial {
    double arealDensity = 0.15;     ///< [kg/m^2] mass per rest area; (0, 100]
    double stretchStiffness = 5.0e3; ///< [N/m] membrane force per unit width per unit strain along
                                     ///< warp/weft; (0, 1e9]
    double shearStiffness = 5.0e2;  ///< [N/m] in-plane shear modulus; [0, 1e9] (0 = no shear resistance)
    double bendStiffness = 1.0e-5;  ///< [N*m] resists curvature; [0, 1e3] (0 = no bending)
    double damping = 0.0;           ///< [s] stiffness-proportional (Rayleigh) damping; [0, 10]
                                    ///< (0 = undamped)

    /// Names the first field outside its range, with its value.
    Status validate() const;
};

} // namespace cc::cloth
