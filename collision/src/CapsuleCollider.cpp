#include "crowdcloth/collision/CapsuleCollider.h"

#include "QueryInput.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace cc::collision {

namespace {

// Parameter of the point of segment ab closest to p.
double segmentParameter(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double len2 = d.squaredNorm();
    return len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
}

Capsule lerp(const Capsule& c0, const Capsule& c1, double t) {
    return {c0.a + t * (c1.a - c0.a), c0.b + t * (c1.b - c0.b), c0.radius + t * (c1.radius - c0.radius)};
}

struct Closest {
    double gap;  // distance from the surface, < 0 inside
    double s;    // axis parameter
    Vec3 normal;
};

Closest closestOnCapsule(const Vec3& p, const Capsule& c) {
    const double s = segmentParameter(p, c.a, c.b);
    const Vec3 axisPoint = c.a + s * (c.b - c.a);
    const Vec3 away = p - axisPoint;
    const double dist = away.norm();
    Vec3 normal;
    if (dist > 1e-12 * (1.0 + c.radius)) {
        normal = away / dist;
    } else {
        // On the axis: any direction perpendicular to it is as good; pick one deterministically.
        const Vec3 axis = c.b - c.a;
        normal = axis.squaredNorm() > 0.0 ? axis.unitOrthogonal() : Vec3::UnitY();
    }
    return {dist - c.radius, s, normal};
}

} // namespace

Status CapsuleCollider::check(Span<const Capsule> capsules, const char* what) const {
    if (capsules.empty()) return Status::invalidArgument(std::string(what) + ": zero capsules");
    for (std::size_t i = 0; i < capsules.size(); ++i) {
        const Capsule& c = capsules[i];
        if (!isFinite(c.a) || !isFinite(c.b)) {
            return Status::invalidArgument(std::string(what) + ": capsule " + std::to_string(i) +
                                           " has a non-finite end point");
        }
        if (!(c.radius > 0.0 && c.radius <= 100.0)) {
            return Status::invalidArgument(std::string(what) + ": capsule " + std::to_string(i) + " radius " +
                                           std::to_string(c.radius) + " m is outside (0, 100]");
        }
    }
    return Status::ok();
}

Result<CapsuleCollider> CapsuleCollider::create(Span<const Capsule> capsules) {
    CapsuleCollider collider;
    if (Status s = collider.check(capsules, "CapsuleCollider::create"); !s) return s;
    collider.mCurrent.assign(capsules.begin(), capsules.end());
    collider.mPrevious = collider.mCurrent;
    return collider;
}

Status CapsuleCollider::update(Span<const Capsule> capsules, double dt) {
    if (!(dt > 0.0) || !std::isfinite(dt)) {
        return Status::invalidArgument("CapsuleCollider::update: dt = " + std::to_string(dt) + " s must be finite and > 0");
    }
    if (Status s = check(capsules, "CapsuleCollider::update"); !s) return s;
    if (capsules.size() != mCurrent.size()) {
        return Status::invalidArgument("CapsuleCollider::update: got " + std::to_string(capsules.size()) +
                                       " capsules, the collider has " + std::to_string(mCurrent.size()));
    }
    mPrevious.swap(mCurrent);
    mCurrent.assign(capsules.begin(), capsules.end());
    mDt = dt;
    return Status::ok();
}

Status CapsuleCollider::reset(Span<const Capsule> capsules) {
    if (Status s = check(capsules, "CapsuleCollider::reset"); !s) return s;
    mCurrent.assign(capsules.begin(), capsules.end());
    mPrevious = mCurrent;
    return Status::ok();
}

Status CapsuleCollider::queryProximity(Span<const Vec3> points, const ContactQuery& query,
                                       std::vector<Contact>& outContacts) const {
    outContacts.clear();
    if (Status s = query.validateFor(points.size()); !s) return s;
    if (Status s = detail::checkPoints(points, "CapsuleCollider::queryProximity"); !s) return s;
    if (points.empty()) return Status::ok();
    const double maxReach = query.maxReach();
    // Only capsules whose reach overlaps the points' box can touch any of them (a cape never
    // reaches the shins).
    Eigen::AlignedBox3d box;
    for (const Vec3& p : points) box.extend(p);
    uint32_t near[64];
    Vec3 centre[64];
    double bound2[64];  // squared radius of the sphere around the capsule within which a point can be in reach
    uint32_t nearCount = 0;
    for (uint32_t k = 0; k < mCurrent.size(); ++k) {
        const Capsule& c = mCurrent[k];
        const double grow = c.radius + maxReach;
        Eigen::AlignedBox3d reach(c.a.cwiseMin(c.b) - Vec3::Constant(grow), c.a.cwiseMax(c.b) + Vec3::Constant(grow));
        if (!reach.intersects(box)) continue;
        if (nearCount == 64) {  // more capsules than the list holds: test them all
            nearCount = UINT32_MAX;
            break;
        }
        centre[nearCount] = 0.5 * (c.a + c.b);
        const double r = 0.5 * (c.b - c.a).norm() + grow;
        bound2[nearCount] = r * r * (1.0 + 1e-12);
        near[nearCount++] = k;
    }
    // One contact per capsule within reach: overlapping capsules are parts of one body, and a point
    // near two of them is bounded by both (see Contact::part).
    for (uint32_t i = 0; i < points.size(); ++i) {
        const uint32_t count = nearCount == UINT32_MAX ? uint32_t(mCurrent.size()) : nearCount;
        for (uint32_t n = 0; n < count; ++n) {
            const uint32_t k = nearCount == UINT32_MAX ? n : near[n];
            if (nearCount != UINT32_MAX && (points[i] - centre[n]).squaredNorm() > bound2[n]) continue;
            const Closest c = closestOnCapsule(points[i], mCurrent[k]);
            if (c.gap > query.reach(i)) continue;
            const Capsule& now = mCurrent[k];
            const Capsule& before = mPrevious[k];
            Contact contact;
            contact.vertex = i;
            contact.primitive = k;
            contact.part = k;
            contact.normal = c.normal;
            contact.point = now.a + c.s * (now.b - now.a) + now.radius * c.normal;
            const Vec3 was = before.a + c.s * (before.b - before.a) + before.radius * c.normal;
            contact.surfaceVelocity = (contact.point - was) / mDt;
            contact.depth = query.thickness - c.gap;
            contact.time = 1.0;
            contact.source = ContactSource::Proximity;
            outContacts.push_back(contact);
        }
    }
    return Status::ok();
}

Status CapsuleCollider::queryContinuous(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                                        std::vector<Contact>& outContacts) const {
    outContacts.clear();
    if (Status s = detail::checkContinuousQuery(start, end, query, "CapsuleCollider"); !s) return s;
    const double contactGap = 0.25 * query.thickness;  // as BodyCollider: first touch within thickness / 4
    const double tolerance = 1e-3 * contactGap;
    for (uint32_t i = 0; i < start.size(); ++i) {
        Contact best;
        best.vertex = UINT32_MAX;
        for (uint32_t k = 0; k < mCurrent.size(); ++k) {
            const Capsule& c0 = mPrevious[k];
            const Capsule& c1 = mCurrent[k];
            const double lipschitz = (end[i] - start[i]).norm() + std::max((c1.a - c0.a).norm(), (c1.b - c0.b).norm()) +
                                     std::abs(c1.radius - c0.radius);
            double t = 0.0;
            Closest c = closestOnCapsule(start[i], c0);
            if (c.gap <= contactGap) continue;  // already touching: a proximity contact
            bool hit = false;
            // Each advance is a safe lower bound on the first contact; the cap only ends a grazing
            // approach early, reporting a (safe) contact at the time reached.
            for (int iteration = 0; iteration < 1000; ++iteration) {
                if (c.gap - contactGap <= tolerance) {
                    hit = true;
                    break;
                }
                if (lipschitz <= 0.0) break;
                t += (c.gap - contactGap) / lipschitz;
                if (t > 1.0) break;
                c = closestOnCapsule(start[i] + t * (end[i] - start[i]), lerp(c0, c1, t));
                hit = iteration == 999;
            }
            if (!hit || (best.vertex != UINT32_MAX && t >= best.time)) continue;
            best.vertex = i;
            best.primitive = k;
            best.part = k;
            best.time = t;
            best.normal = c.normal;
            best.point = c1.a + c.s * (c1.b - c1.a) + c1.radius * c.normal;
            const Vec3 was = c0.a + c.s * (c0.b - c0.a) + c0.radius * c.normal;
            best.surfaceVelocity = (best.point - was) / mDt;
            best.depth = query.thickness - (end[i] - best.point).dot(best.normal);
            best.source = ContactSource::Continuous;
        }
        if (best.vertex != UINT32_MAX) outContacts.push_back(best);
    }
    return Status::ok();
}

} // namespace cc::collision
