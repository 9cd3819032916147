#include "CookedAsset.h"

#include "crowdcloth/core/BoundingSphere.h"

#include <algorithm>
#include <cmath>


namespace cc {

Status ClothAssetDesc::validate() const {
    auto inRange = [](double x, double lo, double hi) { return std::isfinite(x) && x > lo && x <= hi; };
    if (uint32_t(kind) > uint32_t(GarmentKind::Poncho)) return Status::invalidArgument("ClothAssetDesc.kind is unknown");
    if (uint32_t(cut) > uint32_t(GarmentCut::Circle)) return Status::invalidArgument("ClothAssetDesc.cut is unknown");
    auto fittedOr = [&](double x, double hi) { return x == 0.0 || inRange(x, 0.0, hi); };
    if (!fittedOr(width, 10.0)) return Status::invalidArgument("ClothAssetDesc.width must be 0 (fitted) or in (0, 10] m");
    if (!fittedOr(length, 10.0)) return Status::invalidArgument("ClothAssetDesc.length must be 0 (fitted) or in (0, 10] m");
    if (!fittedOr(relativeLength, 1.0))
        return Status::invalidArgument("ClothAssetDesc.relativeLength must be 0 (the kind's) or in (0, 1] body heights");
    if (!fittedOr(hemWidth, 50.0)) return Status::invalidArgument("ClothAssetDesc.hemWidth must be 0 (the cut's) or in (0, 50] m");
    if (!(std::isfinite(ease) && ease >= 0.0 && ease <= 0.5)) return Status::invalidArgument("ClothAssetDesc.ease must be in [0, 0.5] m");
    if (!inRange(cellSize, 0.0, 1.0)) return Status::invalidArgument("ClothAssetDesc.cellSize must be in (0, 1] m");
    if (levelCount < 1 || levelCount > 10) return Status::invalidArgument("ClothAssetDesc.levelCount must be in [1, 10]");
    if (renderLevel + 1 < levelCount || renderLevel > 10)
        return Status::invalidArgument("ClothAssetDesc.renderLevel must be in [levelCount - 1, 10]");
    if (!inRange(thickness, 0.0, 1.0)) return Status::invalidArgument("ClothAssetDesc.thickness must be in (0, 1] m");
    if (!(velocityDamping >= 0.0 && velocityDamping <= 100.0))
        return Status::invalidArgument("ClothAssetDesc.velocityDamping must be in [0, 100] 1/s");
    if (!(compressionStiffness >= 0.0 && compressionStiffness <= 1.0))
        return Status::invalidArgument("ClothAssetDesc.compressionStiffness must be in [0, 1]");
    if (!(friction >= 0.0 && friction <= 2.0)) return Status::invalidArgument("ClothAssetDesc.friction must be in [0, 2]");
    if (!inRange(foldRadius, 0.0, 100.0)) return Status::invalidArgument("ClothAssetDesc.foldRadius must be in (0, 100] m");
    cloth::ClothMaterial material;
    material.arealDensity = arealDensity;
    material.stretchStiffness = stretchStiffness;
    material.shearStiffness = shearStiffness;
    material.bendStiffness = bendStiffness;
    material.damping = damping;
    if (Status s = material.validate(); !s) return Status::invalidArgument("ClothAssetDesc: " + s.message());
    return Status::ok();
}

namespace detail {
namespace {

Result<lod::GarmentPattern> makePattern(const ClothAssetDesc& desc) {
    switch (desc.kind) {
    case GarmentKind::Cape: return lod::GarmentPattern::cape(desc.width, desc.length, desc.cellSize);
    case GarmentKind::Skirt: return lod::GarmentPattern::skirt(desc.width, desc.length, desc.cellSize);
    case GarmentKind::Dress: return lod::GarmentPattern::dress(desc.width, desc.length, desc.cellSize);
    case GarmentKind::Poncho: return lod::GarmentPattern::poncho(desc.width, desc.length, 0.3, desc.cellSize);
    }
    return Status::invalidArgument("ClothAssetDesc.kind is unknown");
}

/// Every garment hangs from the top side (v = height) of its panels: the cape's shoulder line,
/// the skirt's waist ring, the dress's neckline ring, the poncho's shoulder seam.
std::vector<uint32_t> topLine(const lod::GarmentHierarchy& h) {
    std::vector<uint32_t> ids;
    const auto& panels = h.pattern().panels;
    for (uint32_t p = 0; p < panels.size(); ++p) {
        const uint32_t columns = panels[p].shape == lod::PanelShape::Tube ? panels[p].columns - 1 : panels[p].columns;
        for (uint32_t i = 0; i <= columns; ++i) ids.push_back(h.baseVertex(p, i, panels[p].rows));
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
}

/// Rows from (source, weight) lists, in row order.
SparseInterpolation fromRows(const std::vector<std::vector<SparseInterpolation::Term>>& rows, uint32_t sourceCount) {
    SparseInterpolation out;
    out.sourceCount = sourceCount;
    for (const auto& row : rows) {
        out.terms.insert(out.terms.end(), row.begin(), row.end());
        out.rowStart.push_back(uint32_t(out.terms.size()));
    }
    return out;
}

/// The refine and coarsen transfers between uniform levels `coarse` and `fine` = coarse + 1.
void buildTransfers(const lod::GarmentHierarchy& hierarchy, CookedLevel& coarse, CookedLevel& fine) {
    const lod::ActiveMesh& c = coarse.active;
    const lod::ActiveMesh& f = fine.active;
    // Refine: a vertex the coarse level has keeps its state; a new midpoint averages its ends.
    std::vector<std::vector<SparseInterpolation::Term>> rows(f.simToVertex.size());
    for (std::size_t s = 0; s < rows.size(); ++s) {
        const uint32_t v = f.simToVertex[s];
        if (c.vertexToSim[v] != lod::ActiveMesh::kNone) {
            rows[s] = {{c.vertexToSim[v], 1.0}};
        } else {
            const auto ends = hierarchy.edgeEnds(v);
            rows[s] = {{c.vertexToSim[ends[0]], 0.5}, {c.vertexToSim[ends[1]], 0.5}};
        }
    }
    coarse.refine = fromRows(rows, uint32_t(c.simToVertex.size()));
    // Coarsen: mass per hierarchy vertex at the fine level (copies summed).
    std::vector<double> mass(hierarchy.vertexCount(), 0.0);
    for (std::size_t s = 0; s < f.simToVertex.size(); ++s) mass[f.simToVertex[s]] += f.masses[s];
    std::vector<std::vector<SparseInterpolation::Term>> velocity(hierarchy.vertexCount());
    std::vector<double> total(hierarchy.vertexCount(), 0.0);
    for (std::size_t s = 0; s < c.simToVertex.size(); ++s) {
        const uint32_t v = c.simToVertex[s];
        if (!velocity[v].empty()) continue;
        velocity[v].push_back({f.vertexToSim[v], mass[v]});
        total[v] = mass[v];
    }
    for (std::size_t s = 0; s < f.simToVertex.size(); ++s) {
        const uint32_t v = f.simToVertex[s];
        if (c.vertexToSim[v] != lod::ActiveMesh::kNone || f.vertexToSim[v] != s) continue;
        for (uint32_t end : hierarchy.edgeEnds(v)) {
            velocity[end].push_back({uint32_t(s), 0.5 * mass[v]});
            total[end] += 0.5 * mass[v];
        }
    }
    std::vector<std::vector<SparseInterpolation::Term>> positions(c.simToVertex.size()), velocities(c.simToVertex.size());
    for (std::size_t s = 0; s < c.simToVertex.size(); ++s) {
        const uint32_t v = c.simToVertex[s];
        positions[s] = {{f.vertexToSim[v], 1.0}};
        velocities[s] = velocity[v];
        for (auto& term : velocities[s]) term.weight /= total[v];
    }
    fine.coarsenPositions = fromRows(positions, uint32_t(f.simToVertex.size()));
    fine.coarsenVelocities = fromRows(velocities, uint32_t(f.simToVertex.size()));
}

} // namespace

Result<CookedAsset> cookClothAsset(const ClothAssetDesc& desc) {
    if (Status s = desc.validate(); !s) return s;
    if (desc.width == 0.0 || desc.length == 0.0)
        return Status::invalidArgument("ClothAssetDesc: width and length 0 are fitted to a body (cook through GarmentFit)");
    auto pattern = makePattern(desc);
    if (!pattern.isOk()) return Status::invalidArgument("ClothAssetDesc: " + pattern.status().message());
    return cookClothPattern(desc, pattern.value(), {});
}

Result<CookedAsset> cookClothPattern(const ClothAssetDesc& desc, const lod::GarmentPattern& pattern,
                                     Span<const PatternPoint> attached) {
    CookedAsset asset;
    asset.desc = desc;
    asset.material.arealDensity = desc.arealDensity;
    asset.material.stretchStiffness = desc.stretchStiffness;
    asset.material.shearStiffness = desc.shearStiffness;
    asset.material.bendStiffness = desc.bendStiffness;
    asset.material.damping = desc.damping;

    lod::HierarchySettings hs;
    hs.arealDensity = desc.arealDensity;
    hs.maxLevel = std::max(desc.renderLevel, desc.levelCount - 1);
    hs.renderLevel = desc.renderLevel;
    auto base = lod::GarmentHierarchy::create(pattern, hs);
    if (!base.isOk()) return Status::invalidArgument("ClothAssetDesc: " + base.status().message());
    asset.renderTriangles = base.value().renderTriangles();
    asset.renderVertexCount = base.value().renderVertexCount();
    if (attached.empty()) {
        asset.attachedVertices = topLine(base.value());
    } else {
        for (const PatternPoint& p : attached) {
            const uint32_t id = base.value().baseVertex(p.panel, p.i, p.j);
            if (id == lod::GarmentHierarchy::kNone) return Status::invalidArgument("cookClothPattern: attachment off the pattern");
            asset.attachedVertices.push_back(id);
        }
        std::sort(asset.attachedVertices.begin(), asset.attachedVertices.end());
        asset.attachedVertices.erase(std::unique(asset.attachedVertices.begin(), asset.attachedVertices.end()),
                                     asset.attachedVertices.end());
    }

    std::vector<uint32_t> renderIds(asset.renderVertexCount);
    for (uint32_t r = 0; r < asset.renderVertexCount; ++r) renderIds[r] = r;
    for (uint32_t level = 0; level < desc.levelCount; ++level) {
        CookedLevel cooked;
        cooked.hierarchy = base.value();
        if (Status s = cooked.hierarchy.setUniformLevel(level); !s) return s;
        cooked.active = cooked.hierarchy.activeMesh();
        auto render = cooked.hierarchy.interpolation(cooked.active, renderIds);
        if (!render.isOk()) return render.status();
        cooked.render = std::move(render).value();
        for (uint32_t slot = 0; slot < asset.attachedVertices.size(); ++slot) {
            const uint32_t sim = cooked.active.vertexToSim[asset.attachedVertices[slot]];
            cooked.attached.push_back({sim, slot});
            for (const auto& weld : cooked.active.welds)
                if (weld[0] == sim) cooked.attached.push_back({weld[1], slot});
        }
        std::sort(cooked.attached.begin(), cooked.attached.end(),
                  [](const AttachedVertex& a, const AttachedVertex& b) { return a.sim < b.sim; });
        // Interpolating a surface of fold radius R with edges h misses it by about h^2 / (8 R);
        // each 4-8 level halves the triangle area, so h^2 halves too.
        const double h2 = desc.cellSize * desc.cellSize / std::pow(2.0, double(level));
        cooked.errorMetres = h2 / (8.0 * desc.foldRadius);
        std::vector<uint32_t> attachedSims;
        for (const AttachedVertex& a : cooked.attached) attachedSims.push_back(a.sim);
        auto clothLevel = cloth::ClothLevel::cookMesh(cooked.active.mesh, asset.material, attachedSims, cooked.active.welds);
        if (!clothLevel.isOk()) return Status::invalidArgument("ClothAssetDesc: level " + std::to_string(level) + ": " +
                                                               clothLevel.status().message());
        cooked.cloth = std::move(clothLevel).value();
        const cloth::ClothLevel& cl = *cooked.cloth;
        cooked.attachedSlot.resize(cl.attachedNodeCount());
        for (const AttachedVertex& a : cooked.attached) {
            const uint32_t node = cl.nodeOfVertex()[a.sim];
            cooked.attachedSlot[node - cl.freeNodeCount()] = a.slot;
        }
        asset.levels.push_back(std::move(cooked));
        if (level > 0) buildTransfers(asset.levels[level].hierarchy, asset.levels[level - 1], asset.levels[level]);
    }

    std::vector<Vec3> renderPositions, renderNormals;
    asset.levels.back().hierarchy.renderPositions(renderPositions, renderNormals);
    const BoundingSphere bounds = centroidSphere(renderPositions);
    asset.centroid = bounds.centre;
    asset.radius = bounds.radius;
    return asset;
}

} // namespace detail
} // namespace cc
