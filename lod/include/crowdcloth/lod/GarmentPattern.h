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
///
/// A flared panel (hemWidth > width) is cut as an annular sector, the way flared skirts, capes and
/// gores are drafted: the top side (v = height, where garments hang from) is an arc of length
/// `width`, the bottom side (the hem, v = 0) an arc of length `hemWidth`, the sides are straight
/// radii of length `height`. Grid columns run along the radii, so every grid row is an arc and
/// rows stay square to columns at any flare. A tube whose hem is 2 pi height wider than its top is
/// a full circle skirt.
///
///        width (top, v = height)
///         ______
///        /      \__  columns: radii of the sector
///       /        \__ rows: arcs
///      /__________\_
///        hemWidth (v = 0)
///
/// Every panel's rest shape lies in one pattern plane, moved there by `chartOrigin` and
/// `chartAngle`. A panel's own shape does not depend on where it lies, but distances measured
/// across panels do (the solver's tethers bind each vertex to its nearest attachment in the rest
/// plane): lay sewn panels out edge to edge, as a pattern is drafted, never on top of each other.
struct PanelDesc {
    PanelShape shape = PanelShape::Rectangle;
    double width = 1.0;            ///< [m] extent along u at v = height (a tube's circumference); > 0
    double height = 1.0;           ///< [m] extent along v; > 0
    double hemWidth = 0.0;         ///< [m] extent along u at v = 0; 0 = width (a rectangle); else
                                   ///< in [width, width + 2 pi height]
    uint32_t columns = 4;          ///< base squares along u; >= 1 (a tube needs >= 3)
    uint32_t rows = 4;             ///< base squares along v; >= 1
    Vec3 origin = Vec3::Zero();    ///< [m] world point of pattern (0, 0); a tube's ring centre at v = 0
    Vec3 uAxis = Vec3::UnitX();    ///< unit world direction of u (a tube: direction to the u = 0 point)
    Vec3 vAxis = Vec3::UnitY();    ///< unit world direction of v, orthogonal to uAxis
    Vec2 chartOrigin = Vec2::Zero();  ///< [m] where the panel's rest point (0, 0) lies in the pattern plane
    double chartAngle = 0.0;          ///< [rad] rotation of the panel's rest shape in the pattern plane

    /// Width of the v = 0 side [m] (hemWidth, or width when hemWidth is 0).
    double bottomWidth() const { return hemWidth > 0.0 ? hemWidth : width; }
    /// Sector angle of the rest shape [rad]: (bottomWidth - width) / height; 0 for a rectangle.
    double flareAngle() const { return (bottomWidth() - width) / height; }
    /// Rest (pattern) position [m] of grid point (s, t), s = i / columns and t = j / rows in [0, 1],
    /// in the pattern plane (moved by chartOrigin and chartAngle).
    Vec2 rest(double s, double t) const;
    /// The same in the panel's own frame: the top side centred at (width / 2, height).
    Vec2 localRest(double s, double t) const;
    /// The inverse of rest(): the grid fractions (s, t) of a rest position.
    Vec2 gridOf(const Vec2& restPosition) const;
    /// Initial world position of grid point (s, t): the pattern laid flat in the plane of uAxis
    /// and vAxis, or rolled into a tube (a cone when flared, isometric to the rest shape as long
    /// as the flare is below a full circle).
    Vec3 place(double s, double t) const;
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
    /// at y = length, axis along Y through the origin. `hemCircumference` [m] flares it (an A-line,
    /// up to a full circle at circumference + 2 pi length); 0 = straight.
    static Result<GarmentPattern> skirt(double circumference, double length, double cellSize,
                                        double hemCircumference = 0.0);
    /// A dress body: a front and a back rectangle sewn along both long sides (a tube made of two
    /// panels, two seams), hanging from y = length; front at z > 0, back at z < 0.
    static Result<GarmentPattern> dress(double width, double length, double cellSize);
    /// A poncho: a front and a back rectangle sewn along their top sides (the shoulder line at
    /// y = length), hanging at z = +/- depth / 2.
    static Result<GarmentPattern> poncho(double width, double length, double depth, double cellSize);
};

} // namespace cc::lod
