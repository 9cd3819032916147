#include "crowdcloth/lod/GarmentHierarchy.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

namespace cc::lod {

namespace {

/// Grid point (i, j) of panel p on side `side`, k-th along it.
std::array<uint32_t, 2> sidePoint(const PanelDesc& d, PanelSide side, uint32_t k) {
    switch (side) {
    case PanelSide::Bottom: return {k, 0};
    case PanelSide::Top: return {k, d.rows};
    case PanelSide::Left: return {0, k};
    case PanelSide::Right: return {d.columns, k};
    }
    return {0, 0};
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

} // namespace

Status HierarchySettings::validate() const {
    if (!std::isfinite(arealDensity) || !(arealDensity > 0.0) || arealDensity > 100.0) {
        return Status::invalidArgument("HierarchySettings.arealDensity = " + std::to_string(arealDensity) +
                                       " is outside (0, 100] kg/m^2");
    }
    if (maxLevel > 20) {
        return Status::invalidArgument("HierarchySettings.maxLevel = " + std::to_string(maxLevel) +
                                       " is above 20 (each level doubles the triangles)");
    }
    if (renderLevel > maxLevel) {
        return Status::invalidArgument("HierarchySettings.renderLevel = " + std::to_string(renderLevel) +
                                       " is above maxLevel = " + std::to_string(maxLevel));
    }
    if (maxRenderVertices < 1) return Status::invalidArgument("HierarchySettings.maxRenderVertices must be >= 1");
    return Status::ok();
}

Result<GarmentHierarchy> GarmentHierarchy::create(const GarmentPattern& pattern, const HierarchySettings& settings) {
    if (Status s = pattern.validate(); !s) return s;
    if (Status s = settings.validate(); !s) return s;
    GarmentHierarchy h;
    h.mPattern = pattern;
    h.mSettings = settings;

    // Base grid points of all panels, then glue the tube wraps and the seams (union-find).
    uint64_t gridPoints = 0, baseTriangles = 0;
    for (const PanelDesc& d : pattern.panels) {
        h.mPanelBaseOffset.push_back(static_cast<uint32_t>(gridPoints));
        gridPoints += uint64_t(d.columns + 1) * (d.rows + 1);
        baseTriangles += 2ull * d.columns * d.rows;
    }
    // Uniform level L has baseTriangles * 2^L triangles and about half as many vertices.
    const double renderVertices = 0.5 * double(baseTriangles) * std::ldexp(1.0, int(settings.renderLevel)) +
                                  double(gridPoints);
    if (renderVertices > settings.maxRenderVertices || gridPoints > (1ull << 26)) {
        return Status::invalidArgument("GarmentHierarchy: renderLevel " + std::to_string(settings.renderLevel) +
                                       " gives about " + std::to_string(uint64_t(renderVertices)) +
                                       " render vertices, above maxRenderVertices = " +
                                       std::to_string(settings.maxRenderVertices));
    }
    std::vector<uint32_t> parent(gridPoints);
    std::iota(parent.begin(), parent.end(), 0u);
    auto gridId = [&](uint32_t p, uint32_t i, uint32_t j) {
        return h.mPanelBaseOffset[p] + j * (pattern.panels[p].columns + 1) + i;
    };
    auto unite = [&](uint32_t a, uint32_t b) {
        a = findRoot(parent, a);
        b = findRoot(parent, b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // lowest id represents: deterministic
    };
    for (uint32_t p = 0; p < pattern.panels.size(); ++p) {
        const PanelDesc& d = pattern.panels[p];
        if (d.shape != PanelShape::Tube) continue;
        for (uint32_t j = 0; j <= d.rows; ++j) unite(gridId(p, 0, j), gridId(p, d.columns, j));
    }
    for (const Seam& seam : pattern.seams) {
        const PanelDesc& a = pattern.panels[seam.panelA];
        const PanelDesc& b = pattern.panels[seam.panelB];
        const bool alongU = seam.sideA == PanelSide::Bottom || seam.sideA == PanelSide::Top;
        const uint32_t n = alongU ? a.columns : a.rows;
        for (uint32_t k = 0; k <= n; ++k) {
            const auto pa = sidePoint(a, seam.sideA, k);
            const auto pb = sidePoint(b, seam.sideB, seam.reversed ? n - k : k);
            unite(gridId(seam.panelA, pa[0], pa[1]), gridId(seam.panelB, pb[0], pb[1]));
        }
    }
    std::vector<uint32_t> compact(gridPoints, kNone);
    h.mBaseVertexIds.resize(gridPoints);
    for (uint32_t p = 0; p < pattern.panels.size(); ++p) {
        const PanelDesc& d = pattern.panels[p];
        for (uint32_t j = 0; j <= d.rows; ++j) {
            for (uint32_t i = 0; i <= d.columns; ++i) {
                const uint32_t g = gridId(p, i, j);
                const uint32_t root = findRoot(parent, g);
                if (compact[root] == kNone) {
                    compact[root] = static_cast<uint32_t>(h.mVertices.size());
                    Vertex v;
                    v.position = d.place(double(i) / d.columns, double(j) / d.rows);
                    v.active = true;
                    h.mVertices.push_back(v);
                }
                h.mBaseVertexIds[g] = compact[root];
            }
        }
    }
    h.mActiveVertexCount = static_cast<uint32_t>(h.mVertices.size());

    // Base triangles: each grid square is a diamond of two right triangles with apex at the right
    // angle and base on the diagonal; the diagonals alternate like RectanglePanel's.
    for (uint32_t p = 0; p < pattern.panels.size(); ++p) {
        const PanelDesc& d = pattern.panels[p];
        auto corner = [&](uint32_t i, uint32_t j) {
            return std::make_pair(h.mBaseVertexIds[gridId(p, i, j)], d.rest(double(i) / d.columns, double(j) / d.rows));
        };
        for (uint32_t j = 0; j < d.rows; ++j) {
            for (uint32_t i = 0; i < d.columns; ++i) {
                const auto a = corner(i, j), b = corner(i + 1, j), c = corner(i, j + 1), e = corner(i + 1, j + 1);
                std::array<std::array<std::pair<uint32_t, Vec2>, 3>, 2> tris;
                if ((i + j) % 2 == 0) {
                    tris = {{{b, e, a}, {c, a, e}}};
                } else {
                    tris = {{{a, b, c}, {e, c, b}}};
                }
                for (const auto& t : tris) {
                    Triangle tri;
                    for (int k = 0; k < 3; ++k) {
                        tri.vertices[k] = t[k].first;
                        tri.rest[k] = t[k].second;
                    }
                    if (tri.vertices[0] == tri.vertices[1] || tri.vertices[1] == tri.vertices[2] ||
                        tri.vertices[0] == tri.vertices[2]) {
                        return Status::invalidArgument("GarmentHierarchy: seams collapse base square (" +
                                                       std::to_string(i) + ", " + std::to_string(j) + ") of panel " +
                                                       std::to_string(p) + " (add columns/rows)");
                    }
                    tri.panel = p;
                    tri.level = 0;
                    tri.parent = kNone;
                    tri.children = {kNone, kNone};
                    tri.active = false;
                    h.mTriangles.push_back(tri);
                }
            }
        }
    }
    // A vertex pair may bound at most two triangles (seams that glue too few squares break that).
    for (uint32_t t = 0; t < h.mTriangles.size(); ++t) {
        const auto& v = h.mTriangles[t].vertices;
        for (int k = 0; k < 3; ++k) {
            EdgeSlots& slots = h.mEdges[edgeKey(v[k], v[(k + 1) % 3])];
            if (slots.triangles[0] == kNone) {
                slots.triangles[0] = t;
            } else if (slots.triangles[1] == kNone) {
                slots.triangles[1] = t;
            } else {
                return Status::invalidArgument("GarmentHierarchy: base edge (" + std::to_string(v[k]) + ", " +
                                               std::to_string(v[(k + 1) % 3]) + ") of panel " +
                                               std::to_string(h.mTriangles[t].panel) +
                                               " would join three triangles (seams too short; add columns/rows)");
            }
        }
    }
    h.mEdges.clear();
    for (uint32_t t = 0; t < h.mTriangles.size(); ++t) h.activate(t);
    h.mActiveTriangleCount = static_cast<uint32_t>(h.mTriangles.size());
    h.mQuiet.assign(h.mTriangles.size(), 0);
    for (uint32_t t = 0; t < h.mTriangles.size(); ++t) {
        const double third = settings.arealDensity * h.restArea(t) / 3.0;
        for (uint32_t v : h.mTriangles[t].vertices) h.mVertices[v].mass += third;
    }
    std::vector<double> baseMasses;
    for (const Vertex& v : h.mVertices) baseMasses.push_back(v.mass);

    // The render mesh is the uniform render level; building it once fixes every render vertex id.
    if (Status s = h.setUniformLevel(settings.renderLevel); !s) return s;
    h.mRenderVertexCount = static_cast<uint32_t>(h.mVertices.size());
    for (uint32_t t : h.activeTriangles()) h.mRenderTriangles.push_back(h.mTriangles[t].vertices);
    if (Status s = h.setUniformLevel(0); !s) return s;
    for (std::size_t v = 0; v < baseMasses.size(); ++v) h.mVertices[v].mass = baseMasses[v];
    for (Vertex& v : h.mVertices) {
        v.velocity = Vec3::Zero();
        v.morph = Vec3::Zero();
        v.morphFramesLeft = 0;
        v.morphListed = false;
    }
    h.mMorphing.clear();
    return h;
}

uint32_t GarmentHierarchy::baseVertex(uint32_t panel, uint32_t i, uint32_t j) const {
    if (panel >= mPattern.panels.size()) return kNone;
    const PanelDesc& d = mPattern.panels[panel];
    if (i > d.columns || j > d.rows) return kNone;
    return mBaseVertexIds[mPanelBaseOffset[panel] + j * (d.columns + 1) + i];
}

double GarmentHierarchy::restArea(uint32_t t) const {
    const auto& r = mTriangles[t].rest;
    return 0.5 * cross2(r[1] - r[0], r[2] - r[0]);
}

uint32_t GarmentHierarchy::neighbour(uint32_t t, uint32_t a, uint32_t b) const {
    auto it = mEdges.find(edgeKey(a, b));
    if (it == mEdges.end()) return kNone;
    const auto& s = it->second.triangles;
    return s[0] == t ? s[1] : s[0];
}

void GarmentHierarchy::activate(uint32_t t) {
    Triangle& tri = mTriangles[t];
    tri.active = true;
    for (int k = 0; k < 3; ++k) {
        auto& s = mEdges[edgeKey(tri.vertices[k], tri.vertices[(k + 1) % 3])].triangles;
        (s[0] == kNone ? s[0] : s[1]) = t;
    }
}

void GarmentHierarchy::deactivate(uint32_t t) {
    Triangle& tri = mTriangles[t];
    tri.active = false;
    for (int k = 0; k < 3; ++k) {
        auto it = mEdges.find(edgeKey(tri.vertices[k], tri.vertices[(k + 1) % 3]));
        auto& s = it->second.triangles;
        if (s[0] == t) {
            s[0] = s[1];
        }
        s[1] = kNone;
        if (s[0] == kNone) mEdges.erase(it);
    }
}

std::vector<uint32_t> GarmentHierarchy::activeTriangles() const {
    std::vector<uint32_t> out;
    out.reserve(mActiveTriangleCount);
    for (uint32_t t = 0; t < mTriangles.size(); ++t) {
        if (mTriangles[t].active) out.push_back(t);
    }
    return out;
}

uint32_t GarmentHierarchy::makeChild(uint32_t parentId, uint32_t midpoint, int which, const Vec2& restMid) {
    const Triangle& p = mTriangles[parentId];
    Triangle c;
    // Parent (a, b0, b1) splits at the base midpoint m into (m, a, b0) and (m, b1, a): both keep the
    // counter-clockwise order and have their right angle at m, their base on a parent leg.
    if (which == 0) {
        c.vertices = {midpoint, p.vertices[0], p.vertices[1]};
        c.rest = {restMid, p.rest[0], p.rest[1]};
    } else {
        c.vertices = {midpoint, p.vertices[2], p.vertices[0]};
        c.rest = {restMid, p.rest[2], p.rest[0]};
    }
    c.panel = p.panel;
    c.level = p.level + 1;
    c.parent = parentId;
    c.children = {kNone, kNone};
    c.active = false;
    mTriangles.push_back(c);
    mQuiet.push_back(0);
    return static_cast<uint32_t>(mTriangles.size() - 1);
}

Status GarmentHierarchy::splitLeaf(uint32_t t, std::vector<uint32_t>* outSplit, int depth) {
    // Forced splits climb at most one level per step, so depth is bounded by the level.
    if (depth > 64) return Status::error(StatusCode::InvalidOperation, "GarmentHierarchy: forced split chain too deep");
    const uint32_t b0 = mTriangles[t].vertices[1], b1 = mTriangles[t].vertices[2];
    uint32_t n = neighbour(t, b0, b1);
    if (n != kNone) {
        const Triangle& other = mTriangles[n];
        if (edgeKey(other.vertices[1], other.vertices[2]) != edgeKey(b0, b1)) {
            // The neighbour is one level coarser and our base is its leg: split it first, which
            // puts a triangle of our level with our base edge on the other side.
            if (Status s = splitLeaf(n, outSplit, depth + 1); !s) return s;
            n = neighbour(t, b0, b1);
            if (n == kNone || edgeKey(mTriangles[n].vertices[1], mTriangles[n].vertices[2]) != edgeKey(b0, b1)) {
                return Status::error(StatusCode::InvalidOperation,
                                     "GarmentHierarchy: triangle " + std::to_string(t) + " found no diamond partner");
            }
        }
    }
    splitDiamond(t, n, outSplit);
    return Status::ok();
}

void GarmentHierarchy::splitDiamond(uint32_t t, uint32_t n, std::vector<uint32_t>* outSplit) {
    const uint32_t b0 = mTriangles[t].vertices[1], b1 = mTriangles[t].vertices[2];
    const uint64_t key = edgeKey(b0, b1);
    uint32_t m;
    auto it = mMidpoints.find(key);
    if (it == mMidpoints.end()) {
        m = static_cast<uint32_t>(mVertices.size());
        Vertex v;
        v.ends = {std::min(b0, b1), std::max(b0, b1)};
        v.diamond = {t, n};
        v.level = mTriangles[t].level + 1;
        mVertices.push_back(v);
        mMidpoints.emplace(key, m);
    } else {
        m = it->second;
    }
    double area = 0.0;
    for (uint32_t d : {t, n}) {
        if (d == kNone) continue;
        area += restArea(d);
        if (mTriangles[d].children[0] == kNone) {
            const Vec2 restMid = 0.5 * (mTriangles[d].rest[1] + mTriangles[d].rest[2]);
            const uint32_t c0 = makeChild(d, m, 0, restMid);
            const uint32_t c1 = makeChild(d, m, 1, restMid);
            mTriangles[d].children = {c0, c1};
        }
        deactivate(d);
        activate(mTriangles[d].children[0]);
        activate(mTriangles[d].children[1]);
        mQuiet[mTriangles[d].children[0]] = mQuiet[mTriangles[d].children[1]] = 0;
        mActiveTriangleCount += 1;
    }
    // Lumped masses: the apexes keep theirs, each base end gives a sixth of each triangle's mass to
    // the midpoint. With the mean velocity at the midpoint, momentum is unchanged.
    const double delta = mSettings.arealDensity * area / 6.0;
    Vertex& e0 = mVertices[b0];
    Vertex& e1 = mVertices[b1];
    Vertex& mid = mVertices[m];
    mid.position = 0.5 * (e0.position + e1.position) + mid.morph;  // the render position: no pop
    mid.velocity = 0.5 * (e0.velocity + e1.velocity);
    mid.mass = 2.0 * delta;
    mid.morph = Vec3::Zero();
    mid.morphFramesLeft = 0;
    mid.active = true;
    e0.mass -= delta;
    e1.mass -= delta;
    ++mActiveVertexCount;
    if (outSplit) outSplit->push_back(m);
}

Status GarmentHierarchy::refine(uint32_t id, std::vector<uint32_t>* outSplit) {
    if (id >= mTriangles.size() || !mTriangles[id].active) {
        return Status::error(StatusCode::InvalidOperation,
                             "GarmentHierarchy::refine: triangle " + std::to_string(id) + " is not active");
    }
    if (mTriangles[id].level >= mSettings.maxLevel) {
        return Status::error(StatusCode::InvalidOperation, "GarmentHierarchy::refine: triangle " + std::to_string(id) +
                                                               " is at maxLevel " +
                                                               std::to_string(mSettings.maxLevel));
    }
    return splitLeaf(id, outSplit, 0);
}

bool GarmentHierarchy::canCoarsen(uint32_t vertex) const {
    if (vertex >= mVertices.size()) return false;
    const Vertex& v = mVertices[vertex];
    if (!v.active || v.ends[0] == kNone) return false;
    for (uint32_t d : v.diamond) {
        if (d == kNone) continue;
        const Triangle& p = mTriangles[d];
        if (p.active || p.children[0] == kNone) return false;
        if (!mTriangles[p.children[0]].active || !mTriangles[p.children[1]].active) return false;
    }
    return true;
}

Status GarmentHierarchy::coarsen(uint32_t vertex) {
    if (!canCoarsen(vertex)) {
        const std::string what = vertex >= mVertices.size()      ? " does not exist"
                                 : !mVertices[vertex].active      ? " is not active"
                                 : mVertices[vertex].ends[0] == kNone ? " is a base vertex"
                                                                  : " has finer triangles around it";
        return Status::error(StatusCode::InvalidOperation,
                             "GarmentHierarchy::coarsen: vertex " + std::to_string(vertex) + what);
    }
    Vertex& mid = mVertices[vertex];
    Vertex& e0 = mVertices[mid.ends[0]];
    Vertex& e1 = mVertices[mid.ends[1]];
    // Hand mass and momentum back to the edge's ends, half each (the split took equal shares).
    const double half = 0.5 * mid.mass;
    e0.velocity = (e0.mass * e0.velocity + half * mid.velocity) / (e0.mass + half);
    e1.velocity = (e1.mass * e1.velocity + half * mid.velocity) / (e1.mass + half);
    e0.mass += half;
    e1.mass += half;
    // Keep the vertex's offset from the edge midpoint in the render mesh; advanceMorph fades it.
    mid.morph = mid.position - 0.5 * (e0.position + e1.position);
    mid.morphFramesLeft = std::max<uint32_t>(1, mSettings.morphFrames);
    if (!mid.morphListed) {
        mid.morphListed = true;
        mMorphing.push_back(vertex);
    }
    mid.mass = 0.0;
    mid.velocity = Vec3::Zero();
    mid.active = false;
    --mActiveVertexCount;
    for (uint32_t d : mid.diamond) {
        if (d == kNone) continue;
        deactivate(mTriangles[d].children[0]);
        deactivate(mTriangles[d].children[1]);
        activate(d);
        mQuiet[d] = 0;
        mActiveTriangleCount -= 1;
    }
    return Status::ok();
}

std::vector<uint32_t> GarmentHierarchy::coarsenableVertices() const {
    std::vector<uint32_t> out;
    for (uint32_t v = 0; v < mVertices.size(); ++v) {
        if (canCoarsen(v)) out.push_back(v);
    }
    return out;
}

Status GarmentHierarchy::setUniformLevel(uint32_t level) {
    if (level > mSettings.maxLevel) {
        return Status::invalidArgument("GarmentHierarchy::setUniformLevel: level " + std::to_string(level) +
                                       " is above maxLevel " + std::to_string(mSettings.maxLevel));
    }
    uint32_t finest = 0;
    for (uint32_t t : activeTriangles()) finest = std::max(finest, mTriangles[t].level);
    for (uint32_t l = finest; l > level; --l) {
        for (uint32_t v = 0; v < mVertices.size(); ++v) {
            if (mVertices[v].active && mVertices[v].level == l) {
                if (Status s = coarsen(v); !s) return s;
            }
        }
    }
    for (uint32_t l = 0; l < level; ++l) {
        for (uint32_t t : activeTriangles()) {
            if (mTriangles[t].active && mTriangles[t].level == l) {
                if (Status s = splitLeaf(t, nullptr, 0); !s) return s;
            }
        }
    }
    return Status::ok();
}

Status GarmentHierarchy::setState(uint32_t vertex, const Vec3& position, const Vec3& velocity) {
    if (vertex >= mVertices.size() || !mVertices[vertex].active) {
        return Status::invalidArgument("GarmentHierarchy::setState: vertex " + std::to_string(vertex) +
                                       " is not active");
    }
    if (!isFinite(position) || !isFinite(velocity)) {
        return Status::invalidArgument("GarmentHierarchy::setState: vertex " + std::to_string(vertex) +
                                       " gets a non-finite position or velocity");
    }
    mVertices[vertex].position = position;
    mVertices[vertex].velocity = velocity;
    return Status::ok();
}

double GarmentHierarchy::totalMass() const {
    double sum = 0.0;
    for (const Vertex& v : mVertices) sum += v.mass;
    return sum;
}

Vec3 GarmentHierarchy::totalMomentum() const {
    Vec3 sum = Vec3::Zero();
    for (const Vertex& v : mVertices) {
        if (v.active) sum += v.mass * v.velocity;
    }
    return sum;
}

double GarmentHierarchy::kineticEnergy() const {
    double sum = 0.0;
    for (const Vertex& v : mVertices) {
        if (v.active) sum += 0.5 * v.mass * v.velocity.squaredNorm();
    }
    return sum;
}

void GarmentHierarchy::numberSimVertices(ActiveMesh& out, bool withMesh) const {
    out = ActiveMesh{};
    out.vertexToSim.assign(mVertices.size(), ActiveMesh::kNone);
    // One simulation vertex per (hierarchy vertex, pattern position): a seam or wrap vertex has
    // one pattern position per side. Pattern positions are bitwise reproducible (midpoints of the
    // same corners), so exact comparison finds the copies.
    struct Copy {
        uint32_t panel;
        Vec2 rest;
        uint32_t sim;
    };
    std::unordered_map<uint32_t, std::vector<Copy>> extra;
    std::vector<Copy> first(mVertices.size());
    std::vector<uint32_t> triangleIds = activeTriangles();
    for (uint32_t t : triangleIds) {
        const Triangle& tri = mTriangles[t];
        std::array<uint32_t, 3> simTri;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tri.vertices[k];
            uint32_t sim = out.vertexToSim[v];
            if (sim == ActiveMesh::kNone) {
                sim = static_cast<uint32_t>(out.simToVertex.size());
                out.vertexToSim[v] = sim;
                first[v] = {tri.panel, tri.rest[k], sim};
                out.simToVertex.push_back(v);
                out.mesh.restPositions.push_back(tri.rest[k]);
            } else if (first[v].panel != tri.panel || first[v].rest != tri.rest[k]) {
                sim = ActiveMesh::kNone;
                for (const Copy& c : extra[v]) {
                    if (c.panel == tri.panel && c.rest == tri.rest[k]) sim = c.sim;
                }
                if (sim == ActiveMesh::kNone) {
                    sim = static_cast<uint32_t>(out.simToVertex.size());
                    extra[v].push_back({tri.panel, tri.rest[k], sim});
                    out.simToVertex.push_back(v);
                    out.mesh.restPositions.push_back(tri.rest[k]);
                    out.welds.push_back({out.vertexToSim[v], sim});
                }
            }
            simTri[k] = sim;
        }
        if (withMesh) out.mesh.triangles.push_back(simTri);
    }
    if (!withMesh) return;
    out.triangleIds = std::move(triangleIds);
    const std::size_t n = out.simToVertex.size();
    out.mesh.positions.resize(n);
    out.velocities.resize(n);
    out.masses.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        out.mesh.positions[i] = mVertices[out.simToVertex[i]].position;
        out.velocities[i] = mVertices[out.simToVertex[i]].velocity;
    }
    for (std::size_t k = 0; k < out.triangleIds.size(); ++k) {
        const double third = mSettings.arealDensity * restArea(out.triangleIds[k]) / 3.0;
        for (uint32_t s : out.mesh.triangles[k]) out.masses[s] += third;
    }
}

ActiveMesh GarmentHierarchy::activeMesh() const {
    ActiveMesh out;
    numberSimVertices(out, true);
    return out;
}

Status GarmentHierarchy::readState(const ActiveMesh& active, Span<const Vec3> positions, Span<const Vec3> velocities) {
    const std::size_t n = active.simToVertex.size();
    if (positions.size() != n || velocities.size() != n) {
        return Status::invalidArgument("GarmentHierarchy::readState: expected " + std::to_string(n) +
                                       " positions and velocities, got " + std::to_string(positions.size()) +
                                       " and " + std::to_string(velocities.size()));
    }
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t v = active.simToVertex[i];
        if (v >= mVertices.size() || !mVertices[v].active) {
            return Status::invalidArgument("GarmentHierarchy::readState: simulation vertex " + std::to_string(i) +
                                           " maps to inactive vertex " + std::to_string(v) +
                                           " (the active mesh changed; call activeMesh() again)");
        }
        if (!isFinite(positions[i]) || !isFinite(velocities[i])) {
            return Status::invalidArgument("GarmentHierarchy::readState: simulation vertex " + std::to_string(i) +
                                           " has a non-finite position or velocity");
        }
    }
    if (n != mActiveVertexCount + active.welds.size()) {
        return Status::invalidArgument("GarmentHierarchy::readState: the active mesh is stale (" + std::to_string(n) +
                                       " simulation vertices for " + std::to_string(mActiveVertexCount) +
                                       " active vertices)");
    }
    for (std::size_t i = 0; i < n; ++i) {
        Vertex& v = mVertices[active.simToVertex[i]];
        if (active.vertexToSim[active.simToVertex[i]] == i) {
            v.position = positions[i];
            v.velocity = velocities[i];
        }
    }
    if (active.welds.empty()) return Status::ok();
    // Welded copies: the mass-weighted mean keeps the momentum the solver had.
    struct Sum {
        Vec3 momentum = Vec3::Zero(), moment = Vec3::Zero();
        double mass = 0.0;
        void add(double m, const Vec3& x, const Vec3& v) {
            moment += m * x;
            momentum += m * v;
            mass += m;
        }
    };
    std::unordered_map<uint32_t, Sum> sums;
    for (const auto& [a, b] : active.welds) {
        auto [it, inserted] = sums.try_emplace(a);
        if (inserted) it->second.add(active.masses[a], positions[a], velocities[a]);
        it->second.add(active.masses[b], positions[b], velocities[b]);
    }
    for (const auto& [a, sum] : sums) {  // independent writes: the order does not matter
        Vertex& v = mVertices[active.simToVertex[a]];
        v.position = sum.moment / sum.mass;
        v.velocity = sum.momentum / sum.mass;
    }
    return Status::ok();
}

void GarmentHierarchy::writeState(const ActiveMesh& active, std::vector<Vec3>& outPositions,
                                  std::vector<Vec3>& outVelocities) const {
    const std::size_t n = active.simToVertex.size();
    outPositions.resize(n);
    outVelocities.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        outPositions[i] = mVertices[active.simToVertex[i]].position;
        outVelocities[i] = mVertices[active.simToVertex[i]].velocity;
    }
}

Result<SparseInterpolation> GarmentHierarchy::interpolation(const ActiveMesh& active,
                                                            Span<const uint32_t> vertices) const {
    if (active.vertexToSim.size() > mVertices.size()) {
        return Status::invalidArgument("GarmentHierarchy::interpolation: the active mesh is not this hierarchy's");
    }
    uint32_t highest = 0;
    for (std::size_t r = 0; r < vertices.size(); ++r) {
        if (vertices[r] >= mVertices.size()) {
            return Status::invalidArgument("GarmentHierarchy::interpolation: row " + std::to_string(r) +
                                           " asks for vertex " + std::to_string(vertices[r]) + " of " +
                                           std::to_string(mVertices.size()));
        }
        highest = std::max(highest, vertices[r]);
    }
    // Weights of every vertex up to the highest asked, in id order (a midpoint's ends come first).
    // Inside an active triangle the midpoint recursion is linear interpolation, so a row has at most
    // three terms.
    using Terms = std::vector<SparseInterpolation::Term>;
    std::vector<Terms> w(vertices.empty() ? 0 : highest + 1);
    for (uint32_t v = 0; v < w.size(); ++v) {
        const Vertex& vx = mVertices[v];
        const uint32_t sim = v < active.vertexToSim.size() ? active.vertexToSim[v] : ActiveMesh::kNone;
        if (vx.active) {
            if (sim == ActiveMesh::kNone) {
                return Status::invalidArgument("GarmentHierarchy::interpolation: active vertex " + std::to_string(v) +
                                               " is not in the active mesh (stale ActiveMesh)");
            }
            w[v] = {{sim, 1.0}};
            continue;
        }
        if (vx.ends[0] == kNone) continue;
        Terms t;
        for (uint32_t e : vx.ends) {
            for (const auto& term : w[e]) {
                auto it = std::find_if(t.begin(), t.end(), [&](const auto& x) { return x.source == term.source; });
                if (it == t.end()) {
                    t.push_back({term.source, 0.5 * term.weight});
                } else {
                    it->weight += 0.5 * term.weight;
                }
            }
        }
        std::sort(t.begin(), t.end(), [](const auto& a, const auto& b) { return a.source < b.source; });
        w[v] = std::move(t);
    }
    SparseInterpolation out;
    out.sourceCount = static_cast<uint32_t>(active.simToVertex.size());
    for (uint32_t v : vertices) {
        out.terms.insert(out.terms.end(), w[v].begin(), w[v].end());
        out.rowStart.push_back(static_cast<uint32_t>(out.terms.size()));
    }
    return out;
}

void GarmentHierarchy::renderPositions(std::vector<Vec3>& outPositions, std::vector<Vec3>& outNormals) const {
    outPositions.resize(mRenderVertexCount);
    for (uint32_t v = 0; v < mRenderVertexCount; ++v) {
        const Vertex& vx = mVertices[v];
        outPositions[v] = vx.active ? vx.position
                                    : Vec3(0.5 * (outPositions[vx.ends[0]] + outPositions[vx.ends[1]]) + vx.morph);
    }
    outNormals.assign(mRenderVertexCount, Vec3::Zero());
    for (const auto& t : mRenderTriangles) {
        const Vec3 n = (outPositions[t[1]] - outPositions[t[0]]).cross(outPositions[t[2]] - outPositions[t[0]]);
        for (uint32_t v : t) outNormals[v] += n;
    }
    for (Vec3& n : outNormals) {
        const double len = n.norm();
        if (len > 0.0) n /= len;  // a vertex whose triangles have collapsed keeps a zero normal
    }
}

void GarmentHierarchy::advanceMorph() {
    std::size_t kept = 0;
    for (uint32_t v : mMorphing) {
        Vertex& vx = mVertices[v];
        if (vx.morphFramesLeft <= 1) {
            vx.morph = Vec3::Zero();
            vx.morphFramesLeft = 0;
            vx.morphListed = false;
            continue;
        }
        vx.morph *= double(vx.morphFramesLeft - 1) / double(vx.morphFramesLeft);
        --vx.morphFramesLeft;
        mMorphing[kept++] = v;
    }
    mMorphing.resize(kept);
}

} // namespace cc::lod
