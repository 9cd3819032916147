#include "crowdcloth/character/BodyMeasurements.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "BodySlices.h"

namespace cc {
namespace {

std::string metres(double y) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.3f m", y);
    return text;
}

/// Outside distance of p from a convex CCW hull (<= 0 inside): the largest signed edge distance.
double outsideDistance(const std::vector<Vec2>& hull, const Vec2& p) {
    double worst = std::numeric_limits<double>::lowest();
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec2& a = hull[i];
        const Vec2 edge = hull[(i + 1) % hull.size()] - a;
        const double length = edge.norm();
        if (length == 0.0) continue;
        worst = std::max(worst, -(edge.x() * (p.y() - a.y()) - edge.y() * (p.x() - a.x())) / length);
    }
    return worst;
}

} // namespace

std::vector<uint8_t> trianglesOf(const std::vector<std::array<uint32_t, 3>>& triangles,
                                 const std::vector<BodyRegion>& vertexRegions, std::initializer_list<BodyRegion> wanted) {
    std::vector<uint8_t> keep(triangles.size(), 0);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        int count = 0;
        for (uint32_t v : triangles[t])
            for (BodyRegion w : wanted) count += vertexRegions[v] == w;
        keep[t] = count >= 2;
    }
    return keep;
}

BodyRing measureRing(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                     const std::vector<uint8_t>& keepTriangle, double y, const Vec3& left, const Vec3& forward) {
    BodyRing ring;
    ring.height = y;
    std::vector<Vec2> points;
    detail::slicePoints(positions, triangles, keepTriangle, y, points);
    if (points.size() < 3) return ring;
    ring.hull = convexHull(points);
    ring.girth = detail::perimeter(ring.hull);
    double aLo = std::numeric_limits<double>::max(), aHi = std::numeric_limits<double>::lowest();
    double bLo = aLo, bHi = aHi;
    for (const Vec2& p : ring.hull) {
        const double a = p.x() * left.x() + p.y() * left.z(), b = p.x() * forward.x() + p.y() * forward.z();
        aLo = std::min(aLo, a), aHi = std::max(aHi, a), bLo = std::min(bLo, b), bHi = std::max(bHi, b);
    }
    ring.halfWidth = 0.5 * (aHi - aLo);
    ring.halfDepth = 0.5 * (bHi - bLo);
    ring.centre = 0.5 * (aLo + aHi) * left + 0.5 * (bLo + bHi) * forward + Vec3(0.0, y, 0.0);
    return ring;
}

Result<BodyMeasurements> measureBody(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                                     const BodyRegions& regions, Span<const Vec3> jointPositions) {
    if (positions.size() != regions.vertices.size())
        return Status::invalidArgument("measureBody: " + std::to_string(positions.size()) + " positions for " +
                                       std::to_string(regions.vertices.size()) + " labelled vertices");
    BodyMeasurements m;
    m.left = regions.left;
    m.forward = regions.forward;
    m.method = regions.method;
    m.groundY = std::numeric_limits<double>::max();
    m.topY = std::numeric_limits<double>::lowest();
    for (const Vec3& p : positions) m.groundY = std::min(m.groundY, p.y()), m.topY = std::max(m.topY, p.y());
    m.height = m.topY - m.groundY;
    const double h = m.height;
    if (!(h > 0.0)) return Status::invalidArgument("the body has no height");
    const double step = 0.0025 * h;
    const auto at = [&](double fraction) { return m.groundY + fraction * h; };

    const auto trunkLegs = trianglesOf(triangles, regions.vertices, {BodyRegion::Torso, BodyRegion::LeftLeg, BodyRegion::RightLeg});
    const auto torso = trianglesOf(triangles, regions.vertices, {BodyRegion::Torso});
    const auto arms = trianglesOf(triangles, regions.vertices, {BodyRegion::LeftArm, BodyRegion::RightArm});
    const auto torsoArms = trianglesOf(triangles, regions.vertices, {BodyRegion::Torso, BodyRegion::LeftArm, BodyRegion::RightArm});
    const auto column = trianglesOf(triangles, regions.vertices, {BodyRegion::Torso, BodyRegion::Neck, BodyRegion::Head});
    const auto ring = [&](const std::vector<uint8_t>& keep, double y) {
        return measureRing(positions, triangles, keep, y, m.left, m.forward);
    };
    const auto jointY = [&](const std::array<int32_t, 2>& joints, double& out) {
        if (jointPositions.empty() || joints[0] < 0 || joints[1] < 0) return false;
        out = 0.5 * (jointPositions[std::size_t(joints[0])].y() + jointPositions[std::size_t(joints[1])].y());
        return true;
    };

    // Shoulders: the arm joints' height, or the top of the arms' skin for a body without skeleton.
    bool anyArm = false;
    double armTop = std::numeric_limits<double>::lowest();
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (isArm(regions.vertices[v])) anyArm = true, armTop = std::max(armTop, positions[v].y());
    if (!jointY(regions.upperArm, m.shoulderY)) m.shoulderY = anyArm ? armTop - 0.03 * h : at(0.81);
    if (!(m.shoulderY > at(0.4) && m.shoulderY < m.topY))
        return Status::invalidArgument("the shoulders (" + metres(m.shoulderY) + ") are not in the upper body");

    // Crotch: going down from the hips, the first height at which the middle between the legs is
    // outside the body.
    double hipJointY = 0.0;
    const bool haveHipJoints = jointY(regions.thigh, hipJointY);
    const double crotchSearchTop = haveHipJoints ? hipJointY + 0.1 * h : at(0.6);
    m.crotchY = 0.0;
    std::vector<Vec2> points;
    const std::vector<uint32_t> sameIds = detail::samePositionIds(positions);
    for (double y = crotchSearchTop; y > at(0.15); y -= step) {
        std::vector<detail::SliceLoop> loops;
        detail::sliceLoops(positions, triangles, trunkLegs, sameIds, y, loops);
        detail::slicePoints(positions, triangles, trunkLegs, y, points);
        if (points.empty()) continue;
        Vec2 middle = Vec2::Zero();
        for (const Vec2& p : points) middle += p;
        middle /= double(points.size());
        bool covered = false;
        for (const detail::SliceLoop& loop : loops)
            covered = covered || detail::insideConvex(convexHull(loop.points), middle, 0.0);
        if (!covered) {
            m.crotchY = y;
            break;
        }
    }
    if (m.crotchY == 0.0) return Status::invalidArgument("the legs never part (no crotch found below " + metres(crotchSearchTop) + ")");
    if (!haveHipJoints) hipJointY = m.crotchY + 0.05 * h;

    // Hips: the widest section of hips and thighs around the hip joints.
    for (double y = std::max(m.crotchY, hipJointY - 0.08 * h); y <= hipJointY + 0.08 * h; y += step) {
        BodyRing r = ring(trunkLegs, y);
        if (r.girth > m.hips.girth) m.hips = std::move(r);
    }
    if (!(m.hips.girth > 0.0)) return Status::invalidArgument("no hips found around " + metres(hipJointY));

    // Waist: the narrowest torso section between a sixth and three fifths of the way up to the
    // shoulders (the natural waist sits about a third of the way up).
    const double span = m.shoulderY - m.hips.height;
    if (!(span > 0.05 * h)) return Status::invalidArgument("the shoulders are not above the hips");
    m.waist.girth = std::numeric_limits<double>::max();
    for (double y = m.hips.height + 0.15 * span; y <= m.hips.height + 0.6 * span; y += step) {
        BodyRing r = ring(torso, y);
        if (r.girth > 0.0 && r.girth < m.waist.girth) m.waist = std::move(r);
    }
    if (m.waist.girth == std::numeric_limits<double>::max())
        return Status::invalidArgument("no waist found between the hips (" + metres(m.hips.height) + ") and the shoulders (" +
                                       metres(m.shoulderY) + ")");

    // Chest: under the armpits, where the arms have come clear of the torso. Arms that hug the
    // torso all the way down leave no gap to find: the armpit is then put a third of the way down
    // from the shoulders to the waist, where an adult's is.
    const double torsoSpan = m.shoulderY - m.waist.height;
    double armpitY = m.shoulderY - 0.35 * torsoSpan;
    if (anyArm) {
        for (double y = m.shoulderY - 0.01 * h; y > m.shoulderY - 0.5 * torsoSpan; y -= step) {
            const BodyRing t = ring(torso, y);
            if (t.hull.size() < 3) continue;
            detail::slicePoints(positions, triangles, arms, y, points);
            double gap = std::numeric_limits<double>::max();
            for (const Vec2& p : points) gap = std::min(gap, outsideDistance(t.hull, p));
            if (gap >= 0.005 * h) {
                armpitY = y;
                break;
            }
        }
    }
    const double chestY = std::max(armpitY - 0.01 * h, m.waist.height + 0.3 * torsoSpan);
    m.chest = ring(torso, chestY);
    if (!(m.chest.girth > 0.0)) return Status::invalidArgument("no chest found at " + metres(chestY));

    // Shoulder tips: the outer edge of shoulders and upper arms a little below the joints.
    {
        detail::slicePoints(positions, triangles, torsoArms, m.shoulderY - 0.03 * h, points);
        if (points.size() < 2) return Status::invalidArgument("no shoulders found at " + metres(m.shoulderY));
        double aLo = std::numeric_limits<double>::max(), aHi = std::numeric_limits<double>::lowest();
        for (const Vec2& p : points) {
            const double a = p.x() * m.left.x() + p.y() * m.left.z();
            aLo = std::min(aLo, a), aHi = std::max(aHi, a);
        }
        m.shoulderWidth = aHi - aLo;
        const double b = (m.chest.centre.x() * m.forward.x() + m.chest.centre.z() * m.forward.z());
        for (int side = 0; side < 2; ++side) {
            const double tip = side == 0 ? aHi : aLo;
            double top = m.shoulderY - 0.03 * h;
            for (std::size_t v = 0; v < positions.size(); ++v) {
                const BodyRegion g = regions.vertices[v];
                if (g != BodyRegion::Torso && !isArm(g)) continue;
                const double a = positions[v].dot(m.left);
                if (std::abs(a - tip) < 0.06 * h && positions[v].y() < m.shoulderY + 0.06 * h) top = std::max(top, positions[v].y());
            }
            (side == 0 ? m.leftShoulder : m.rightShoulder) = tip * m.left + b * m.forward + Vec3(0.0, top, 0.0);
        }
    }

    // Neck: the narrowest section of the column above the shoulders; its base is where the column
    // first narrows to near that width going up.
    {
        double narrowest = std::numeric_limits<double>::max(), narrowestY = m.shoulderY;
        const double top = m.shoulderY + 0.8 * (m.topY - m.shoulderY);
        for (double y = m.shoulderY; y <= top; y += step) {
            const BodyRing r = ring(column, y);
            if (r.girth > 0.0 && r.girth < narrowest) narrowest = r.girth, narrowestY = y;
        }
        if (narrowest == std::numeric_limits<double>::max())
            return Status::invalidArgument("no neck found above the shoulders (" + metres(m.shoulderY) + ")");
        for (double y = m.shoulderY; y <= narrowestY; y += step) {
            BodyRing r = ring(column, y);
            if (r.girth > 0.0 && r.girth <= 1.35 * narrowest) {
                m.neck = std::move(r);
                break;
            }
        }
        if (!(m.neck.girth > 0.0)) m.neck = ring(column, narrowestY);
    }

    // The landmarks must stack up like a body's.
    const struct {
        double below, above;
        const char* what;
    } order[] = {{m.groundY, m.crotchY, "crotch above the ground"},     {m.crotchY, m.hips.height, "hips above the crotch"},
                 {m.hips.height, m.waist.height, "waist above the hips"}, {m.waist.height, m.chest.height, "chest above the waist"},
                 {m.chest.height, m.shoulderY, "shoulders above the chest"}, {m.chest.height, m.neck.height, "neck above the chest"},
                 {m.neck.height, m.topY, "head above the neck"}};
    for (const auto& o : order)
        if (!(o.below < o.above || (o.below == o.above && o.below == m.crotchY)))
            return Status::invalidArgument(std::string("the measured landmarks are out of order: expected the ") + o.what + " (" +
                                           metres(o.above) + " vs " + metres(o.below) + ")");
    if (!(m.neck.girth < m.chest.girth))
        return Status::invalidArgument("the neck (" + metres(m.neck.girth) + " girth) is not narrower than the chest (" +
                                       metres(m.chest.girth) + ")");
    return m;
}

void relaxedArmsPose(const Character& character, const BodyRegions& regions, Span<const Vec3> restPositions,
                     double abduction, double threshold, Span<Transform> outLocal) {
    const Skeleton& s = character.skeleton;
    s.restPose(outLocal);
    std::vector<Mat4> global(s.jointCount());
    s.computeGlobalTransforms(Span<const Transform>(outLocal.data(), outLocal.size()), global);
    for (int side = 0; side < 2; ++side) {
        const int32_t joint = regions.upperArm[std::size_t(side)];
        if (joint < 0) continue;
        const BodyRegion arm = side == 0 ? BodyRegion::LeftArm : BodyRegion::RightArm;
        Vec3 centroid = Vec3::Zero();
        std::size_t count = 0;
        for (std::size_t v = 0; v < restPositions.size(); ++v)
            if (regions.vertices[v] == arm) centroid += restPositions[v], ++count;
        if (count == 0) continue;
        const Vec3 shoulder = global[std::size_t(joint)].topRightCorner<3, 1>();
        const Vec3 along = centroid / double(count) - shoulder;
        if (along.norm() < 1e-9) continue;
        const double fromVertical = std::acos(std::clamp(along.normalized().dot(-Vec3::UnitY()), -1.0, 1.0));
        if (fromVertical <= threshold) continue;
        // Swing the arm about the shoulder, in the plane of the arm and the vertical, down to
        // `abduction` from vertical.
        Vec3 axis = along.cross(-Vec3::UnitY());
        if (axis.norm() < 1e-9) continue;
        const Quat swing(Eigen::AngleAxisd(fromVertical - abduction, axis.normalized()));
        const int32_t parent = s.joints[std::size_t(joint)].parent;
        Mat3 parentRotation = Mat3::Identity();
        if (parent >= 0) {
            const Mat3 linear = global[std::size_t(parent)].topLeftCorner<3, 3>();
            parentRotation = linear.colwise().normalized();
        }
        const Quat inParent(parentRotation.transpose() * swing.toRotationMatrix() * parentRotation);
        outLocal[std::size_t(joint)].rotation = (inParent * outLocal[std::size_t(joint)].rotation).normalized();
    }
}

} // namespace cc
