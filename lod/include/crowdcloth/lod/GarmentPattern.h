#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc::lod {

/// How a pattern panel closes on itself.
enum class PanelShape : uint8_t {
    Rectangle,  ///< an open sheet
    Tube,       ///< periodic in u: the u = width side is sewn to the u = 0 side (a skirt, a sleeve)
};

/// A side of a rectangular panel. Its vertices are numbered along increasing u (Bottom, Top) or
/// increasing v (Left, Right).
enum class PanelSide : uint8_t { Bottom, Right, Top, Left };

/// One pattern panel in metres, with its coarse 4-8 base grid and its initial placement.
///
/// The base grid is `columns` x `rows` squares, each split by a diagonal that alternates like a
/// checkerboard (the "Union Jack" layout of RectanglePanel); each base triangle is the root of a
/// 4-8 (bintree) hierarchy. Pins, attachments and seams live on base grid vertices.
struct PanelDesc {
    PanelShape shape = PanelShape::Rectangle;
    double width = 1.0;            ///< [m] extent along u (a tube's circumference); > 0
    double height = 1.0;           ///< [m] extent along v; > 0
    uint32_t columns = 4;          ///< base squares along u; >= 1 (a tube needs >= 3)
    uint32_t rows = 4;             ///< base squares along v; >= 1
    Vec3 origin = Vec3::Zero();    ///< [m] world point of pattern (0, 0); a tube's ring centre at v = 0
    Vec3 uAxis = Vec3::UnitX();    ///< unit world direction of u (a tube: direction to the u = 0 point)
    Vec3 vAxis = Vec3::UnitY();    ///< unit world direction of v, orthogonal to uAxis

    /// Initial world position of pattern point (u, v).
    Vec3 place(const Vec2& uv) const;
};

/// Sews side `sideA` of panel `panelA` to side `sideB` of panel `panelB`, vertex for vertex: the
/// k-th vertex of A's side meets the k-th vertex of B's side (the (n-k)-th when `reversed`). Both
/// sides need the same number of base segments; the sewn panels must keep one orientation (the
/// shared edge is walked in opposite directions by its two triangles).
struct Seam {
    uint32_t panelA = 0;
    PanelSide sideA = PanelSide::Right;
    uint32_t panelB = 0;
    PanelSide sideB = PanelSide::Left;
    bool reversed = false;
};

/// A garment: panels and the seams that join them.
struct GarmentPattern {
    std::vector<PanelDesc> panels;
    std::vector<Seam> seams;

    /// Names the first bad panel field or seam.
    Status validate() const;

    /// A cape: one rectangle hanging in the XY plane from its top side at y = height, centred on
    /// x = 0. Base squares are about `cellSize` [m] on a side.
    static Result<GarmentPattern> cape(double width, double height, double cellSize);
    /// A skirt: a tube of the given circumference [m] hanging down -Y from its waist ring (v = length)
    /// at y = length, axis along Y through the origin.
    static Result<GarmentPattern> skirt(double circumference, double length, double cellSize);
    /// A dress body: a front and a back rectangle sewn along both long sides (a tube made of two
    /// panels, two seams), hanging from y = length; front at z > 0, back at z < 0.
    static Result<GarmentPattern> dress(double width, double length, double cellSize);
    /// A poncho: a front and a back rectangle sewn along their top sides (the shoulder line at
    /// y = length), hanging at z = +/- depth / 2.
    static Result<GarmentPattern> poncho(double width, double length, double depth, double cellSize);
};

} // namespace cc::lod
