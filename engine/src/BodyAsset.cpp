#include "BodyAsset.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace cc::detail {

Result<BodyAsset> makeMannequinBody(const MannequinDesc& desc) {
    MannequinParams params;
    params.height = desc.height;
    params.shoulderWidth = desc.shoulderWidth;
    params.hipWidth = desc.hipWidth;
    params.waistWidth = desc.waistWidth;
    params.limbGirth = desc.limbGirth;
    auto mannequin = buildMannequin(params);
    if (!mannequin.isOk()) return Status::invalidArgument("MannequinDesc: " + mannequin.status().message());
    BodyAsset body;
    body.mannequin = std::move(mannequin).value();
    body.anchorMesh = body.mesh();
    body.anchorMesh.triangles.clear();
    for (const BodyPart& part : body.mannequin.parts) {
        if (part.name != "torso" && part.name != "neck") continue;
        const auto& all = body.mesh().triangles;
        body.anchorMesh.triangles.insert(body.anchorMesh.triangles.end(), all.begin() + part.firstTriangle,
                                         all.begin() + part.firstTriangle + part.triangleCount);
    }
    if (body.anchorMesh.triangles.empty()) body.anchorMesh.triangles = body.mesh().triangles;
    return body;
}

Status readFloat3(const float* data, uint32_t count, uint32_t strideBytes, const char* what,
                  std::vector<Vec3>& outPositions) {
    if (!data && count > 0) return Status::invalidArgument(std::string(what) + " is null");
    const uint32_t stride = strideBytes == 0 ? 3 * sizeof(float) : strideBytes;
    if (stride < 3 * sizeof(float)) return Status::invalidArgument(std::string(what) + ": stride below 12 bytes");
    outPositions.resize(count);
    const unsigned char* bytes = reinterpret_cast<const unsigned char*>(data);
    for (uint32_t i = 0; i < count; ++i) {
        float xyz[3];
        std::memcpy(xyz, bytes + std::size_t(i) * stride, sizeof(xyz));
        outPositions[i] = Vec3(xyz[0], xyz[1], xyz[2]);
        if (!isFinite(outPositions[i]))
            return Status::invalidArgument(std::string(what) + ": vertex " + std::to_string(i) + " is not finite");
    }
    return Status::ok();
}

Result<BodyAsset> makeHostSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                      const uint32_t* triangles, uint32_t triangleCount) {
    if (vertexCount < 3 || triangleCount < 1 || !triangles)
        return Status::invalidArgument("addSkinnedBody: needs at least 3 vertices and 1 triangle");
    if (vertexCount > kMaxBodyVertices || triangleCount > kMaxBodyTriangles)
        return Status::invalidArgument("addSkinnedBody: more vertices or triangles than the caps allow");
    BodyAsset body;
    body.hostSkinned = true;
    SkinnedMesh& mesh = body.mannequin.character.body;
    if (Status s = readFloat3(bindPositions, vertexCount, strideBytes, "addSkinnedBody bind positions",
                              mesh.bindPositions); !s)
        return s;
    mesh.triangles.resize(triangleCount);
    for (uint32_t t = 0; t < triangleCount; ++t) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = triangles[3 * t + k];
            if (v >= vertexCount)
                return Status::invalidArgument("addSkinnedBody: triangle " + std::to_string(t) + " uses vertex " +
                                               std::to_string(v) + " of " + std::to_string(vertexCount));
            mesh.triangles[t][k] = v;
        }
    }
    // One pseudo-joint with weight 1 everywhere: bindings then carry offsets rigidly with the
    // triangle they sit on, which is all a host-skinned body offers.
    mesh.jointIndices.assign(vertexCount, {0, 0, 0, 0});
    mesh.jointWeights.assign(vertexCount, {1.0, 0.0, 0.0, 0.0});
    mesh.inverseBindMatrices.assign(1, Mat4::Identity());
    mesh.computeBindNormals();
    body.anchorMesh = mesh;
    return body;
}

namespace {

struct Box {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max());
    Vec3 hi = Vec3::Constant(std::numeric_limits<double>::lowest());
};

Box bounds(const std::vector<Vec3>& points) {
    Box b;
    for (const Vec3& p : points) b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
    return b;
}

/// The body's back (smallest z) over heights [yLow, yHigh] within halfWidth of the centre line:
/// a cape hung there starts clear of the shoulder blades, the seat and the arms.
double backOver(const std::vector<Vec3>& points, double yLow, double yHigh, double centreX, double halfWidth) {
    double back = std::numeric_limits<double>::max();
    for (const Vec3& p : points)
        if (p.y() >= yLow && p.y() <= yHigh && std::abs(p.x() - centreX) < halfWidth) back = std::min(back, p.z());
    return back == std::numeric_limits<double>::max() ? 0.0 : back;
}

} // namespace

Vec3 garmentPlacement(const BodyAsset& body, GarmentKind kind, double garmentWidth, double garmentLength,
                      double thickness) {
    const std::vector<Vec3>& points = body.mesh().bindPositions;
    const Box box = bounds(points);
    const double height = box.hi.y() - box.lo.y();
    const Vec3 centre = 0.5 * (box.lo + box.hi);
    double shoulderY = box.lo.y() + 0.82 * height;
    Vec3 waist(centre.x(), box.lo.y() + 0.6 * height, centre.z());
    if (!body.hostSkinned) {
        const BodyLandmarks& l = body.mannequin.landmarks;
        shoulderY = 0.5 * (l.leftShoulder.y() + l.rightShoulder.y());
        waist = l.waistCentre;
    }
    const double gap = thickness + 0.01;
    switch (kind) {
    case GarmentKind::Cape: {
        const double top = shoulderY - 0.03;
        const double back = backOver(points, top - garmentLength, top, centre.x(), 0.5 * garmentWidth);
        return Vec3(centre.x(), top - garmentLength, back - gap);
    }
    case GarmentKind::Skirt: return waist - Vec3(0.0, garmentLength, 0.0);
    case GarmentKind::Dress: return Vec3(waist.x(), shoulderY - 0.05 - garmentLength, waist.z());
    case GarmentKind::Poncho: return Vec3(waist.x(), shoulderY + gap - garmentLength, waist.z());
    }
    return Vec3::Zero();
}

} // namespace cc::detail
