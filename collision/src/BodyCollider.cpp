#include "crowdcloth/collision/BodyCollider.h"

#include "QueryInput.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include "crowdcloth/collision/BodyTopology.h"
#include "crowdcloth/collision/Ccd.h"
#include "crowdcloth/core/ParallelFor.h"
#include "EmbreeDevice.h"
#include "TriangleFeatures.h"

namespace cc::collision {

using detail::ClosestPoint;
using detail::Feature;

Status BodyColliderSettings::validate() const {
    if (!(rebuildFraction > 0.0 && rebuildFraction <= 100.0)) {
        return Status::invalidArgument("BodyColliderSettings.rebuildFraction = " + std::to_string(rebuildFraction) +
                                       " is outside (0, 100]");
    }
    if (!(degenerateArea >= 0.0 && degenerateArea <= 0.1)) {
        return Status::invalidArgument("BodyColliderSettings.degenerateArea = " + std::to_string(degenerateArea) +
                                       " is outside [0, 0.1]");
    }
    return Status::ok();
}

struct BodyCollider::Impl {
    CollisionDevice* device = nullptr;
    BodyColliderSettings settings;
    std::shared_ptr<const BodyTopology> shape;  // shared by every collider of the body
    std::vector<Vec3> current, previous, velocity, buildPose;
    double buildDiagonal = 0.0;

    // Pseudonormals of the current pose (Baerentzen & Aanaes 2005): unit face normals, angle-weighted
    // vertex normals (on demand, from shape's triangles around the vertex), and per triangle edge
    // the sum of the face normals sharing that edge.
    std::vector<Vec3> faceNormal, edgeNormal;
    std::vector<uint8_t> degenerate;

    RTCScene scene = nullptr;       // current pose, refit each update
    RTCGeometry mesh = nullptr;
    RTCScene swept = nullptr;       // one user primitive per triangle: bounds of its motion
    RTCGeometry sweptGeometry = nullptr;
    // The swept tree matches (previous, current) only after the first continuous query since the
    // last update refit it (a body only proximity queries touch never pays for it); queries run
    // concurrently, so the refit is guarded.
    mutable std::atomic<bool> sweptCurrent{false};
    mutable std::mutex sweptMutex;
    Status refitSwept() const;
    BodyColliderStats stats;

    ~Impl() { releaseScenes(); }
    void releaseScenes() {
        // Our references to the geometries too: attaching adds the scene's own, so without these
        // every build leaks the geometry and its buffers (issue 11).
        if (mesh) rtcReleaseGeometry(mesh);
        if (sweptGeometry) rtcReleaseGeometry(sweptGeometry);
        if (scene) rtcReleaseScene(scene);
        if (swept) rtcReleaseScene(swept);
        scene = swept = nullptr;
        mesh = sweptGeometry = nullptr;
    }

    Status checkPose(Span<const Vec3> positions, const char* what) const;
    void computeNormals();
    Status buildScenes();
    void recordBuild();  // the pose the trees were built on
    void commitMesh();   // the current pose into the mesh tree
    void writeVertexBuffer();
    Status refit();
    Vec3 pseudonormal(uint32_t t, Feature f) const;
    Vec3 vertexPseudonormal(uint32_t v) const;
};

namespace {

// Embree's float boxes may miss a double triangle by a rounding error: queries are widened by this
// relative amount (plus an absolute floor) and the exact test runs in double.
constexpr double kFloatSlack = 1e-5;

float widen(double radius, double scale) { return float(radius * (1.0 + kFloatSlack) + kFloatSlack * scale + 1e-7); }

void sweptBounds(const RTCBoundsFunctionArguments* args) {
    const auto* impl = static_cast<const BodyCollider::Impl*>(args->geometryUserPtr);
    const auto& tri = impl->shape->triangles[args->primID];
    Eigen::AlignedBox3d box;
    for (uint32_t v : tri) {
        box.extend(impl->previous[v]);
        box.extend(impl->current[v]);
    }
    const double pad = kFloatSlack * (box.diagonal().norm() + 1.0);
    RTCBounds* b = args->bounds_o;
    b->lower_x = float(box.min().x() - pad), b->lower_y = float(box.min().y() - pad), b->lower_z = float(box.min().z() - pad);
    b->upper_x = float(box.max().x() + pad), b->upper_y = float(box.max().y() + pad), b->upper_z = float(box.max().z() + pad);
}

} // namespace

Status BodyCollider::Impl::checkPose(Span<const Vec3> positions, const char* what) const {
    if (positions.size() != current.size()) {
        return Status::invalidArgument(std::string(what) + ": got " + std::to_string(positions.size()) +
                                       " body vertices, the body has " + std::to_string(current.size()));
    }
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!isFinite(positions[i])) {
            return Status::invalidArgument(std::string(what) + ": body vertex " + std::to_string(i) +
                                           " has a non-finite position");
        }
    }
    return Status::ok();
}

void BodyCollider::Impl::computeNormals() {
    const uint32_t nt = uint32_t(shape->triangles.size());
    stats.degenerateTriangles = 0;
    const double limit2 = 4.0 * settings.degenerateArea * settings.degenerateArea;
    for (uint32_t t = 0; t < nt; ++t) {
        const auto& tri = shape->triangles[t];
        const Vec3 a = current[tri[0]], e0 = current[tri[1]] - a, e2 = current[tri[2]] - a;
        const Vec3 e1 = e2 - e0;
        const Vec3 cross = e0.cross(e2);
        const double longest2 = std::max(std::max(e0.squaredNorm(), e1.squaredNorm()), e2.squaredNorm());
        // Degenerate when area = |cross| / 2 <= degenerateArea * longest^2 (squared: no square roots).
        const double cross2 = cross.squaredNorm();
        const bool bad = !(cross2 > limit2 * longest2 * longest2) || longest2 == 0.0;
        degenerate[t] = bad;
        if (bad) {
            ++stats.degenerateTriangles;
            faceNormal[t].setZero();
            continue;
        }
        faceNormal[t] = cross / std::sqrt(cross2);
    }
    for (std::size_t g = 0; g + 1 < shape->edgeStart.size(); ++g) {
        Vec3 sum = Vec3::Zero();
        for (uint32_t s = shape->edgeStart[g]; s < shape->edgeStart[g + 1]; ++s) sum += faceNormal[shape->edgeSlots[s] / 3];
        for (uint32_t s = shape->edgeStart[g]; s < shape->edgeStart[g + 1]; ++s) edgeNormal[shape->edgeSlots[s]] = sum;
    }
}

Vec3 BodyCollider::Impl::vertexPseudonormal(uint32_t v) const {
    // Angle-weighted sum of the face normals around v (Baerentzen & Aanaes 2005), in a fixed order.
    Vec3 sum = Vec3::Zero();
    for (uint32_t k = shape->vertexStart[v]; k < shape->vertexStart[v + 1]; ++k) {
        const uint32_t t = shape->vertexTriangles[k];
        if (degenerate[t]) continue;
        const auto& tri = shape->triangles[t];
        const int corner = shape->welded[t][0] == v ? 0 : shape->welded[t][1] == v ? 1 : 2;
        // Interior angle at the corner, between the edges leaving it.
        const Vec3& at = current[tri[corner]];
        const Vec3 u = current[tri[(corner + 1) % 3]] - at, w = current[tri[(corner + 2) % 3]] - at;
        sum += std::atan2(u.cross(w).norm(), u.dot(w)) * faceNormal[t];
    }
    return sum;
}

Vec3 BodyCollider::Impl::pseudonormal(uint32_t t, Feature f) const {
    switch (f) {
    case Feature::Face: return faceNormal[t];
    case Feature::Vertex0: return vertexPseudonormal(shape->welded[t][0]);
    case Feature::Vertex1: return vertexPseudonormal(shape->welded[t][1]);
    case Feature::Vertex2: return vertexPseudonormal(shape->welded[t][2]);
    case Feature::Edge0: return edgeNormal[3 * t + 0];
    case Feature::Edge1: return edgeNormal[3 * t + 1];
    case Feature::Edge2: return edgeNormal[3 * t + 2];
    }
    return faceNormal[t];
}

void BodyCollider::Impl::writeVertexBuffer() {
    auto* buffer = static_cast<float*>(rtcGetGeometryBufferData(mesh, RTC_BUFFER_TYPE_VERTEX, 0));
    for (std::size_t i = 0; i < current.size(); ++i) {
        buffer[3 * i + 0] = float(current[i].x());
        buffer[3 * i + 1] = float(current[i].y());
        buffer[3 * i + 2] = float(current[i].z());
    }
}

Status BodyCollider::Impl::buildScenes() {
    detail::ScopedFlushDenormals ftz;
    if (scene) {
        // Rebuilt in place: Embree's fresh scenes cost 5-7 ms on the 5,776-triangle mannequin
        // (their memory allocated and faulted in anew), a rebuild of the existing ones 0.5.
        commitMesh();
        rtcSetGeometryBuildQuality(sweptGeometry, RTC_BUILD_QUALITY_LOW);  // a rebuild, once
        rtcCommitGeometry(sweptGeometry);
        rtcCommitScene(swept);
        // Refits from here on; the geometry is committed again, so the scene is too before the next
        // continuous query (a refit of boxes that did not change).
        rtcSetGeometryBuildQuality(sweptGeometry, RTC_BUILD_QUALITY_REFIT);
        rtcCommitGeometry(sweptGeometry);
        sweptCurrent = false;
        recordBuild();
        return device->takeError();
    }
    RTCDevice dev = device->impl().device;
    scene = rtcNewScene(dev);
    // Context filters: traceRays collects every crossing of a ray in one traversal.
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    mesh = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Low quality: each update rebuilds this tree in place (Embree's Morton builder) instead of
    // refitting it. On one build thread that is the faster one, measured on a 5,880-triangle
    // body: 0.4 ms to build against 2.0, 0.55 ms per update against 1.5, queries 15 % slower.
    rtcSetGeometryBuildQuality(mesh, RTC_BUILD_QUALITY_LOW);
    // rtcSetNewGeometryBuffer pads the buffer for Embree's 16-byte loads (ECOSYSTEM.md pitfall 2).
    auto* index = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(uint32_t), shape->triangles.size()));
    const bool gotVertexBuffer = rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), current.size()) != nullptr;
    if (!index || !gotVertexBuffer) {
        Status e = device->takeError();
        return Status::error(StatusCode::InvalidOperation, "BodyCollider: could not allocate Embree buffers (" +
                                                               e.message() + ")");
    }
    for (std::size_t t = 0; t < shape->triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) index[3 * t + k] = shape->triangles[t][k];
    }
    writeVertexBuffer();
    rtcCommitGeometry(mesh);
    rtcAttachGeometryByID(scene, mesh, 0);
    rtcCommitScene(scene);

    swept = rtcNewScene(dev);
    rtcSetSceneFlags(swept, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(swept, RTC_BUILD_QUALITY_LOW);
    sweptGeometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryBuildQuality(sweptGeometry, RTC_BUILD_QUALITY_REFIT);
    rtcSetGeometryUserPrimitiveCount(sweptGeometry, uint32_t(shape->triangles.size()));
    rtcSetGeometryUserData(sweptGeometry, this);
    rtcSetGeometryBoundsFunction(sweptGeometry, sweptBounds, nullptr);
    rtcCommitGeometry(sweptGeometry);
    rtcAttachGeometryByID(swept, sweptGeometry, 0);
    rtcCommitScene(swept);
    sweptCurrent = true;
    recordBuild();
    return device->takeError();
}

void BodyCollider::Impl::commitMesh() {
    // The refit workflow (ECOSYSTEM.md pitfall 3): write, mark updated, commit geometry and scene.
    // The mesh is low quality: a commit rebuilds its tree in place.
    writeVertexBuffer();
    rtcUpdateGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(mesh);
    rtcCommitScene(scene);
}

void BodyCollider::Impl::recordBuild() {
    buildPose = current;
    Eigen::AlignedBox3d box;
    for (const Vec3& p : current) box.extend(p);
    buildDiagonal = box.diagonal().norm();
    ++stats.rebuilds;
}

Status BodyCollider::Impl::refit() {
    double moved = 0.0;
    for (std::size_t i = 0; i < current.size(); ++i) moved += (current[i] - buildPose[i]).norm();
    moved /= double(current.size());
    if (moved > settings.rebuildFraction * buildDiagonal) return buildScenes();

    detail::ScopedFlushDenormals ftz;
    commitMesh();
    // The swept boxes follow the same motion; their tree is refit when a continuous query asks.
    sweptCurrent = false;
    ++stats.refits;
    return device->takeError();
}

Result<std::unique_ptr<BodyCollider>> BodyCollider::create(CollisionDevice& device,
                                                           Span<const std::array<uint32_t, 3>> triangles,
                                                           Span<const Vec3> positions,
                                                           const BodyColliderSettings& settings) {
    auto shape = BodyTopology::build(triangles, positions);
    if (!shape.isOk()) return shape.status();
    return create(device, std::move(shape).value(), positions, settings);
}

Result<std::unique_ptr<BodyCollider>> BodyCollider::create(CollisionDevice& device,
                                                           std::shared_ptr<const BodyTopology> shape,
                                                           Span<const Vec3> positions,
                                                           const BodyColliderSettings& settings) {
    if (Status s = settings.validate(); !s) return s;
    if (!shape) return Status::invalidArgument("BodyCollider: the body topology is null");
    auto impl = std::make_unique<Impl>();
    impl->device = &device;
    impl->settings = settings;
    impl->shape = std::move(shape);
    impl->current.assign(impl->shape->vertexCount, Vec3::Zero());
    if (Status s = impl->checkPose(positions, "BodyCollider::create"); !s) return s;
    impl->current.assign(positions.begin(), positions.end());
    impl->previous = impl->current;
    impl->velocity.assign(positions.size(), Vec3::Zero());
    const std::size_t nt = impl->shape->triangles.size();
    impl->faceNormal.assign(nt, Vec3::Zero());
    impl->edgeNormal.assign(3 * nt, Vec3::Zero());
    impl->degenerate.assign(nt, 0);
    impl->computeNormals();
    if (Status s = impl->buildScenes(); !s) return s;
    return std::unique_ptr<BodyCollider>(new BodyCollider(std::move(impl)));
}

BodyCollider::BodyCollider(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}
BodyCollider::~BodyCollider() = default;

Status BodyCollider::update(Span<const Vec3> positions, double dt) {
    if (!(dt > 0.0) || !std::isfinite(dt)) {
        return Status::invalidArgument("BodyCollider::update: dt = " + std::to_string(dt) + " s must be finite and > 0");
    }
    if (Status s = mImpl->checkPose(positions, "BodyCollider::update"); !s) return s;
    Impl& m = *mImpl;
    m.previous.swap(m.current);
    m.current.assign(positions.begin(), positions.end());
    for (std::size_t i = 0; i < m.current.size(); ++i) m.velocity[i] = (m.current[i] - m.previous[i]) / dt;
    m.computeNormals();
    return m.refit();
}

Status BodyCollider::Impl::refitSwept() const {
    if (sweptCurrent.load(std::memory_order_acquire)) return Status::ok();
    std::lock_guard<std::mutex> lock(sweptMutex);
    if (sweptCurrent.load(std::memory_order_relaxed)) return Status::ok();
    detail::ScopedFlushDenormals ftz;
    rtcCommitGeometry(sweptGeometry);
    rtcCommitScene(swept);
    sweptCurrent.store(true, std::memory_order_release);
    return device->takeError();
}

Status BodyCollider::reset(Span<const Vec3> positions) {
    if (Status s = mImpl->checkPose(positions, "BodyCollider::reset"); !s) return s;
    Impl& m = *mImpl;
    m.current.assign(positions.begin(), positions.end());
    m.previous = m.current;
    std::fill(m.velocity.begin(), m.velocity.end(), Vec3::Zero());
    m.computeNormals();
    // The trees are refit unless the pose moved far from the one they were built on, as in an
    // update: positions are in the body's own frame, so a teleported body, or a collider handed to
    // another character of the same body, is in a similar pose.
    return m.refit();
}

uint32_t BodyCollider::vertexCount() const { return uint32_t(mImpl->current.size()); }
uint32_t BodyCollider::triangleCount() const { return uint32_t(mImpl->shape->triangles.size()); }
Span<const Vec3> BodyCollider::currentPositions() const { return mImpl->current; }
Span<const Vec3> BodyCollider::previousPositions() const { return mImpl->previous; }
const BodyColliderStats& BodyCollider::stats() const { return mImpl->stats; }

namespace {

/// The nearest point of one part of the body.
struct PartCandidate {
    uint32_t part = UINT32_MAX;
    double best2 = 0.0;  // squared distance
    uint32_t triangle = UINT32_MAX;
    ClosestPoint closest;
};

/// The nearest point of each of the nearest parts within reach (kParts at most; a point is rarely
/// within reach of more than two or three).
struct ProximitySearch {
    static constexpr int kParts = 4;
    const BodyCollider::Impl* body;
    Vec3 p;
    double reach2;
    double scale;
    PartCandidate parts[kParts];
    int count = 0;
};

/// With every part slot taken, only a triangle nearer than the farthest kept part can change the
/// answer: the search sphere shrinks to that part (exact; a wide correction reach around a swinging
/// hem otherwise visits every triangle of every limb near it).
void shrinkWhenFull(const ProximitySearch& search, RTCPointQuery& query) {
    if (search.count < ProximitySearch::kParts) return;
    double farthest2 = 0.0;
    for (int k = 0; k < search.count; ++k) farthest2 = std::max(farthest2, search.parts[k].best2);
    query.radius = std::min(query.radius, widen(std::sqrt(farthest2), search.scale));
}

bool proximityCallback(RTCPointQueryFunctionArguments* args) {
    auto* search = static_cast<ProximitySearch*>(args->userPtr);
    const BodyCollider::Impl& body = *search->body;
    const uint32_t t = args->primID;
    if (body.degenerate[t]) return false;
    const auto& tri = body.shape->triangles[t];
    const ClosestPoint c = detail::closestPointOnTriangle(search->p, body.current[tri[0]], body.current[tri[1]],
                                                          body.current[tri[2]]);
    const double d2 = (search->p - c.point).squaredNorm();
    if (d2 > search->reach2) return false;
    const uint32_t part = body.shape->part[t];
    int slot = 0;
    while (slot < search->count && search->parts[slot].part != part) ++slot;
    if (slot == search->count) {
        if (search->count < ProximitySearch::kParts) {
            ++search->count;
        } else {
            // Full: replace the farthest part if this one is nearer.
            slot = 0;
            for (int k = 1; k < search->count; ++k)
                if (search->parts[k].best2 > search->parts[slot].best2) slot = k;
            if (d2 >= search->parts[slot].best2) return false;
        }
        search->parts[slot] = {part, d2, t, c};
        shrinkWhenFull(*search, *args->query);
        return true;
    }
    PartCandidate& best = search->parts[slot];
    // Ties go to the lower triangle index, so the result does not depend on traversal order.
    if (d2 < best.best2 || (d2 == best.best2 && t < best.triangle)) {
        best.best2 = d2;
        best.triangle = t;
        best.closest = c;
        // One part within reach: the search sphere can shrink to it (ECOSYSTEM.md pitfall 4).
        if (body.shape->partCount == 1) args->query->radius = std::min(args->query->radius, widen(std::sqrt(d2), search->scale));
        shrinkWhenFull(*search, *args->query);
        return true;
    }
    return false;
}

Vec3 surfaceVelocity(const BodyCollider::Impl& body, uint32_t t, const std::array<double, 3>& w) {
    const auto& tri = body.shape->triangles[t];
    return w[0] * body.velocity[tri[0]] + w[1] * body.velocity[tri[1]] + w[2] * body.velocity[tri[2]];
}

} // namespace

namespace {

/// A ray's crossings of the body's closed parts, gathered by an intersection filter that records
/// every hit and rejects it, so one traversal finds them all (Embree's "collect all hits").
struct CrossingCollector {
    RTCIntersectContext context;  // first: Embree hands the filter this pointer
    const BodyCollider::Impl* body = nullptr;
    Vec3 direction = Vec3::Zero();
    RayParts parts = RayParts::Closed;
    static constexpr int kMax = 256;  // a ray through a body crosses a few dozen surfaces at most
    std::array<std::pair<float, int8_t>, kMax> crossings{};  // distance, +1 leaving / -1 entering
    int count = 0;
};

void collectCrossing(const RTCFilterFunctionNArguments* args);

} // namespace

Status BodyCollider::traceRays(Span<const Vec3> origins, Span<const Vec3> directions,
                               RayParts parts, Span<RayTrace> outTraces) const {
    if (origins.size() != directions.size() || outTraces.size() != origins.size())
        return Status::invalidArgument("BodyCollider::traceRays: one direction and one trace per origin");
    if (Status s = detail::checkPoints(origins, "BodyCollider::traceRays"); !s) return s;
    for (std::size_t i = 0; i < directions.size(); ++i)
        if (!(std::abs(directions[i].norm() - 1.0) < 1e-6))
            return Status::invalidArgument("BodyCollider::traceRays: direction " + std::to_string(i) + " is not a unit vector");
    CrossingCollector collector;
    collector.body = mImpl.get();
    collector.parts = parts;
    for (std::size_t i = 0; i < origins.size(); ++i) {
        const Vec3& o = origins[i];
        const Vec3& d = directions[i];
        rtcInitIntersectContext(&collector.context);
        collector.context.filter = collectCrossing;
        collector.direction = d;
        collector.count = 0;
        RTCRayHit hit{};
        hit.ray.org_x = float(o.x()), hit.ray.org_y = float(o.y()), hit.ray.org_z = float(o.z());
        hit.ray.dir_x = float(d.x()), hit.ray.dir_y = float(d.y()), hit.ray.dir_z = float(d.z());
        hit.ray.tnear = 0.0f;
        hit.ray.tfar = std::numeric_limits<float>::infinity();
        hit.ray.mask = 0xFFFFFFFFu;
        hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(mImpl->scene, &collector.context, &hit);
        // In order along the ray; a ray through a shared edge or vertex meets each of its
        // triangles at one distance: one crossing.
        auto* first = collector.crossings.data();
        std::sort(first, first + collector.count);
        int kept = 0;
        for (int k = 0; k < collector.count; ++k) {
            const auto& c = collector.crossings[std::size_t(k)];
            const bool repeat = kept > 0 && c.second == collector.crossings[std::size_t(kept - 1)].second &&
                                c.first - collector.crossings[std::size_t(kept - 1)].first <= 1e-6f * (1.0f + c.first);
            if (!repeat) collector.crossings[std::size_t(kept++)] = c;
        }
        // Inside as many parts as the ray leaves more often than it enters; it is out of the body
        // at the crossing where that count first drops to zero.
        RayTrace trace;
        for (int k = 0; k < kept; ++k) {
            const auto& c = collector.crossings[std::size_t(k)];
            trace.partsInside += c.second;
            if (c.second < 0 && trace.firstEntry < 0.0) trace.firstEntry = double(c.first);
        }
        int inside = trace.partsInside;
        for (int k = 0; k < kept && inside > 0; ++k) {
            inside -= collector.crossings[std::size_t(k)].second;
            if (inside == 0) trace.firstExit = double(collector.crossings[std::size_t(k)].first);
        }
        outTraces[i] = trace;
    }
    return Status::ok();
}

namespace {

void collectCrossing(const RTCFilterFunctionNArguments* args) {
    auto* collector = reinterpret_cast<CrossingCollector*>(args->context);
    const BodyCollider::Impl& body = *collector->body;
    for (unsigned int k = 0; k < args->N; ++k) {
        if (!args->valid[k]) continue;
        args->valid[k] = 0;  // rejected: the traversal goes on to the next hit
        const uint32_t t = RTCHitN_primID(args->hit, args->N, k);
        if (body.degenerate[t]) continue;
        if (collector->parts == RayParts::Closed && !body.shape->partClosed[body.shape->part[t]])
            continue;
        // The body's own outward normals (Embree's Ng follows its winding convention, not ours).
        const double facing = body.faceNormal[t].dot(collector->direction);
        if (facing == 0.0 || collector->count == CrossingCollector::kMax) continue;
        collector->crossings[std::size_t(collector->count++)] = {RTCRayN_tfar(args->ray, args->N, k), int8_t(facing > 0.0 ? 1 : -1)};
    }
}

} // namespace

Status BodyCollider::queryProximity(Span<const Vec3> points, const ContactQuery& query,
                                    std::vector<Contact>& outContacts) const {
    outContacts.clear();
    if (Status s = query.validateFor(points.size()); !s) return s;
    if (Status s = detail::checkPoints(points, "BodyCollider::queryProximity"); !s) return s;
    const Impl& body = *mImpl;
    // kParts slots per point, filled in parallel, then compacted in index order: sorted by vertex
    // and independent of thread timing.
    constexpr int kParts = ProximitySearch::kParts;
    outContacts.resize(points.size() * kParts);
    parallelFor(int64_t(points.size()), query.parallel, [&](int64_t begin, int64_t end) {
        detail::ScopedFlushDenormals ftz;
        for (int64_t i = begin; i < end; ++i) {
            for (int k = 0; k < kParts; ++k) outContacts[i * kParts + k].vertex = UINT32_MAX;
            const double reach = query.reach(std::size_t(i));
            ProximitySearch search;
            search.body = &body;
            search.p = points[i];
            search.reach2 = reach * reach * (1.0 + 1e-12);
            search.scale = points[i].cwiseAbs().maxCoeff() + reach;
            RTCPointQuery q;
            q.x = float(points[i].x()), q.y = float(points[i].y()), q.z = float(points[i].z());
            q.time = 0.0f;
            q.radius = widen(reach, search.scale);
            RTCPointQueryContext context;
            rtcInitPointQueryContext(&context);
            rtcPointQuery(body.scene, &q, &context, proximityCallback, &search);
            // One contact per part within reach, each with its own side: a point inside any part
            // is inside the body, and each part it is near bounds where it may go.
            for (int k = 1; k < search.count; ++k)  // by part: a few entries, insertion sort
                for (int j = k; j > 0 && search.parts[j].part < search.parts[j - 1].part; --j)
                    std::swap(search.parts[j], search.parts[j - 1]);
            for (int k = 0; k < search.count; ++k) {
                const PartCandidate& found = search.parts[k];
                const double dist = std::sqrt(found.best2);
                const Vec3 pseudo = body.pseudonormal(found.triangle, found.closest.feature);
                const Vec3 away = points[i] - found.closest.point;
                const bool inside = away.dot(pseudo) < 0.0;
                Vec3 normal;
                if (found.closest.feature == Feature::Face || dist <= 1e-12 * search.scale) {
                    normal = pseudo.normalized();
                } else {
                    normal = (inside ? -away : away) / dist;
                }
                Contact& c = outContacts[i * kParts + k];
                c.vertex = uint32_t(i);
                c.primitive = found.triangle;
                c.part = found.part;
                c.point = found.closest.point;
                c.normal = normal;
                c.surfaceVelocity = surfaceVelocity(body, found.triangle, found.closest.weights);
                c.depth = query.thickness - (inside ? -dist : dist);
                c.time = 1.0;
                c.source = ContactSource::Proximity;
            }
        }
    });
    outContacts.erase(std::remove_if(outContacts.begin(), outContacts.end(),
                                     [](const Contact& c) { return c.vertex == UINT32_MAX; }),
                      outContacts.end());
    return Status::ok();
}

namespace {

struct SweptSearch {
    const BodyCollider::Impl* body;
    Vec3 start, end;
    CcdSettings ccd;
    double reach;      // [m] farthest distance at which the CCD can report a contact
    double thickness;  // [m] the query's: a contact deeper than nothing only within it of the plane
    Contact* best;     // the earliest hit so far; vertex == UINT32_MAX while none
};

/// True when a point moving linearly from p0 to p1 stays farther than `reach` from the plane of a
/// triangle whose corners move linearly (a0 -> a1, ...), over the whole step: then it stays that far
/// from the triangle too, and the exact CCD can only answer "separated". The signed distance times
/// |n(t)| is the cubic f(t) = (p - a)(t) . n(t), n = (b - a) x (c - a) quadratic; both are bounded
/// on [0, 1] by their Bernstein coefficients (the convex hull property, Farin 2002, ch. 5). Cloth
/// sliding over a limb at a gap moves fast along the surface but stays off it: the swept box and
/// the Lipschitz bound above cannot tell, this test can.
bool staysAbovePlane(const Vec3& p0, const Vec3& p1, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1,
                     const Vec3& b1, const Vec3& c1, double reach) {
    const Vec3 q0 = p0 - a0, dq = (p1 - a1) - q0;
    const Vec3 e10 = b0 - a0, de1 = (b1 - a1) - e10;
    const Vec3 e20 = c0 - a0, de2 = (c1 - a1) - e20;
    const Vec3 n0 = e10.cross(e20), n1 = e10.cross(de2) + de1.cross(e20), n2 = de1.cross(de2);
    // Power-basis coefficients of f, then its Bernstein coefficients.
    const double f0 = q0.dot(n0), f1 = q0.dot(n1) + dq.dot(n0), f2 = q0.dot(n2) + dq.dot(n1), f3 = dq.dot(n2);
    const double fMin = std::min({f0, f0 + f1 / 3.0, f0 + (2.0 * f1 + f2) / 3.0, f0 + f1 + f2 + f3});
    if (!(fMin > 0.0)) return false;
    const double nMax = std::max({n0.norm(), (n0 + 0.5 * n1).norm(), (n0 + n1 + n2).norm()});
    return fMin > reach * nMax;
}

bool sweptCallback(RTCPointQueryFunctionArguments* args) {
    auto* search = static_cast<SweptSearch*>(args->userPtr);
    const BodyCollider::Impl& body = *search->body;
    const uint32_t t = args->primID;
    if (body.degenerate[t]) return false;
    const auto& tri = body.shape->triangles[t];
    const Vec3 &a0 = body.previous[tri[0]], &b0 = body.previous[tri[1]], &c0 = body.previous[tri[2]];
    // Only a vertex that starts on the outer side of the triangle can cross it; one already behind
    // it is a penetration the proximity contact (with its pseudonormal side test) resolves.
    const Vec3 n0 = (b0 - a0).cross(c0 - a0);
    if ((search->start - a0).dot(n0) < 0.0) return false;
    const Vec3 &a1 = body.current[tri[0]], &b1 = body.current[tri[1]], &c1 = body.current[tri[2]];
    // A hit's contact lies on the face at the end pose with the face normal, so its depth is the
    // thickness minus the end point's height over the face's plane: a vertex that ends a thickness
    // or more above it gets a contact that asks for nothing (and would displace a proximity
    // contact of the same part that does). Most vertices a limb sweeps past end there.
    if ((search->end - a1).dot(body.faceNormal[t]) >= search->thickness) return false;
    // Cheap proof of separation before the exact test. In the frame of corner a the point moves
    // by dq and the edges by de1, de2; any point a + u e1 + v e2 (u, v >= 0, u + v <= 1) then moves
    // by at most L = |dq| + max(|de1|, |de2|), so the distance over the step is >= (d0 + d1 - L) / 2.
    // Cloth resting on or riding with the body (small relative motion) never reaches the CCD.
    const Vec3 da = a1 - a0;
    const double lipschitz = ((search->end - search->start) - da).norm() +
                             std::max(((b1 - b0) - da).norm(), ((c1 - c0) - da).norm());
    const double d0 = (search->start - detail::closestPointOnTriangle(search->start, a0, b0, c0).point).norm();
    const double d1 = (search->end - detail::closestPointOnTriangle(search->end, a1, b1, c1).point).norm();
    if (0.5 * (d0 + d1 - lipschitz) > search->reach) return false;
    if (staysAbovePlane(search->start, search->end, a0, b0, c0, a1, b1, c1, search->reach)) return false;
    CcdHit hit;
    const CcdOutcome outcome = vertexTriangleCcd({search->start, a0, b0, c0},
                                                 {search->end, body.current[tri[0]], body.current[tri[1]],
                                                  body.current[tri[2]]},
                                                 search->ccd, hit);
    if (outcome != CcdOutcome::Contact) return false;
    Contact& best = *search->best;
    if (best.vertex != UINT32_MAX && (hit.toi > best.time || (hit.toi == best.time && t > best.primitive))) {
        return false;
    }
    const auto& w = hit.weights;
    best.vertex = 0;  // set by the caller
    best.primitive = t;
    best.part = body.shape->part[t];
    best.time = hit.toi;
    best.point = w[0] * body.current[tri[0]] + w[1] * body.current[tri[1]] + w[2] * body.current[tri[2]];
    best.normal = body.faceNormal[t];
    best.surfaceVelocity = surfaceVelocity(body, t, w);
    return false;
}

} // namespace

Status BodyCollider::queryContinuous(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                                     std::vector<Contact>& outContacts) const {
    outContacts.clear();
    if (Status s = detail::checkContinuousQuery(start, end, query, "BodyCollider"); !s) return s;
    const Impl& body = *mImpl;
    if (Status s = body.refitSwept(); !s) return s;
    // The swept test reports first contact within a quarter of the thickness: a vertex resting at
    // the thickness is left to the proximity contact, one about to cross is caught before it does.
    CcdSettings ccd;
    ccd.thickness = 0.25 * query.thickness;
    // Resolving the gap finer than half the contact distance, or the time of impact finer than a
    // thousandth of the update, buys nothing (the contact plane is placed at the end pose; a wider
    // band only reports a near miss, whose plane asks for nothing) and costs inclusion boxes:
    // 86 per query at 5 % and 1e-6, 31 at these.
    ccd.distanceTolerance = 0.5 * ccd.thickness;
    ccd.timeTolerance = 1e-3;
    const double reach = std::sqrt(3.0) * ccd.thickness + 2.0 * ccd.distanceTolerance;
    outContacts.resize(start.size());
    parallelFor(int64_t(start.size()), query.parallel, [&](int64_t begin, int64_t stop) {
        detail::ScopedFlushDenormals ftz;
        for (int64_t i = begin; i < stop; ++i) {
            Contact& c = outContacts[i];
            c = Contact{};
            c.vertex = UINT32_MAX;
            SweptSearch search{&body, start[i], end[i], ccd, reach, query.thickness, &c};
            // The sphere around the vertex's segment: every swept box it can touch.
            const Vec3 mid = 0.5 * (start[i] + end[i]);
            const double scale = mid.cwiseAbs().maxCoeff() + 1.0;
            RTCPointQuery q;
            q.x = float(mid.x()), q.y = float(mid.y()), q.z = float(mid.z());
            q.time = 0.0f;
            q.radius = widen(0.5 * (end[i] - start[i]).norm() + reach, scale);
            RTCPointQueryContext context;
            rtcInitPointQueryContext(&context);
            rtcPointQuery(body.swept, &q, &context, sweptCallback, &search);
            if (c.vertex == UINT32_MAX) continue;
            c.vertex = uint32_t(i);
            c.depth = query.thickness - (end[i] - c.point).dot(c.normal);
            c.source = ContactSource::Continuous;
        }
    });
    outContacts.erase(std::remove_if(outContacts.begin(), outContacts.end(),
                                     [](const Contact& c) { return c.vertex == UINT32_MAX; }),
                      outContacts.end());
    return Status::ok();
}

} // namespace cc::collision
