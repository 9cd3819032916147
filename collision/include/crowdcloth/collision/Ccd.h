#pragma once

#include <array>
#include <cstdint>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Tolerances of a continuous collision query.
struct CcdSettings {
    double thickness = 1.0e-4;          ///< [m] report contact when the primitives come this close;
                                        ///< >= 0 (0 = only actual touching)
    double distanceTolerance = 1.0e-7;  ///< [m] how finely the search resolves the gap; > 0. Sets the
                                        ///< false-positive band, never a false negative
    double timeTolerance = 1.0e-6;      ///< [-] resolution of the time of impact, (0, 1); the
                                        ///< reported toi is at most this much early
    int maxBoxes = 20000;               ///< [-] search boxes before giving up conservatively; >= 1

    /// Names the first invalid field.
    Status validate() const;
};

/// What a continuous query found.
enum class CcdOutcome : uint8_t {
    Separated,  ///< proven: the primitives never come within `thickness` during the motion
    Contact,    ///< they may come within `thickness`; see CcdHit
    NonFinite,  ///< an input coordinate is NaN or infinite; nothing was computed
};

/// The earliest contact of a continuous query.
struct CcdHit {
    double toi = 1.0;        ///< [-] time of impact in [0, 1]: no contact happens before it
    /// Vertex-triangle: barycentric weights (w0, w1, w2) of the closest triangle point at `toi`.
    /// Edge-edge: (s, u, 0), the closest points a + s (b - a) and c + u (d - c) at `toi`.
    std::array<double, 3> weights{0.0, 0.0, 0.0};
    Vec3 normal = Vec3::UnitY();  ///< unit; points from the triangle (edge cd) towards the vertex
                                  ///< (edge ab): the closest-point direction at `toi`, else the
                                  ///< face (edge cross) normal turned to the side the vertex (edge ab)
                                  ///< started on, else against their relative motion
    int boxesChecked = 0;    ///< [-] search boxes examined (cost)
    bool capped = false;     ///< the box budget ran out: `toi` is a safe lower bound, not resolved
};

/// Continuous vertex-triangle test over a linear motion t in [0, 1].
///
/// start = {p, a, b, c} at t = 0 and end = the same points at t = 1; every point moves on a
/// straight line. Finds the earliest time at which the Euclidean distance between p and triangle
/// abc can be <= settings.thickness.
///
/// Conservative (no false negatives): the search runs on the multilinear function
/// F(t, u, v) = p(t) - a(t) - u (b(t) - a(t)) - v (c(t) - a(t)), whose values over a box of
/// (t, u, v) lie in the bounding box of its 8 corner values, and discards only boxes whose bounding
/// box, grown by a bound on the rounding error, misses the cube [-thickness, thickness]^3 (the
/// inclusion test of Wang et al. 2021, "A Large-Scale Benchmark and an Inclusion-Based Algorithm
/// for Continuous Collision Detection"). Boxes are searched earliest time first, so `toi` is a
/// lower bound on the first contact time. The L-infinity test also admits motions that stay up to
/// sqrt(3) * thickness + distanceTolerance away: those are the false positives. Coplanar, parallel,
/// zero-motion and grazing motions need no special case. The classic alternative, the roots of
/// the coplanarity cubic (Provot 1997; Bridson et al. 2002), misses contacts in floating point at
/// exactly these degenerate motions (Wang et al. 2021, section 4), so it is not used.
///
/// Thread-safe, allocation-free unless the first box is inconclusive.
CcdOutcome vertexTriangleCcd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                             const CcdSettings& settings, CcdHit& outHit);

/// Continuous edge-edge test over a linear motion t in [0, 1]: start = {a, b, c, d} at t = 0,
/// end at t = 1, edges ab and cd. Same contract as vertexTriangleCcd, on
/// F(t, s, u) = a(t) + s (b(t) - a(t)) - c(t) - u (d(t) - c(t)).
CcdOutcome edgeEdgeCcd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                       const CcdSettings& settings, CcdHit& outHit);

/// Barycentric weights (w0, w1, w2) of the point of triangle abc closest to p (Ericson 2005,
/// Real-Time Collision Detection, 5.1.5). A degenerate triangle yields its closest edge point.
std::array<double, 3> closestTriangleWeights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Parameters (s, u) of the closest points a + s (b - a) and c + u (d - c) of segments ab and cd,
/// both in [0, 1] (Ericson 2005, 5.1.9). Parallel segments get the pair with the smallest s.
std::array<double, 2> closestSegmentParameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// closestSegmentParameters() when both parameters are strictly inside (0, 1), else false (out
/// untouched): the same values and the same answer, but most pairs of a cloth's nearby edges are
/// closest at an end, and those are told apart from the lines' closest points without a division.
bool interiorClosestSegmentParameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                      std::array<double, 2>& out);

} // namespace cc::collision
