#include "GarmentFit.h"

#include "PlacementRelaxation.h"

#include "crowdcloth/core/BoundingSphere.h"
#include "crowdcloth/core/ConvexHull.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

namespace cc::detail {
namespace {

/// [rad] how far a thigh swings forward (and the other back) in a stride: skirts and dresses are
/// cut wide enough to clear both knees at this swing (a walk swings ~20-25 degrees, a run more),
/// or at the widest stride of the body's own clips where that is wider (measured: CesiumMan's
/// walk 47 degrees, RobotExpressive's run 68; cut for 30, their legs tore through the hem), up to
/// kWidestStride (a split or a fall is no stride to cut for).
constexpr double kStrideAngle = 30.0 * kPi / 180.0;
constexpr double kWidestStride = 75.0 * kPi / 180.0;
/// [rad] the steepest outward slope a hanging panel starts at; more flare than that starts folded
/// in waves (godets), so a circle skirt starts hanging instead of flat at the waist.
constexpr double kMaxDropSlope = 50.0 * kPi / 180.0;
/// [rad] least flare of an A-line cut, as the slope of its cone.
constexpr double kALineSlope = 8.0 * kPi / 180.0;
/// [rad] how far an arm swings forward and back from where the garment is fitted (a walk swings
/// the upper arm ~20-30 degrees, a run more): capes and ponchos are cut to clear the arms anywhere
/// in this swing, since the clip a body plays need not hold its arms where the fit did.
constexpr double kArmSwing = 35.0 * kPi / 180.0;
/// [rad] how far behind the body's sides (seen from above) a cape's arc ends.
constexpr double kCapeInset = 0.4;
/// [m] below its top row a garment's clearance from the body grows from the top row's (the
/// attachment line hugs the body) to the full clearance: a step there would stretch the first rows.
constexpr double kClearanceRamp = 0.1;
constexpr int kRingSamples = 360;   ///< ring points by normal direction (before resampling)
constexpr int kPlacementColumns = 256;
constexpr int kPlacementRows = 48;  ///< per panel

/// The horizontal frame of the body: points as (x, z), directions by angle from its left towards
/// its front (theta = 0 left, pi/2 front, pi right, 3 pi / 2 back).
struct Frame {
    Vec2 left, forward;
    Vec2 direction(double theta) const { return std::cos(theta) * left + std::sin(theta) * forward; }
};

Vec2 flat(const Vec3& p) { return Vec2(p.x(), p.z()); }

double polylineLength(const std::vector<Vec2>& p, bool closed) {
    double length = 0.0;
    for (std::size_t i = 1; i < p.size(); ++i) length += (p[i] - p[i - 1]).norm();
    if (closed && p.size() > 1) length += (p.front() - p.back()).norm();
    return length;
}

/// Support point of a convex polygon in direction n.
Vec2 support(const std::vector<Vec2>& hull, const Vec2& n) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < hull.size(); ++i)
        if (hull[i].dot(n) > hull[best].dot(n)) best = i;
    return hull[best];
}

/// The ring around a convex region at distance `offset`, plus `waves` outward bulges of height
/// `amplitude`, by normal direction from theta0 to theta1 (a closed ring when the span is 2 pi).
std::vector<Vec2> ringAround(const std::vector<Vec2>& hull, const Frame& f, double offset, double amplitude, int waves,
                             double theta0, double theta1) {
    const bool closed = std::abs(theta1 - theta0 - 2.0 * kPi) < 1e-9;
    const int n = closed ? kRingSamples : kRingSamples / 2 + 1;
    std::vector<Vec2> ring(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double u = closed ? double(i) / n : double(i) / (n - 1);
        const double theta = theta0 + u * (theta1 - theta0);
        const Vec2 normal = f.direction(theta);
        const double bulge = amplitude * 0.5 * (1.0 - std::cos(2.0 * kPi * waves * u));
        ring[std::size_t(i)] = support(hull, normal) + (offset + bulge) * normal;
    }
    return ring;
}

/// `count` + 1 points at equal arc length along a polyline, from arc length `from` over `span`
/// (a closed polyline wraps around).
std::vector<Vec2> resample(const std::vector<Vec2>& p, bool closed, double from, double span, int count) {
    std::vector<double> at(p.size() + 1, 0.0);
    for (std::size_t i = 1; i <= p.size(); ++i) {
        if (i == p.size() && !closed) break;
        at[i] = at[i - 1] + (p[i % p.size()] - p[i - 1]).norm();
    }
    const double total = closed ? at[p.size()] : at[p.size() - 1];
    const std::size_t segments = closed ? p.size() : p.size() - 1;
    std::vector<Vec2> out(std::size_t(count) + 1);
    std::size_t seg = 0;
    for (int k = 0; k <= count; ++k) {
        double a = from + span * k / count;
        if (closed) a = std::fmod(std::fmod(a, total) + total, total);
        a = std::clamp(a, 0.0, total);
        if (closed || k == 0 || a < at[seg]) seg = 0;
        while (seg + 1 < segments && at[seg + 1] < a) ++seg;
        const double len = at[seg + 1] - at[seg];
        const double w = len > 0.0 ? (a - at[seg]) / len : 0.0;
        out[std::size_t(k)] = (1.0 - w) * p[seg] + w * p[(seg + 1) % p.size()];
    }
    if (closed && std::abs(span - total) <= 1e-9 * total) out.back() = out.front();  // a full turn closes exactly
    return out;
}

/// Arc length along a polyline to its point nearest q.
double arcPositionOf(const std::vector<Vec2>& p, bool closed, const Vec2& q) {
    double best = std::numeric_limits<double>::max(), bestAt = 0.0, at = 0.0;
    const std::size_t segments = closed ? p.size() : p.size() - 1;
    for (std::size_t i = 0; i < segments; ++i) {
        const Vec2& a = p[i];
        const Vec2& b = p[(i + 1) % p.size()];
        const Vec2 ab = b - a;
        const double len2 = ab.squaredNorm();
        const double t = len2 > 0.0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        const double d = (a + t * ab - q).norm();
        if (d < best) best = d, bestAt = at + t * std::sqrt(len2);
        at += std::sqrt(len2);
    }
    return bestAt;
}

/// Outside distance of p from a convex CCW polygon (<= 0 inside).
double outside(const std::vector<Vec2>& hull, const Vec2& p) {
    double worst = std::numeric_limits<double>::lowest();
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec2& a = hull[i];
        const Vec2 e = hull[(i + 1) % hull.size()] - a;
        const double len = e.norm();
        if (len > 0.0) worst = std::max(worst, -(e.x() * (p.y() - a.y()) - e.y() * (p.x() - a.x())) / len);
    }
    return worst;
}


std::string cm(double metres) { return std::to_string(int(std::lround(100.0 * metres))) + " cm"; }

/// The body as the fitting sees it: its sections in the rest pose with the arms relaxed.
class Envelope {
public:
    /// `armSwing` [rad]: how far the arms swing forward and back in what hangs over them.
    Envelope(const BodyAsset& body, double armSwing) : mBody(body) {
        const auto& tris = body.mesh().triangles;
        const auto& regions = body.regions.vertices;
        mTrunkLegs = trianglesOf(tris, regions, {BodyRegion::Torso, BodyRegion::LeftLeg, BodyRegion::RightLeg});
        mArms = trianglesOf(tris, regions, {BodyRegion::LeftArm, BodyRegion::RightArm});
        mAllButHead = trianglesOf(tris, regions, {BodyRegion::Torso, BodyRegion::Neck, BodyRegion::LeftArm, BodyRegion::RightArm,
                                                  BodyRegion::LeftLeg, BodyRegion::RightLeg});
        // The arms swung forward and back about the shoulders' axis (the body's left, through the
        // shoulder line above the chest's centre).
        const BodyMeasurements& m = body.measurements;
        const Vec3 pivot(m.chest.centre.x(), m.shoulderY, m.chest.centre.z());
        for (double angle : {-armSwing, armSwing}) {
            if (armSwing == 0.0) break;
            const Mat3 turn = Eigen::AngleAxisd(angle, m.left.normalized()).toRotationMatrix();
            std::vector<Vec3> p = body.fitPositions;
            for (std::size_t v = 0; v < p.size(); ++v)
                if (isArm(regions[v])) p[v] = pivot + turn * (p[v] - pivot);
            mSwung.push_back(std::move(p));
        }
    }
    /// Cross-section points of the trunk and legs (or, `withArms`, of everything below the head,
    /// the arms anywhere in their swing).
    void body(double y, bool withArms, std::vector<Vec2>& out) const {
        out = slice(mBody.fitPositions, withArms ? mAllButHead : mTrunkLegs, y);
        if (!withArms) return;
        for (const std::vector<Vec3>& p : mSwung) {
            const std::vector<Vec2> arms = slice(p, mArms, y);
            out.insert(out.end(), arms.begin(), arms.end());
        }
        out = convexHull(out);
    }
    /// Cross-section points of the arms where the garment is fitted.
    void arms(double y, std::vector<Vec2>& out) const { out = slice(mBody.fitPositions, mArms, y); }

private:
    std::vector<Vec2> slice(const std::vector<Vec3>& positions, const std::vector<uint8_t>& keep, double y) const {
        return measureRing(positions, mBody.mesh().triangles, keep, y, Vec3::UnitX(), Vec3::UnitZ()).hull;
    }
    const BodyAsset& mBody;
    std::vector<uint8_t> mTrunkLegs, mArms, mAllButHead;
    std::vector<std::vector<Vec3>> mSwung;  ///< fitPositions with the arms swung back, then forward
};

/// One section of a garment (a panel or a ring of panels) as rows of rings from its top down.
struct Section {
    std::vector<std::vector<Vec2>> rings;  ///< dense polylines (closed rings or open back arcs)
    std::vector<double> heights;           ///< [m] y of each ring
    bool closed = true;
};

/// What a hanging section is asked to do.
struct DropSpec {
    bool closed = true;          ///< a ring all round (skirt, dress, poncho) or an arc behind (cape)
    double theta0 = 0.0, theta1 = 2.0 * kPi;  ///< [rad] directions the rows span (Frame::direction)
    bool withArms = false;       ///< hangs over the arms (cape, poncho) instead of inside them
    bool capByArms = false;      ///< stays inside the arms (skirt, dress)
    double topWidth = 0.0;       ///< [m] rest length of the top row
    double flare = 0.0;          ///< [rad] rest sector angle (row length grows flare per metre down)
    double length = 0.0;         ///< [m] slant length
    double clearance = 0.0;      ///< [m] from the body, reached kClearanceRamp below the top
    double topClearance = 0.0;   ///< [m] from the body at the top row
    std::vector<Vec2> topRing;   ///< the top row (placed), continuing a yoke or the attachment line
    double topY = 0.0;
    Vec2 axis = Vec2::Zero();    ///< centre the body's sections are pushed out from by the clearance
};

double clearanceAt(const DropSpec& spec, double depth) {
    return spec.topClearance + (spec.clearance - spec.topClearance) * std::clamp(depth / kClearanceRamp, 0.0, 1.0);
}

/// Rows of a hanging section: each row's ring clears everything of the body above it (and the
/// row above), has exactly its rest length (offset outwards, then folded into waves when the slope
/// would exceed kMaxDropSlope), and lies one rest row spacing below the row above along the cloth.
/// `outShortfall` gets the largest rest length missing where the body needs more than the cut gives.
Section hangSection(const Envelope& envelope, const Frame& f, const DropSpec& spec, double& outShortfall, double& outShortfallY) {
    Section s;
    s.closed = spec.closed;
    s.rings.push_back(spec.topRing);
    s.heights.push_back(spec.topY);
    outShortfall = 0.0;
    const int rows = kPlacementRows;
    const double ds = spec.length / rows;
    const double theta0 = spec.theta0, theta1 = spec.theta1;
    const double turning = theta1 - theta0;
    std::vector<Vec2> inner = spec.topRing;  // grows: everything above must stay inside
    std::vector<Vec2> slice;
    double previousOffset = 0.0, y = spec.topY;
    double scanned = y;
    for (int k = 1; k <= rows; ++k) {
        const double want = spec.topWidth + spec.flare * ds * k;
        std::vector<Vec2> ring;
        double nextY = y - ds * std::cos(std::min(std::asin(std::min(1.0, spec.flare / turning)), kMaxDropSlope));
        for (int iteration = 0; iteration < 2; ++iteration) {
            // Body sections between the last scanned height and this row, pushed out by the clearance.
            std::vector<Vec2> points = inner;
            for (double yy = scanned; yy >= nextY; yy -= 0.005) {
                envelope.body(yy, spec.withArms, slice);
                const double c = clearanceAt(spec, spec.topY - yy);
                for (const Vec2& q : slice) {
                    const Vec2 d = q - spec.axis;
                    const double len = d.norm();
                    points.push_back(len > 0.0 ? Vec2(q + c * d / len) : q);
                }
            }
            const std::vector<Vec2> hull = convexHull(points);
            if (hull.size() < 3) break;
            // Offset for the exact length (the offset of a convex curve adds turning x offset).
            const double base = polylineLength(ringAround(hull, f, 0.0, 0.0, 1, theta0, theta1), spec.closed);
            double offset = (want - base) / turning;
            if (offset < 0.0 && !spec.closed) {
                // A cape narrower than the back behind it covers the middle of the back.
                const std::vector<Vec2> arc = ringAround(hull, f, 0.0, 0.0, 1, theta0, theta1);
                const double middle = arcPositionOf(arc, false, support(hull, f.direction(1.5 * kPi)));
                const double from = std::clamp(middle - 0.5 * want, 0.0, base - want);
                ring = resample(arc, false, from, want, kRingSamples / 2);
                previousOffset = 0.0;
                if (iteration == 0) {
                    nextY = y - ds;
                    continue;
                }
                break;
            }
            if (offset < 0.0) {
                if (-offset * turning > outShortfall) outShortfall = -offset * turning, outShortfallY = nextY;
                offset = 0.0;
            }
            offset = std::min(offset, previousOffset + ds * std::sin(kMaxDropSlope));
            double cap = std::numeric_limits<double>::max();
            if (spec.capByArms) {
                envelope.arms(nextY, slice);
                for (const Vec2& q : slice) {
                    const double d = outside(hull, q) - spec.clearance;
                    if (d > 0.0) cap = std::min(cap, d);
                }
                if (cap < std::numeric_limits<double>::max()) offset = std::min(offset, std::max(cap, 0.0));
            }
            // The length the slope could not give goes into waves.
            double amplitude = 0.0;
            int waves = spec.closed ? 8 : 4;
            const double plain = base + turning * offset;
            if (want > plain + 1e-4) {
                const double maxAmplitude = std::min(cap - offset, 0.3 * spec.length);
                for (; waves <= 32; waves *= 2) {
                    double lo = 0.0, hi = std::max(maxAmplitude, 0.0);
                    if (polylineLength(ringAround(hull, f, offset, hi, waves, theta0, theta1), spec.closed) < want) {
                        amplitude = hi;
                        continue;
                    }
                    for (int b = 0; b < 20; ++b) {
                        const double mid = 0.5 * (lo + hi);
                        (polylineLength(ringAround(hull, f, offset, mid, waves, theta0, theta1), spec.closed) < want ? lo : hi) = mid;
                    }
                    amplitude = hi;
                    break;
                }
                waves = std::min(waves, 32);
            }
            ring = ringAround(hull, f, offset, amplitude, waves, theta0, theta1);
            if (iteration == 0) {
                // The row lies one rest spacing below the row above along the cloth.
                const std::vector<Vec2> a = resample(s.rings.back(), spec.closed, 0.0, polylineLength(s.rings.back(), spec.closed), 64);
                const std::vector<Vec2> b = resample(ring, spec.closed, 0.0, polylineLength(ring, spec.closed), 64);
                double mean2 = 0.0;
                for (std::size_t i = 0; i < a.size(); ++i) mean2 += (a[i] - b[i]).squaredNorm();
                mean2 /= double(a.size());
                nextY = y - std::sqrt(std::max(ds * ds - mean2, 0.04 * ds * ds));
            }
            previousOffset = offset;
        }
        for (double yy = scanned; yy >= nextY; yy -= 0.005) {
            envelope.body(yy, spec.withArms, slice);
            const double c = clearanceAt(spec, spec.topY - yy);
            for (const Vec2& q : slice) {
                const Vec2 d = q - spec.axis;
                const double len = d.norm();
                inner.push_back(len > 0.0 ? Vec2(q + c * d / len) : q);
            }
        }
        inner = convexHull(inner);
        scanned = nextY;
        y = nextY;
        s.rings.push_back(ring);
        s.heights.push_back(y);
    }
    return s;
}

/// Samples a section's rows into a panel's placement: from arc length `from` over `span` of each
/// row (the span scaled with the row's length), `flip` reverses the direction along the row.
PanelPlacement placeRows(const Section& s, double fromFraction, double spanFraction, bool centred) {
    PanelPlacement p;
    const std::size_t n = s.rings.size();
    for (int r = 0; r <= kPlacementRows; ++r) {
        const double x = double(r) * double(n - 1) / kPlacementRows;
        const std::size_t i = std::min(std::size_t(x), n - 2);
        const double w = x - double(i);
        std::vector<Vec3> ring(kPlacementColumns + 1, Vec3::Zero());
        for (int side = 0; side < 2; ++side) {
            const std::vector<Vec2>& poly = s.rings[i + std::size_t(side)];
            const double total = polylineLength(poly, s.closed);
            double from = fromFraction * total, span = spanFraction * total;
            if (centred) from = std::clamp(from, 0.0, std::max(0.0, total - span));
            const std::vector<Vec2> pts = resample(poly, s.closed, from, span, kPlacementColumns);
            const double y = s.heights[i + std::size_t(side)];
            const double weight = side == 0 ? 1.0 - w : w;
            for (int c = 0; c <= kPlacementColumns; ++c) ring[std::size_t(c)] += weight * Vec3(pts[std::size_t(c)].x(), y, pts[std::size_t(c)].y());
        }
        p.rings.push_back(std::move(ring));
    }
    return p;
}

/// Base grid of a (flared) panel: columns about cellSize at the mean width, rows about cellSize,
/// kept within the pattern's 1:8 square aspect at the top and at the hem.
uint32_t rowsFor(double length, double top, double hem, uint32_t columns, double cellSize) {
    const double lo = std::ceil(columns * length / (8.0 * top)), hi = std::floor(8.0 * columns * length / hem);
    return uint32_t(std::clamp(std::round(length / cellSize), std::max(1.0, lo), std::max(1.0, std::max(lo, hi))));
}

lod::PanelDesc flaredPanel(lod::PanelShape shape, double top, double hem, double length, uint32_t columns, double cellSize) {
    lod::PanelDesc d;
    d.shape = shape;
    d.width = top;
    d.hemWidth = hem > top * (1.0 + 1e-9) ? std::min(hem, top + 2.0 * kPi * length) : 0.0;
    d.height = length;
    d.columns = columns;
    d.rows = rowsFor(length, top, std::max(hem, top), columns, cellSize);
    return d;
}

uint32_t columnsFor(double meanWidth, double cellSize, uint32_t minimum) {
    return uint32_t(std::clamp(std::round(meanWidth / cellSize), double(minimum), 4096.0));
}

double defaultRelativeLength(GarmentKind kind) {
    switch (kind) {
    case GarmentKind::Cape: return 0.5;
    case GarmentKind::Skirt: return 0.3;
    case GarmentKind::Dress: return 0.45;
    case GarmentKind::Poncho: return 0.3;
    }
    return 0.3;
}

const char* kindName(GarmentKind kind) {
    switch (kind) {
    case GarmentKind::Cape: return "cape";
    case GarmentKind::Skirt: return "skirt";
    case GarmentKind::Dress: return "dress";
    case GarmentKind::Poncho: return "poncho";
    }
    return "garment";
}

/// Pushes hull points out from `axis` by `by`.
std::vector<Vec2> pushedOut(const std::vector<Vec2>& hull, const Vec2& axis, double by) {
    std::vector<Vec2> out;
    for (const Vec2& q : hull) {
        const Vec2 d = q - axis;
        const double len = d.norm();
        out.push_back(len > 0.0 ? Vec2(q + by * d / len) : q);
    }
    return convexHull(out);
}

/// [body heights] farthest an attachment may start from the body.
constexpr double kAttachReach = 0.1;

/// [body heights] an attachment keeps at least this far from the arms.
constexpr double kAttachArmClearance = 0.02;

/// How far p (fitting pose) is from the body, from its torso and neck skin, and from its arms.
struct Nearness {
    BodyRegion region = BodyRegion::Torso;  ///< of the nearest skin
    double body = std::numeric_limits<double>::max();
    double torso = std::numeric_limits<double>::max();
    double arm = std::numeric_limits<double>::max();
};

Nearness nearnessOf(const BodyAsset& body, const Vec3& p) {
    Nearness n;
    const std::vector<Vec3>& x = body.fitPositions;
    for (const auto& t : body.mesh().triangles) {
        std::array<double, 3> barycentric;
        const double d = (closestPointOnTriangle(p, x[t[0]], x[t[1]], x[t[2]], barycentric) - p).norm();
        int corner = 0;
        for (int k = 1; k < 3; ++k)
            if (barycentric[std::size_t(k)] > barycentric[std::size_t(corner)]) corner = k;
        const BodyRegion g = body.regions.vertices[t[std::size_t(corner)]];
        if (isArm(g)) n.arm = std::min(n.arm, d);
        if (g == BodyRegion::Torso || g == BodyRegion::Neck) n.torso = std::min(n.torso, d);
        if (d < n.body) n.body = d, n.region = g;
    }
    return n;
}

/// Keeps the attachments that lie over the torso. Where the top line runs over an arm (a cape's
/// corners on the deltoids, a loose waistband by the elbows) the cloth rests there free, or the
/// swinging arm would tear it from its attached neighbours or pass through it. A point that hugs
/// the torso's skin (within `hug` of it: a fitted waistband) stays attached even where a hanging
/// arm touches it: it is bound to the torso's skin, the arm swings outside it.
Status keepTorsoAttachments(const BodyAsset& body, const std::string& what, double hug, FittedGarment& fit) {
    std::vector<PatternPoint> kept;
    const double h = body.measurements.height;
    for (const PatternPoint& a : fit.attached) {
        const lod::PanelDesc& d = fit.pattern.panels[a.panel];
        const Vec3 p = fit.placement[a.panel].at(double(a.i) / d.columns, double(a.j) / d.rows);
        const Nearness n = nearnessOf(body, p);
        const bool hugging = n.torso <= hug;
        const bool overTorso = hugging || ((n.region == BodyRegion::Torso || n.region == BodyRegion::Neck) && n.body <= kAttachReach * h);
        if (overTorso && (hugging || n.arm >= kAttachArmClearance * h)) kept.push_back(a);
    }
    if (kept.size() < 2)
        return Status::invalidArgument(what + ": its top line does not run over the torso (" + std::to_string(kept.size()) +
                                       " of " + std::to_string(fit.attached.size()) + " attachment points lie over torso skin)");
    fit.attached = std::move(kept);
    return Status::ok();
}

/// Skirts and dresses: a ring attached round the body at `ring`, hanging to the hem.
Result<FittedGarment> fitTube(const ClothAssetDesc& design, const BodyAsset& body, const BodyRing& top, double length,
                              const std::string& what) {
    const BodyMeasurements& m = body.measurements;
    const Frame f{flat(m.left), flat(m.forward)};
    const Envelope envelope(body, 0.0);  // a skirt or dress hangs inside the arms
    const double clearance = design.thickness + 0.01;
    const Vec2 axis = flat(top.centre);
    // The top ring hugs the body at the attachment line: its girth plus the collision thickness.
    const std::vector<Vec2> attach = pushedOut(top.hull, axis, design.thickness);
    const double least = polylineLength(ringAround(attach, f, 0.0, 0.0, 1, 0.0, 2.0 * kPi), true);
    // What the body below needs at each depth: round everything above it, and (A-line) below the
    // hips round both knees in a stride.
    std::vector<std::array<double, 3>> needs;  // (depth, round the body, with the stride)
    const double strideAngle = std::max(kStrideAngle, std::min(m.stride, kWidestStride));
    double needMax = 0.0;
    {
        std::vector<Vec2> points = attach, slice;
        for (double depth = 0.01; depth <= length + 1e-9; depth += 0.01) {
            const double y = top.height - depth;
            envelope.body(y, false, slice);
            const double c = design.thickness + (clearance - design.thickness) * std::min(1.0, depth / kClearanceRamp);
            for (const Vec2& q : pushedOut(slice, axis, c)) points.push_back(q);
            points = convexHull(points);
            const double need = polylineLength(ringAround(points, f, 0.0, 0.0, 1, 0.0, 2.0 * kPi), true);
            const double drop = std::max(0.0, m.hips.height - y);
            const double lateral = m.hips.halfWidth;
            const double swing =
                2.0 * (std::hypot(lateral, 2.0 * drop * std::sin(strideAngle)) - lateral);
            needs.push_back({depth, need, need + swing});
            needMax = std::max(needMax, need);
        }
    }
    double width = design.width > 0.0 ? design.width : least + design.ease;
    // A straight cut is as wide as the body is anywhere along it (a fitted one: hips plus ease).
    if (design.width == 0.0 && design.cut == GarmentCut::Straight) width = std::max(width, needMax + design.ease);
    if (width < least - 1e-9)
        return Status::invalidArgument(what + ": too small to fit: its top is " + cm(width) + " round, the body needs " + cm(least) +
                                       " (" + cm(top.girth) + " girth plus the collision thickness)");
    const std::vector<Vec2> topRing = ringAround(attach, f, (width - least) / (2.0 * kPi), 0.0, 1, 0.0, 2.0 * kPi);
    double required = 0.0;  // [rad] least flare for the body as it stands
    double stride = 0.0;    // [rad] least flare with the stride allowance
    for (const auto& [depth, need, withStride] : needs) {
        required = std::max(required, (need - width) / depth);
        stride = std::max(stride, (withStride - width) / depth);
    }
    double hem = design.hemWidth;  // as given, else the cut's
    if (!(hem > 0.0)) {
        switch (design.cut) {
        case GarmentCut::Straight: hem = width; break;
        case GarmentCut::ALine: hem = width + length * std::max(stride, 2.0 * kPi * std::sin(kALineSlope)); break;
        case GarmentCut::Circle: hem = width + 2.0 * kPi * length; break;
        }
    }
    hem = std::min(hem, width + 2.0 * kPi * length);
    if (hem < width) return Status::invalidArgument(what + ": the hem (" + cm(hem) + ") is narrower than the top (" + cm(width) + ")");
    const double flare = (hem - width) / length;
    if (flare + 1e-9 < required)
        return Status::invalidArgument(what + ": too small to fit: cut " + cm(width) + " at the top and " + cm(hem) +
                                       " at the hem, it cannot pass the body below (a " + cm(width + required * length) +
                                       " hem would); use an A-line cut or a larger size");

    DropSpec spec;
    spec.closed = true;
    spec.capByArms = true;
    spec.topWidth = width;
    spec.flare = flare;
    spec.length = length;
    spec.clearance = clearance;
    spec.topClearance = design.thickness;
    spec.topRing = topRing;
    spec.topY = top.height;
    spec.axis = axis;
    double shortfall = 0.0, shortfallY = 0.0;
    const Section section = hangSection(envelope, f, spec, shortfall, shortfallY);

    FittedGarment fit;
    fit.desc = design;
    fit.desc.width = width;
    fit.desc.length = length;
    fit.desc.hemWidth = hem;
    const double backCentre = arcPositionOf(topRing, true, support(topRing, f.direction(1.5 * kPi)));
    const double topLength = polylineLength(topRing, true);
    if (design.kind == GarmentKind::Skirt) {
        // One tube, its wrap seam at the back; u runs from the left towards the front.
        const uint32_t columns = columnsFor(0.5 * (width + hem), design.cellSize, 6);
        fit.pattern.panels.push_back(flaredPanel(lod::PanelShape::Tube, width, hem, length, columns, design.cellSize));
        fit.placement.push_back(placeRows(section, backCentre / topLength, 1.0, false));
        for (uint32_t i = 0; i < columns; ++i) fit.attached.push_back({0, i, fit.pattern.panels[0].rows});
    } else {
        // Front and back panels sewn at the sides: the front runs from the body's right round the
        // front to its left, the back from the left round the back to the right.
        const double rightSide = arcPositionOf(topRing, true, support(topRing, f.direction(kPi)));
        const uint32_t columns = columnsFor(0.25 * (width + hem), design.cellSize, 3);
        for (int panel = 0; panel < 2; ++panel) {
            fit.pattern.panels.push_back(flaredPanel(lod::PanelShape::Rectangle, 0.5 * width, 0.5 * hem, length, columns, design.cellSize));
            // Rows run with theta increasing (left -> front -> right): walk them backwards.
            PanelPlacement placed = placeRows(section, (rightSide / topLength) - 0.5 * (panel + 1), 0.5, false);
            for (auto& ring : placed.rings) std::reverse(ring.begin(), ring.end());
            fit.placement.push_back(std::move(placed));
            for (uint32_t i = 0; i <= columns; ++i) fit.attached.push_back({uint32_t(panel), i, fit.pattern.panels[std::size_t(panel)].rows});
        }
        fit.pattern.seams.push_back({0, lod::PanelSide::Right, 1, lod::PanelSide::Left, false});
        fit.pattern.seams.push_back({0, lod::PanelSide::Left, 1, lod::PanelSide::Right, false});
        // Drafted side by side: the back's left side on the front's right side (the front and
        // back together are the cone unrolled).
        lod::PanelDesc& back = fit.pattern.panels[1];
        const double sector = back.flareAngle();
        if (sector > 0.0) {
            const Vec2 apex(0.5 * back.width, back.height + back.width / sector);
            back.chartAngle = sector;
            back.chartOrigin = apex - Eigen::Rotation2Dd(sector) * apex;
        } else {
            back.chartOrigin = Vec2(back.width, 0.0);
        }
    }
    // A waistband hugging the waist stays attached beside a hanging arm; a dress's top runs under
    // the armpits, where the arm swings right against it: there it hangs free.
    const double hug = design.kind == GarmentKind::Skirt ? design.thickness + 0.01 * m.height : 0.0;
    if (Status s = keepTorsoAttachments(body, what, hug, fit); !s) return s;
    return fit;
}

/// Capes and ponchos: hung from the shoulder line (a cape behind, from one shoulder's tip round
/// the back of the neck to the other's; a poncho all round), attached along it. One panel: a yoke
/// sewn on would carry the drop's weight across a seam, and seams hold together only between
/// solver steps (their two copies are merged after each step), so a sewn yoke sags off its drop.
Result<FittedGarment> fitOverShoulders(const ClothAssetDesc& design, const BodyAsset& body, double length, double armSwing,
                                       const std::string& what) {
    const BodyMeasurements& m = body.measurements;
    const bool closed = design.kind == GarmentKind::Poncho;
    const Frame f{flat(m.left), flat(m.forward)};
    const Envelope envelope(body, armSwing);
    const double clearance = design.thickness + 0.01;
    // A cape's arc ends on the back of the shoulders, behind the arms: its sides then hang behind
    // the swinging arms instead of round them.
    const double turning = closed ? 2.0 * kPi : kPi - 2.0 * kCapeInset;
    const double theta0 = closed ? 0.0 : kPi + kCapeInset, theta1 = closed ? 2.0 * kPi : 2.0 * kPi - kCapeInset;
    // The shoulder line: the section of torso, neck and arms at the shoulder joints.
    const double topY = m.shoulderY;
    std::vector<Vec2> section;
    envelope.body(topY, true, section);
    if (section.size() < 3) return Status::invalidArgument(what + ": no shoulders found at y = " + std::to_string(topY) + " m");
    const Vec2 axis = flat(m.neck.centre);
    const std::vector<Vec2> line = pushedOut(section, axis, design.thickness);
    const std::vector<Vec2> hugging = ringAround(line, f, 0.0, 0.0, 1, theta0, theta1);
    const double least = polylineLength(hugging, closed);
    double width = design.width > 0.0 ? design.width : least + (closed ? design.ease : 0.0);
    if (closed && width < least - 1e-9)
        return Status::invalidArgument(what + ": too small to fit: its top is " + cm(width) + " round, the shoulders need " + cm(least));
    if (!closed && width < 0.25 * least)
        return Status::invalidArgument(what + ": too small to fit: " + cm(width) + " across, a quarter of the way round the back (" +
                                       cm(least) + ") at least");
    std::vector<Vec2> topRing;
    if (width >= least) {
        // Wider than the shoulders: it stands off them (a cape wrapped further round would lie
        // where the arms swing).
        topRing = ringAround(line, f, (width - least) / turning, 0.0, 1, theta0, theta1);
    } else {
        // A cape narrower than the back covers the middle of it.
        const double middle = arcPositionOf(hugging, false, support(line, f.direction(1.5 * kPi)));
        topRing = resample(hugging, false, std::clamp(middle - 0.5 * width, 0.0, least - width), width, kRingSamples / 2);
    }

    // A poncho must go round the body and arms below it (a cape may cover part of the back).
    double required = 0.0;
    if (closed) {
        std::vector<Vec2> points = line, slice;
        for (double depth = 0.01; depth <= length + 1e-9; depth += 0.01) {
            envelope.body(topY - depth, true, slice);
            const double c = design.thickness + (clearance - design.thickness) * std::min(1.0, depth / kClearanceRamp);
            for (const Vec2& q : pushedOut(slice, axis, c)) points.push_back(q);
            points = convexHull(points);
            const double need = polylineLength(ringAround(points, f, 0.0, 0.0, 1, 0.0, 2.0 * kPi), true);
            required = std::max(required, (need - width) / depth);
        }
    }
    double hem = design.hemWidth;  // as given, else the cut's
    if (!(hem > 0.0)) {
        switch (design.cut) {
        case GarmentCut::Straight: hem = width + length * required; break;
        case GarmentCut::ALine:
            hem = width + length * std::max(required, turning * std::sin(closed ? 10.0 * kPi / 180.0 : 6.0 * kPi / 180.0));
            break;
        case GarmentCut::Circle: hem = width + length * turning; break;
        }
    }
    hem = std::min(hem, width + 2.0 * kPi * length);
    if (hem < width) return Status::invalidArgument(what + ": the hem (" + cm(hem) + ") is narrower than the top (" + cm(width) + ")");
    if (closed && (hem - width) / length + 1e-9 < required)
        return Status::invalidArgument(what + ": too small to fit: cut " + cm(width) + " at the top and " + cm(hem) +
                                       " at the hem, it cannot go round the body and arms below (a " +
                                       cm(width + required * length) + " hem would)");
    DropSpec spec;
    spec.closed = closed;
    spec.theta0 = theta0, spec.theta1 = theta1;
    spec.withArms = true;
    spec.topWidth = width;
    spec.flare = (hem - width) / length;
    spec.length = length;
    spec.clearance = clearance;
    spec.topClearance = design.thickness;
    spec.topRing = topRing;
    spec.topY = topY;
    spec.axis = axis;
    double shortfall = 0.0, shortfallY = 0.0;
    const Section drop = hangSection(envelope, f, spec, shortfall, shortfallY);
    if (closed && shortfall > 0.02)
        return Status::invalidArgument(what + ": too small to fit: " + cm(shortfall) + " short of going round the body at y = " +
                                       std::to_string(shortfallY) + " m; use an A-line cut or a larger hem");

    FittedGarment fit;
    fit.desc = design;
    fit.desc.width = width;
    fit.desc.length = length;
    fit.desc.hemWidth = hem;
    const uint32_t columns = columnsFor(0.5 * (width + hem), design.cellSize, 6);
    fit.pattern.panels.push_back(
        flaredPanel(closed ? lod::PanelShape::Tube : lod::PanelShape::Rectangle, width, hem, length, columns, design.cellSize));
    double from = 0.0;
    if (closed) from = arcPositionOf(topRing, true, support(topRing, f.direction(1.5 * kPi))) / polylineLength(topRing, true);
    fit.placement.push_back(placeRows(drop, from, 1.0, false));
    const uint32_t topColumns = closed ? columns - 1 : columns;
    for (uint32_t i = 0; i <= topColumns; ++i) fit.attached.push_back({0, i, fit.pattern.panels[0].rows});
    if (Status s = keepTorsoAttachments(body, what, 0.0, fit); !s) return s;
    return fit;
}

} // namespace

Vec3 PanelPlacement::at(double s, double t) const {
    const double x = std::clamp(1.0 - t, 0.0, 1.0) * double(rings.size() - 1);
    const std::size_t r = std::min(std::size_t(x), rings.size() - 2);
    const double wr = x - double(r);
    const std::size_t columns = rings[0].size() - 1;
    const double y = std::clamp(s, 0.0, 1.0) * double(columns);
    const std::size_t c = std::min(std::size_t(y), columns - 1);
    const double wc = y - double(c);
    const auto row = [&](std::size_t i) { return (1.0 - wc) * rings[i][c] + wc * rings[i][c + 1]; };
    return (1.0 - wr) * row(r) + wr * row(r + 1);
}

namespace {

Result<FittedGarment> fitByKind(const ClothAssetDesc& design, const BodyAsset& body) {
    if (Status s = design.validate(); !s) return s;
    const std::string what = std::string(kindName(design.kind)) + " on " +
                             (body.character().name.empty() ? std::string("a host-skinned body") : "'" + body.character().name + "'");
    if (!body.fitStatus) return Status::invalidArgument(what + ": " + body.fitStatus.message());
    const BodyMeasurements& m = body.measurements;
    const double length = design.length > 0.0 ? design.length
                                              : (design.relativeLength > 0.0 ? design.relativeLength : defaultRelativeLength(design.kind)) * m.height;
    switch (design.kind) {
    case GarmentKind::Skirt: return fitTube(design, body, m.waist, length, what);
    case GarmentKind::Dress: return fitTube(design, body, m.chest, length, what);
    case GarmentKind::Cape:
    case GarmentKind::Poncho: {
        // Cut to clear the arms anywhere in their swing; a fitted garment that cannot (arms far from
        // the body, swinging wider than any cut goes round) is cut to clear them where they hang.
        auto swung = fitOverShoulders(design, body, length, kArmSwing, what);
        if (swung.isOk() || design.width > 0.0 || design.hemWidth > 0.0) return swung;
        return fitOverShoulders(design, body, length, 0.0, what);
    }
    }
    return Status::invalidArgument("ClothAssetDesc.kind is unknown");
}

} // namespace

Result<FittedGarment> fitGarment(const ClothAssetDesc& design, const BodyAsset& body) {
    auto fitted = fitByKind(design, body);
    if (!fitted.isOk()) return fitted;
    FittedGarment& fit = fitted.value();
    relaxPlacement(fit.pattern, fit.placement);
    return fitted;
}

Result<CookedAsset> cookFittedGarment(const ClothAssetDesc& design, const BodyAsset& body) {
    auto fitted = fitGarment(design, body);
    if (!fitted.isOk()) return fitted.status();
    const FittedGarment& fit = fitted.value();
    auto cooked = cookClothPattern(fit.desc, fit.pattern, fit.attached);
    if (!cooked.isOk()) return Status::invalidArgument(std::string(kindName(design.kind)) + ": " + cooked.status().message());
    CookedAsset asset = std::move(cooked).value();
    // Every level starts where the fit placed it (the pattern's own placement is only a cone).
    for (CookedLevel& level : asset.levels) {
        lod::ActiveMesh& a = level.active;
        std::vector<uint32_t> panelOf(a.simToVertex.size(), 0);
        for (std::size_t k = 0; k < a.triangleIds.size(); ++k)
            for (uint32_t s : a.mesh.triangles[k]) panelOf[s] = level.hierarchy.triangle(a.triangleIds[k]).panel;
        for (std::size_t s = 0; s < a.simToVertex.size(); ++s) {
            const lod::PanelDesc& d = fit.pattern.panels[panelOf[s]];
            const Vec2 st = d.gridOf(a.mesh.restPositions[s]);
            a.mesh.positions[s] = fit.placement[panelOf[s]].at(st.x(), st.y());
        }
        for (const auto& weld : a.welds) a.mesh.positions[weld[1]] = a.mesh.positions[weld[0]];
        for (std::size_t s = 0; s < a.simToVertex.size(); ++s)
            if (a.vertexToSim[a.simToVertex[s]] == s)
                if (Status st = level.hierarchy.setState(a.simToVertex[s], a.mesh.positions[s], Vec3::Zero()); !st) return st;
    }
    std::vector<Vec3> renderPositions, renderNormals;
    asset.levels.back().hierarchy.renderPositions(renderPositions, renderNormals);
    const BoundingSphere bounds = centroidSphere(renderPositions);
    asset.centroid = bounds.centre;
    asset.radius = bounds.radius;
    return asset;
}

} // namespace cc::detail
