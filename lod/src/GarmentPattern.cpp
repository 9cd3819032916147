#include "crowdcloth/lod/GarmentPattern.h"

#include <cmath>
#include <string>

namespace cc::lod {

namespace {

constexpr uint32_t kMaxBaseSquares = 4096;  // per panel side; the hierarchy refines from there

std::string panelName(std::size_t p) { return "GarmentPattern.panels[" + std::to_string(p) + "]"; }

/// +1 when counter-clockwise triangles walk the side in its own numbering order, -1 otherwise.
int walkDirection(PanelSide side) {
    return (side == PanelSide::Bottom || side == PanelSide::Right) ? 1 : -1;
}

Status checkSize(double value, const char* name, const char* what) {
    if (!std::isfinite(value) || !(value > 0.0)) {
        return Status::invalidArgument(std::string("GarmentPattern::") + name + ": " + what +
                                       " must be finite and > 0, got " + std::to_string(value));
    }
    return Status::ok();
}

uint32_t squaresFor(double length, double cellSize, uint32_t minimum) {
    const double n = std::round(length / cellSize);
    return static_cast<uint32_t>(std::max<double>(minimum, std::min<double>(n, kMaxBaseSquares)));
}

} // namespace

Vec2 PanelDesc::rest(double s, double t) const {
    return chartOrigin + Eigen::Rotation2Dd(chartAngle) * localRest(s, t);
}

Vec2 PanelDesc::localRest(double s, double t) const {
    const double flare = flareAngle();
    if (!(flare > 0.0)) return Vec2(s * width, t * height);
    // Annular sector with its apex above the top side: radius grows from the top arc down to the
    // hem, the angle runs across the width; the top centre sits at (width / 2, height).
    const double topRadius = width / flare;
    const double radius = topRadius + (1.0 - t) * height;
    const double angle = (s - 0.5) * flare;
    return Vec2(0.5 * width + radius * std::sin(angle), height + topRadius - radius * std::cos(angle));
}

Vec2 PanelDesc::gridOf(const Vec2& restPosition) const {
    const Vec2 local = Eigen::Rotation2Dd(-chartAngle) * (restPosition - chartOrigin);
    const double flare = flareAngle();
    if (!(flare > 0.0)) return Vec2(local.x() / width, local.y() / height);
    const double topRadius = width / flare;
    const Vec2 fromApex = local - Vec2(0.5 * width, height + topRadius);
    const double radius = fromApex.norm();
    const double angle = std::atan2(fromApex.x(), -fromApex.y());
    return Vec2(angle / flare + 0.5, 1.0 - (radius - topRadius) / height);
}

Vec3 PanelDesc::place(double s, double t) const {
    if (shape == PanelShape::Tube) {
        // A cone whose slant is the panel's height: every ring keeps its rest circumference.
        const double ringLength = width + (1.0 - t) * (bottomWidth() - width);
        const double radius = ringLength / (2.0 * kPi);
        const double sinHalfApex = std::min(1.0, flareAngle() / (2.0 * kPi));
        const double along = height - (1.0 - t) * height * std::sqrt(1.0 - sinHalfApex * sinHalfApex);
        const double angle = 2.0 * kPi * s;
        const Vec3 side = uAxis.cross(vAxis);
        return origin + radius * (std::cos(angle) * uAxis + std::sin(angle) * side) + along * vAxis;
    }
    const Vec2 r = localRest(s, t);
    return origin + r.x() * uAxis + r.y() * vAxis;
}

Status GarmentPattern::validate() const {
    if (panels.empty()) return Status::invalidArgument("GarmentPattern.panels is empty");
    if (panels.size() > 4096) return Status::invalidArgument("GarmentPattern.panels has more than 4096 panels");
    for (std::size_t p = 0; p < panels.size(); ++p) {
        const PanelDesc& d = panels[p];
        const std::string name = panelName(p);
        if (!std::isfinite(d.width) || !(d.width > 0.0)) {
            return Status::invalidArgument(name + ".width must be finite and > 0, got " + std::to_string(d.width));
        }
        if (!std::isfinite(d.height) || !(d.height > 0.0)) {
            return Status::invalidArgument(name + ".height must be finite and > 0, got " + std::to_string(d.height));
        }
        if (d.columns < 1 || d.rows < 1) return Status::invalidArgument(name + ".columns and .rows must be >= 1");
        if (d.shape == PanelShape::Tube && d.columns < 3) {
            return Status::invalidArgument(name + ".columns must be >= 3 for a tube (got " +
                                           std::to_string(d.columns) + ")");
        }
        if (d.columns > kMaxBaseSquares || d.rows > kMaxBaseSquares) {
            return Status::invalidArgument(name + ".columns and .rows must be <= 4096");
        }
        if (!std::isfinite(d.hemWidth) || d.hemWidth < 0.0 ||
            (d.hemWidth > 0.0 && !(d.hemWidth >= d.width && d.hemWidth <= d.width + 2.0 * kPi * d.height * (1.0 + 1e-12)))) {
            return Status::invalidArgument(name + ".hemWidth must be 0 or in [width, width + 2 pi height] (" +
                                           std::to_string(d.width) + ", " +
                                           std::to_string(d.width + 2.0 * kPi * d.height) + "), got " +
                                           std::to_string(d.hemWidth));
        }
        // Thin base squares make long thin triangles at every level; a 1:8 aspect is already poor
        // (a flared panel's squares are narrowest at the top and widest at the hem).
        const double aspect = (d.width / d.columns) / (d.height / d.rows);
        const double hemAspect = (d.bottomWidth() / d.columns) / (d.height / d.rows);
        if (!(aspect >= 0.125 && hemAspect <= 8.0)) {
            return Status::invalidArgument(name + ": base squares are " + std::to_string(d.width / d.columns) +
                                           " x " + std::to_string(d.height / d.rows) +
                                           " m; keep their aspect within 1:8 (adjust columns/rows)");
        }
        if (!isFinite(d.origin)) return Status::invalidArgument(name + ".origin is not finite");
        if (!std::isfinite(d.chartOrigin.x()) || !std::isfinite(d.chartOrigin.y()) || !std::isfinite(d.chartAngle))
            return Status::invalidArgument(name + ".chartOrigin and .chartAngle must be finite");
        if (!isFinite(d.uAxis) || std::abs(d.uAxis.norm() - 1.0) > 1e-9) {
            return Status::invalidArgument(name + ".uAxis must be a unit vector");
        }
        if (!isFinite(d.vAxis) || std::abs(d.vAxis.norm() - 1.0) > 1e-9 || std::abs(d.uAxis.dot(d.vAxis)) > 1e-9) {
            return Status::invalidArgument(name + ".vAxis must be a unit vector orthogonal to uAxis");
        }
    }
    std::vector<uint8_t> used(panels.size() * 4, 0);
    for (std::size_t s = 0; s < seams.size(); ++s) {
        const Seam& seam = seams[s];
        const std::string name = "GarmentPattern.seams[" + std::to_string(s) + "]";
        if (seam.panelA >= panels.size() || seam.panelB >= panels.size()) {
            return Status::invalidArgument(name + " names a panel out of range (" + std::to_string(panels.size()) +
                                           " panels)");
        }
        uint32_t segments[2];
        for (int k = 0; k < 2; ++k) {
            const uint32_t p = k == 0 ? seam.panelA : seam.panelB;
            const PanelSide side = k == 0 ? seam.sideA : seam.sideB;
            const PanelDesc& d = panels[p];
            const bool alongU = side == PanelSide::Bottom || side == PanelSide::Top;
            if (d.shape == PanelShape::Tube && !alongU) {
                return Status::invalidArgument(name + ": the left/right sides of tube panel " + std::to_string(p) +
                                               " are already sewn to each other");
            }
            uint8_t& flag = used[p * 4 + static_cast<uint32_t>(side)];
            if (flag) {
                return Status::invalidArgument(name + ": side " + std::to_string(static_cast<int>(side)) +
                                               " of panel " + std::to_string(p) + " is already in a seam");
            }
            flag = 1;
            segments[k] = alongU ? d.columns : d.rows;
        }
        if (segments[0] != segments[1]) {
            return Status::invalidArgument(name + ": the sides have " + std::to_string(segments[0]) + " and " +
                                           std::to_string(segments[1]) + " base segments; they must match");
        }
        const int product = walkDirection(seam.sideA) * walkDirection(seam.sideB) * (seam.reversed ? -1 : 1);
        if (product != -1) {
            return Status::invalidArgument(name + " would flip panel " + std::to_string(seam.panelB) +
                                           " over (both triangles walk the seam the same way); toggle `reversed`");
        }
    }
    return Status::ok();
}

namespace {

/// The panel every builder starts from: sizes checked (named after the garment and its width
/// parameter) and the base grid chosen so squares are about cellSize on a side.
Result<PanelDesc> sizedPanel(const char* garment, const char* widthName, double width, const char* heightName,
                             double height, double cellSize, uint32_t minColumns) {
    for (Status s : {checkSize(width, garment, widthName), checkSize(height, garment, heightName),
                     checkSize(cellSize, garment, "cellSize")}) {
        if (!s) return s;
    }
    PanelDesc panel;
    panel.width = width;
    panel.height = height;
    panel.columns = squaresFor(width, cellSize, minColumns);
    panel.rows = squaresFor(height, cellSize, 1);
    return panel;
}

} // namespace

Result<GarmentPattern> GarmentPattern::cape(double width, double height, double cellSize) {
    auto sized = sizedPanel("cape", "width", width, "height", height, cellSize, 1);
    if (!sized.isOk()) return sized.status();
    PanelDesc panel = sized.value();
    panel.origin = Vec3(-0.5 * width, 0.0, 0.0);
    GarmentPattern pattern;
    pattern.panels.push_back(panel);
    if (Status s = pattern.validate(); !s) return s;
    return pattern;
}

Result<GarmentPattern> GarmentPattern::skirt(double circumference, double length, double cellSize,
                                             double hemCircumference) {
    auto sized = sizedPanel("skirt", "circumference", circumference, "length", length, cellSize, 3);
    if (!sized.isOk()) return sized.status();
    PanelDesc panel = sized.value();
    panel.shape = PanelShape::Tube;
    if (hemCircumference != 0.0) {
        panel.hemWidth = hemCircumference;
        // Columns for the mean circumference: the squares are then within 1:8 at both ends for any
        // flare up to a full circle.
        if (std::isfinite(hemCircumference)) panel.columns = squaresFor(0.5 * (circumference + hemCircumference), cellSize, 3);
    }
    GarmentPattern pattern;
    pattern.panels.push_back(panel);
    if (Status s = pattern.validate(); !s) return s;
    return pattern;
}

Result<GarmentPattern> GarmentPattern::dress(double width, double length, double cellSize) {
    auto sized = sizedPanel("dress", "width", width, "length", length, cellSize, 1);
    if (!sized.isOk()) return sized.status();
    PanelDesc front = sized.value();
    const double depth = 0.1 * width;
    front.origin = Vec3(-0.5 * width, 0.0, depth);
    PanelDesc back = front;
    back.origin = Vec3(0.5 * width, 0.0, -depth);
    back.uAxis = -Vec3::UnitX();
    GarmentPattern pattern;
    pattern.panels = {front, back};
    pattern.seams.push_back({0, PanelSide::Right, 1, PanelSide::Left, false});
    pattern.seams.push_back({0, PanelSide::Left, 1, PanelSide::Right, false});
    if (Status s = pattern.validate(); !s) return s;
    return pattern;
}

Result<GarmentPattern> GarmentPattern::poncho(double width, double length, double depth, double cellSize) {
    auto sized = sizedPanel("poncho", "width", width, "length", length, cellSize, 1);
    if (!sized.isOk()) return sized.status();
    if (Status s = checkSize(depth, "poncho", "depth"); !s) return s;
    PanelDesc front = sized.value();
    front.origin = Vec3(-0.5 * width, 0.0, 0.5 * depth);
    PanelDesc back = front;
    back.origin = Vec3(0.5 * width, 0.0, -0.5 * depth);
    back.uAxis = -Vec3::UnitX();
    GarmentPattern pattern;
    pattern.panels = {front, back};
    pattern.seams.push_back({0, PanelSide::Top, 1, PanelSide::Top, true});
    if (Status s = pattern.validate(); !s) return s;
    return pattern;
}

} // namespace cc::lod
