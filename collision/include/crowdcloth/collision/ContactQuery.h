#pragma once

#include <string>

#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// What a collider query looks for. A vertex gets a contact when its distance from the surface is
/// below thickness + margin; the margin lets a contact be known one step before it is touched.
struct ContactQuery {
    double thickness = 0.004;  ///< [m] collision offset kept between cloth and body; (0, 1]
    double margin = 0.004;     ///< [m] extra reach beyond the thickness; [0, 1] (0 = only contacts
                               ///< already within the thickness)
    ParallelSettings parallel{0, 512};  ///< threads for the per-vertex queries (results never
                                        ///< depend on it); 1 when garments already run in parallel

    /// Names the first invalid field, with its value.
    Status validate() const {
        if (!(thickness > 0.0 && thickness <= 1.0)) {
            return Status::invalidArgument("ContactQuery.thickness = " + std::to_string(thickness) +
                                           " m is outside (0, 1]");
        }
        if (!(margin >= 0.0 && margin <= 1.0)) {
            return Status::invalidArgument("ContactQuery.margin = " + std::to_string(margin) + " m is outside [0, 1]");
        }
        return Status::ok();
    }
    double reach() const { return thickness + margin; }
};

} // namespace cc::collision
