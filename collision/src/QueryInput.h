#pragma once

#include <string>

#include "crowdcloth/collision/ContactQuery.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"

namespace cc::collision::detail {

/// The first non-finite cloth position, named, for the query `what`.
inline Status checkPoints(Span<const Vec3> points, const char* what) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!isFinite(points[i])) {
            return Status::invalidArgument(std::string(what) + ": cloth vertex " + std::to_string(i) +
                                           " has a non-finite position");
        }
    }
    return Status::ok();
}

/// What every collider checks before a continuous query: the query settings, matching start and
/// end counts, finite positions. `who` names the collider ("BodyCollider", "CapsuleCollider").
/// Messages are built only on failure: queries run per garment per frame, and must not allocate.
inline Status checkContinuousQuery(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                                   const char* who) {
    if (Status s = query.validate(); !s) return s;
    if (start.size() != end.size()) {
        return Status::invalidArgument(std::string(who) + "::queryContinuous: " + std::to_string(start.size()) +
                                       " start positions but " + std::to_string(end.size()) + " end positions");
    }
    for (const auto* points : {&start, &end}) {
        if (checkPoints(*points, "").isOk()) continue;
        const std::string what = std::string(who) + "::queryContinuous (" + (points == &start ? "start" : "end") + ")";
        return checkPoints(*points, what.c_str());
    }
    return Status::ok();
}

} // namespace cc::collision::detail
