#pragma once

#include <algorithm>
#include <string>

#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// What a collider query looks for. A vertex gets a contact when its distance from the surface is
/// below thickness + margin; the margin lets a contact be known one step before it is touched.
struct ContactQuery {
    double thickness = 0.004;  ///< [m] collision offset kept between cloth and body; (0, 1]
    double margin = 0.004;     ///< [m] extra reach beyond the thickness; [0, 1] (0 = only contacts
                               ///< already within the thickness)
    /// When not empty, one margin per queried point in place of `margin` (same range): a point
    /// that moved far looks far, the rest stay cheap.
    Span<const double> pointMargins;
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
    /// validate(), and that pointMargins (if any) has one finite margin in [0, 1] per point.
    Status validateFor(std::size_t pointCount) const {
        if (Status s = validate(); !s) return s;
        if (pointMargins.empty()) return Status::ok();
        if (pointMargins.size() != pointCount)
            return Status::invalidArgument("ContactQuery.pointMargins holds " + std::to_string(pointMargins.size()) +
                                           " margins for " + std::to_string(pointCount) + " points");
        for (std::size_t i = 0; i < pointCount; ++i) {
            if (!(pointMargins[i] >= 0.0 && pointMargins[i] <= 1.0))
                return Status::invalidArgument("ContactQuery.pointMargins[" + std::to_string(i) + "] = " +
                                               std::to_string(pointMargins[i]) + " m is outside [0, 1]");
        }
        return Status::ok();
    }
    double reach() const { return thickness + margin; }
    /// Reach of point i (after validateFor).
    double reach(std::size_t i) const { return thickness + (pointMargins.empty() ? margin : pointMargins[i]); }
    /// The largest reach of any point (after validateFor).
    double maxReach() const {
        double m = margin;
        if (!pointMargins.empty()) {
            m = 0.0;
            for (double x : pointMargins) m = std::max(m, x);
        }
        return thickness + m;
    }
};

} // namespace cc::collision
