#include "crowdcloth/character/BodyRegions.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "BodySlices.h"

namespace cc {
namespace {

/// One tracked cross-section: the loop of a part at one slice height.
struct Section {
    bool present = false;
    std::vector<Vec2> hull;
    Vec2 centroid = Vec2::Zero();
    double perimeter = 0.0;
};

double area(const std::vector<Vec2>& hull) {
    double a = 0.0;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec2& p = hull[i];
        const Vec2& q = hull[(i + 1) % hull.size()];
        a += p.x() * q.y() - p.y() * q.x();
    }
    return 0.5 * a;
}

Section sectionOf(const detail::SliceLoop& loop) {
    Section s;
    s.present = true;
    s.hull = convexHull(loop.points);
    s.centroid = loop.centroid;
    s.perimeter = detail::perimeter(s.hull);
    return s;
}

/// The loop of `loops` that continues a part last seen with centroid `from`: the largest one whose
/// hull holds that centroid, else the nearest within `reach`; -1 when the part ends here.
int follow(const std::vector<detail::SliceLoop>& loops, const std::vector<Section>& sections, const Vec2& from,
           double margin, double reach) {
    int best = -1;
    double bestArea = -1.0;
    for (std::size_t i = 0; i < loops.size(); ++i) {
        if (!detail::insideConvex(sections[i].hull, from, margin)) continue;
        const double a = area(sections[i].hull);
        if (a > bestArea) best = int(i), bestArea = a;
    }
    if (best >= 0) return best;
    double nearest = reach;
    for (std::size_t i = 0; i < loops.size(); ++i) {
        const double d = (sections[i].centroid - from).norm();
        if (d < nearest) best = int(i), nearest = d;
    }
    return best;
}

} // namespace

Result<BodyRegions> findBodyRegionsFromGeometry(const SkinnedMesh& mesh) {
    const std::vector<Vec3>& p = mesh.bindPositions;
    if (p.empty() || mesh.triangles.empty()) return Status::invalidArgument("the body mesh is empty");
    double minY = std::numeric_limits<double>::max(), maxY = std::numeric_limits<double>::lowest();
    for (const Vec3& q : p) minY = std::min(minY, q.y()), maxY = std::max(maxY, q.y());
    const double h = maxY - minY;
    if (!(h > 0.0)) return Status::invalidArgument("the body mesh is flat");
    const int sliceCount = 200;
    const double step = h / sliceCount;
    const auto sliceY = [&](int k) { return minY + (k + 0.5) * step; };
    const std::vector<uint8_t> all;
    std::vector<std::vector<detail::SliceLoop>> loops(sliceCount);
    const std::vector<uint32_t> sameIds = detail::samePositionIds(p);
    std::vector<std::vector<Section>> sections(sliceCount);
    for (int k = 0; k < sliceCount; ++k) {
        detail::sliceLoops(p, mesh.triangles, all, sameIds, sliceY(k), loops[k]);
        for (const auto& loop : loops[k]) sections[k].push_back(sectionOf(loop));
    }
    // margin: how far outside a section's hull a point still continues it (tracking); skin: how
    // far a vertex may lie outside the hull of its slice and still belong to it (a vertex sits up
    // to half a slice above or below the cut, on a surface that slopes).
    const double margin = 0.01 * h, reach = 0.08 * h, skin = 0.003 * h;

    // The torso: the largest section at 55% of the height, followed down to the crotch (where its
    // centre falls between the legs) and up through the neck and head.
    std::vector<Section> torso(sliceCount);
    std::vector<int> torsoLoop(sliceCount, -1);  // which of sections[k] the torso is
    const int start = int(0.55 * sliceCount);
    {
        int best = -1;
        double bestArea = 0.0;
        for (std::size_t i = 0; i < sections[start].size(); ++i) {
            const double a = area(sections[start][i].hull);
            if (a > bestArea) best = int(i), bestArea = a;
        }
        if (best < 0) return Status::invalidArgument("the body has no cross-section at 55% of its height");
        torso[start] = sections[start][std::size_t(best)];
        torsoLoop[start] = best;
    }
    int crotch = -1;
    for (int k = start - 1; k >= 0; --k) {
        const int i = follow(loops[k], sections[k], torso[k + 1].centroid, 0.0, 0.0);
        if (i < 0) {
            crotch = k;
            break;
        }
        torso[k] = sections[k][std::size_t(i)];
        torsoLoop[k] = i;
    }
    if (crotch < int(0.15 * sliceCount))
        return Status::invalidArgument("no torso found: the body's cross-sections never split into two legs");
    int top = start;
    for (int k = start + 1; k < sliceCount; ++k) {
        const int i = follow(loops[k], sections[k], torso[k - 1].centroid, margin, reach);
        if (i < 0) break;
        torso[k] = sections[k][std::size_t(i)];
        torsoLoop[k] = i;
        top = k;
    }

    // Legs: the two largest sections just above the ground, followed up to the crotch.
    std::array<std::vector<Section>, 2> legs{std::vector<Section>(sliceCount), std::vector<Section>(sliceCount)};
    {
        const int k0 = std::min(2, crotch);
        std::vector<std::size_t> order(sections[k0].size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return sections[k0][a].perimeter != sections[k0][b].perimeter ? sections[k0][a].perimeter > sections[k0][b].perimeter : a < b;
        });
        if (order.size() < 2) return Status::invalidArgument("no two legs found: the body does not stand on two feet");
        for (int leg = 0; leg < 2; ++leg) {
            legs[leg][k0] = sections[k0][order[std::size_t(leg)]];
            for (int k = k0 + 1; k <= crotch; ++k) {
                const int i = follow(loops[k], sections[k], legs[leg][k - 1].centroid, margin, reach);
                if (i < 0) break;
                legs[leg][k] = sections[k][std::size_t(i)];
            }
            for (int k = k0 - 1; k >= 0; --k) {  // down to the soles
                const int i = follow(loops[k], sections[k], legs[leg][k + 1].centroid, margin, reach);
                if (i < 0) break;
                legs[leg][k] = sections[k][std::size_t(i)];
            }
        }
    }

    // Below the crotch a leg is its tracked section and every section overlapping it (a body
    // modelled as overlapping parts has a foot and a shin, or a shin and a thigh, side by side at
    // one height); what overlaps no leg is a hand hanging beside the thighs.
    std::vector<std::vector<const std::vector<Vec2>*>> legHulls{std::size_t(crotch + 1)};
    for (int k = 0; k <= crotch; ++k)
        for (int leg = 0; leg < 2; ++leg) {
            if (!legs[leg][k].present) continue;
            legHulls[std::size_t(k)].push_back(&legs[leg][k].hull);
            for (const Section& other : sections[k]) {
                if (other.hull == legs[leg][k].hull) continue;
                bool overlaps = detail::insideConvex(legs[leg][k].hull, other.centroid, 0.0);
                for (std::size_t i = 0; i < other.hull.size() && !overlaps; ++i)
                    overlaps = detail::insideConvex(legs[leg][k].hull, other.hull[i], 0.0);
                if (overlaps) legHulls[std::size_t(k)].push_back(&other.hull);
            }
        }
    const auto sliceOf = [&](const Vec3& q) { return std::clamp(int(std::floor((q.y() - minY) / step)), 0, sliceCount - 1); };
    const auto inLeg = [&](const Vec3& q) {
        const int k = sliceOf(q);
        if (k > crotch) return false;
        for (const std::vector<Vec2>* hull : legHulls[std::size_t(k)])
            if (detail::insideConvex(*hull, Vec2(q.x(), q.z()), margin)) return true;
        return false;
    };

    // The lateral axis: the main horizontal spread of the upper body; facing from the feet (toes
    // point forward).
    Vec2 mean = Vec2::Zero();
    std::size_t n = 0;
    for (const Vec3& q : p)
        if (q.y() > minY + 0.45 * h) mean += Vec2(q.x(), q.z()), ++n;
    mean /= double(std::max<std::size_t>(n, 1));
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const Vec3& q : p)
        if (q.y() > minY + 0.45 * h) cov += (Vec2(q.x(), q.z()) - mean) * (Vec2(q.x(), q.z()) - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    Vec2 lateral = eig.eigenvectors().col(1);
    Vec2 forward(-lateral.y(), lateral.x());
    {
        Vec2 toes = Vec2::Zero(), shins = Vec2::Zero();
        std::size_t toeCount = 0, shinCount = 0;
        for (const Vec3& q : p) {
            const double f = (q.y() - minY) / h;
            if (!inLeg(q)) continue;  // hands may hang as low as the shins
            if (f < 0.04) toes += Vec2(q.x(), q.z()), ++toeCount;
            else if (f > 0.12 && f < 0.25) shins += Vec2(q.x(), q.z()), ++shinCount;
        }
        // Without a clear foot direction the body is taken to face +Z (glTF's convention).
        double ahead = Vec2(0.0, 1.0).dot(forward);
        if (toeCount > 0 && shinCount > 0) {
            const Vec2 d = toes / double(toeCount) - shins / double(shinCount);
            if (d.norm() > 0.01 * h) ahead = d.dot(forward);
        }
        if (ahead < 0.0) forward = -forward;
        lateral = Vec2(forward.y(), -forward.x());  // left = up x forward
    }

    // Where the arms join the torso: its width jumps above the median chest width (one surface
    // for the whole body), or another section starts to overlap it (a body modelled as separate
    // overlapping parts, whose arms are closed meshes of their own).
    std::vector<double> widths;
    const auto widthOf = [&](const Section& s) {
        double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
        for (const Vec2& q : s.hull) lo = std::min(lo, q.dot(lateral)), hi = std::max(hi, q.dot(lateral));
        return 0.5 * (hi - lo);
    };
    for (int k = crotch + 1; k <= start; ++k)
        if (torso[k].present) widths.push_back(widthOf(torso[k]));
    std::sort(widths.begin(), widths.end());
    const double chestHalfWidth = widths.empty() ? 0.1 * h : widths[widths.size() / 2];
    const auto armJoins = [&](int k) {
        if (widthOf(torso[k]) > 1.25 * chestHalfWidth) return true;
        for (std::size_t i = 0; i < sections[k].size(); ++i) {
            if (int(i) == torsoLoop[k]) continue;
            const Vec2 c = sections[k][i].centroid;
            if (std::abs((c - torso[k].centroid).dot(lateral)) < 0.5 * chestHalfWidth) continue;  // neck, not arm
            for (const Vec2& q : sections[k][i].hull)
                if (detail::insideConvex(torso[k].hull, q, 0.0)) return true;
        }
        return false;
    };
    int merged = top + 1;
    for (int k = start; k <= top; ++k)
        if (armJoins(k)) {
            merged = k;
            break;
        }
    // Above the shoulders: the narrowest section below the head's widest is the neck, the head is
    // what lies above it. The head's widest section lies in the top tenth of the height (a head is
    // an eighth of an adult's height, its widest part half-way up it; the shoulders lie lower).
    int headWidest = top;
    {
        double widest = -1.0;
        for (int k = std::max(merged, top - sliceCount / 10); k <= top; ++k)
            if (torso[k].present && torso[k].perimeter > widest) widest = torso[k].perimeter, headWidest = k;
    }
    int neckK = -1;
    double narrowest = std::numeric_limits<double>::max();
    for (int k = merged; k < headWidest; ++k) {
        if (!torso[k].present) continue;
        if (widthOf(torso[k]) <= 1.25 * chestHalfWidth && torso[k].perimeter < narrowest)
            narrowest = torso[k].perimeter, neckK = k;
    }
    if (neckK < 0) return Status::invalidArgument("no head found: nothing narrows into a neck above the shoulders");
    int neckBase = neckK;
    for (int k = merged; k <= neckK; ++k)
        if (torso[k].present && torso[k].perimeter <= 1.35 * narrowest) {
            neckBase = k;
            break;
        }

    // Above the armpits the arms and the torso are one section (one surface for the whole body):
    // the shoulder joint lies over the armpit, so what lies farther out than the torso's widest
    // section below the armpits is arm.
    double armpitHalfWidth = 0.0;
    for (int k = start; k < merged && k <= top; ++k) armpitHalfWidth = std::max(armpitHalfWidth, widthOf(torso[k]));
    if (merged <= start) armpitHalfWidth = 1.15 * chestHalfWidth;

    // The torso at each height: the section followed and every section overlapping it (a body
    // built of pieces: a belt, a breastplate) that lies not beside the arms.
    std::vector<std::vector<const std::vector<Vec2>*>> torsoHulls{std::size_t(sliceCount)};
    for (int k = crotch + 1; k <= top; ++k) {
        if (!torso[k].present) continue;
        torsoHulls[std::size_t(k)].push_back(&torso[k].hull);
        for (std::size_t i = 0; i < sections[k].size(); ++i) {
            if (int(i) == torsoLoop[k]) continue;
            const Section& other = sections[k][i];
            if (k >= merged && std::abs((other.centroid - torso[k].centroid).dot(lateral)) > 0.5 * armpitHalfWidth) continue;
            bool overlaps = detail::insideConvex(torso[k].hull, other.centroid, 0.0);
            for (std::size_t j = 0; j < other.hull.size() && !overlaps; ++j)
                overlaps = detail::insideConvex(torso[k].hull, other.hull[j], 0.0);
            if (overlaps) torsoHulls[std::size_t(k)].push_back(&other.hull);
        }
    }
    const auto inTorso = [&](int k, const Vec2& q) {
        for (const std::vector<Vec2>* hull : torsoHulls[std::size_t(k)])
            if (detail::insideConvex(*hull, q, skin)) return true;
        return false;
    };

    BodyRegions r;
    r.method = "geometry";
    r.left = Vec3(lateral.x(), 0.0, lateral.y());
    r.forward = Vec3(forward.x(), 0.0, forward.y());
    r.vertices.resize(p.size());
    r.anchorWeight.resize(p.size());
    const Vec2 torsoCentre = torso[start].centroid;
    for (std::size_t v = 0; v < p.size(); ++v) {
        const Vec2 q(p[v].x(), p[v].z());
        const int k = sliceOf(p[v]);
        const bool leftSide = (q - torsoCentre).dot(lateral) >= 0.0;
        BodyRegion g = leftSide ? BodyRegion::LeftArm : BodyRegion::RightArm;
        const bool besideArms = std::abs((q - torsoCentre).dot(lateral)) > armpitHalfWidth;
        if (k <= crotch) {
            if (inLeg(p[v])) g = leftSide ? BodyRegion::LeftLeg : BodyRegion::RightLeg;
        } else if (k >= neckK) {
            // Everything above the neck is head: hair, eyes and helmets are often meshes of their
            // own, outside the section that was followed.
            g = BodyRegion::Head;
        } else if (k >= neckBase) {
            if (!besideArms) g = BodyRegion::Neck;
        } else if (inTorso(k, q) && (k < merged || !besideArms)) {
            g = BodyRegion::Torso;
        }
        r.vertices[v] = g;
        // Above the armpits the arm's skin reaches in over the shoulder joint: towards the
        // armpits' width a vertex is less and less surely torso.
        double sure = 1.0;
        if (k >= merged) sure = std::clamp((armpitHalfWidth - std::abs((q - torsoCentre).dot(lateral))) / (0.25 * armpitHalfWidth), 0.0, 1.0);
        r.anchorWeight[v] = (g == BodyRegion::Torso || g == BodyRegion::Neck) ? sure : 0.0;
    }
    std::array<std::size_t, 7> count{};
    for (BodyRegion g : r.vertices) ++count[std::size_t(g)];
    if (count[std::size_t(BodyRegion::LeftLeg)] == 0 || count[std::size_t(BodyRegion::RightLeg)] == 0)
        return Status::invalidArgument("no two legs found below the crotch");
    if (count[std::size_t(BodyRegion::Torso)] == 0) return Status::invalidArgument("no torso found");
    return r;
}

} // namespace cc
