#include "BodyAsset.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "crowdcloth/character/CapsuleFit.h"
#include "crowdcloth/character/ClipStride.h"

namespace cc::detail {
namespace {

/// [rad] arms held higher than this from vertical in the rest pose (T and A poses) are lowered to
/// kRelaxedAbduction before garments are fitted around them: a walk or an idle holds them there.
constexpr double kRaisedArm = 0.5;
constexpr double kRelaxedAbduction = 0.2;
/// [-] a triangle is torso skin when every corner has at least this much weight on torso and neck
/// joints: garments bind only there.
constexpr double kAnchorWeight = 0.9;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string nameOf(const BodyAsset& body) {
    return body.character().name.empty() ? std::string("body") : "body '" + body.character().name + "'";
}

/// Torso and neck triangles by the regions' anchor weights.
void makeAnchorMesh(BodyAsset& body) {
    body.anchorMesh = body.mesh();
    body.anchorMesh.triangles.clear();
    for (const auto& t : body.mesh().triangles) {
        bool torso = true;
        for (uint32_t v : t) torso = torso && body.regions.anchorWeight[v] >= kAnchorWeight;
        if (torso) body.anchorMesh.triangles.push_back(t);
    }
}

/// Regions, the relaxed fitting pose, measurements and (unless the body brings its own) the
/// anchor mesh. A body that is not a humanoid keeps the reason in fitStatus.
void analyse(BodyAsset& body, bool keepAnchorMesh) {
    const Character& ch = body.character();
    const bool skinned = !body.hostSkinned && ch.skeleton.jointCount() > 0;
    std::vector<Vec3> jointPositions;
    CharacterPose pose;
    if (skinned) {
        pose = CharacterPose(ch);
        if (Status s = pose.evaluate(ch, -1, 0.0, ClipWrap::Clamp); !s) {
            body.fitStatus = s;
            return;
        }
        body.restSkin.assign(pose.skinMatrices().begin(), pose.skinMatrices().end());
        body.restPositions.resize(ch.body.vertexCount());
        if (Status s = skinVertices(ch.body, pose.skinMatrices(), body.restPositions, {}); !s) {
            body.fitStatus = s;
            return;
        }
        for (const Mat4& g : pose.globalTransforms()) jointPositions.push_back(g.topRightCorner<3, 1>());
    } else {
        body.restPositions = ch.body.bindPositions;
    }
    body.fitPositions = body.restPositions;
    const std::string name = nameOf(body);
    Status found;
    if (skinned) {
        auto regions = findBodyRegions(ch, body.restPositions);
        if (regions.isOk()) {
            body.regions = std::move(regions).value();
        } else {
            found = regions.status();
        }
    }
    if (!skinned || !found) {
        // No skeleton, or one that does not describe a humanoid: the geometry alone.
        SkinnedMesh rest = ch.body;
        rest.bindPositions = body.restPositions;
        auto regions = findBodyRegionsFromGeometry(rest);
        if (!regions.isOk()) {
            body.fitStatus = Status::invalidArgument(name + ": no torso found to fit garments to (" +
                                                     (found ? std::string() : found.message() + "; ") + "by geometry, " +
                                                     regions.status().message() + ")");
            return;
        }
        body.regions = std::move(regions).value();
        jointPositions.clear();
    }
    if (skinned && !jointPositions.empty()) {
        std::vector<Transform> relaxed(ch.skeleton.jointCount());
        relaxedArmsPose(ch, body.regions, body.restPositions, kRelaxedAbduction, kRaisedArm, relaxed);
        std::copy(relaxed.begin(), relaxed.end(), pose.localPose().begin());
        pose.update(ch);
        if (Status s = skinVertices(ch.body, pose.skinMatrices(), body.fitPositions, {}); !s) {
            body.fitStatus = s;
            return;
        }
    }
    auto measured = measureBody(body.fitPositions, ch.body.triangles, body.regions, jointPositions);
    if (!measured.isOk()) {
        body.fitStatus = Status::invalidArgument(name + ": cannot fit garments (regions by " + body.regions.method +
                                                 "): " + measured.status().message());
        return;
    }
    body.measurements = std::move(measured).value();
    if (skinned) body.measurements.stride = widestClipStride(ch, body.regions);
    if (!keepAnchorMesh) {
        makeAnchorMesh(body);
        if (body.anchorMesh.triangles.empty()) {
            body.fitStatus = Status::invalidArgument(name + ": no torso skin to hang garments from");
            return;
        }
    }
    body.fitStatus = Status::ok();
}

} // namespace

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
    body.mannequin.character.name = "mannequin";
    // The mannequin's torso and neck are closed parts of their own: garments hang from those.
    body.anchorMesh = body.mesh();
    body.anchorMesh.triangles.clear();
    for (const BodyPart& part : body.mannequin.parts) {
        if (part.name != "torso" && part.name != "neck") continue;
        const auto& all = body.mesh().triangles;
        body.anchorMesh.triangles.insert(body.anchorMesh.triangles.end(), all.begin() + part.firstTriangle,
                                         all.begin() + part.firstTriangle + part.triangleCount);
    }
    if (body.anchorMesh.triangles.empty()) body.anchorMesh.triangles = body.mesh().triangles;
    analyse(body, true);
    return body;
}

Result<BodyAsset> makeCharacterBody(const Character& character, const BodyDesc& desc) {
    const std::string name = character.name.empty() ? std::string("addCharacterBody") : "addCharacterBody '" + character.name + "'";
    if (!(std::isfinite(desc.height) && desc.height >= 0.0 && desc.height <= 100.0))
        return Status::invalidArgument(name + ": BodyDesc.height must be in [0, 100] m");
    if (Status s = character.validate(); !s) return Status::invalidArgument(name + ": " + s.message());
    if (character.body.vertexCount() < 3 || character.body.triangles.empty())
        return Status::invalidArgument(name + ": the character has no body mesh");
    BodyAsset body;
    body.mannequin.character = character;
    Character& ch = body.mannequin.character;
    if (desc.height > 0.0) {
        CharacterPose pose(ch);
        if (Status s = pose.evaluate(ch, -1, 0.0, ClipWrap::Clamp); !s) return Status::invalidArgument(name + ": " + s.message());
        std::vector<Vec3> rest(ch.body.vertexCount());
        if (Status s = skinVertices(ch.body, pose.skinMatrices(), rest, {}); !s) return Status::invalidArgument(name + ": " + s.message());
        double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
        for (const Vec3& p : rest) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
        if (!(hi - lo > 0.0)) return Status::invalidArgument(name + ": the character has no height to scale");
        if (Status s = changeBasis(ch, desc.height / (hi - lo), Mat3::Identity()); !s)
            return Status::invalidArgument(name + ": " + s.message());
    }
    analyse(body, false);
    if (!body.fitStatus) {
        // Not a humanoid (or not one we understand): it can still be posed, drawn and collided
        // with; garments report why they cannot be fitted.
        body.anchorMesh = body.mesh();
    }
    if (body.restSkin.empty()) {
        CharacterPose pose(ch);
        if (Status s = pose.evaluate(ch, -1, 0.0, ClipWrap::Clamp); !s) return Status::invalidArgument(name + ": " + s.message());
        body.restSkin.assign(pose.skinMatrices().begin(), pose.skinMatrices().end());
        body.restPositions.resize(ch.body.vertexCount());
        if (Status s = skinVertices(ch.body, pose.skinMatrices(), body.restPositions, {}); !s) return s;
    }
    body.mannequin.capsules = fitBodyCapsules(ch, body.restPositions, body.restSkin);
    if (body.mannequin.capsules.empty())
        return Status::invalidArgument(name + ": no joint carries enough skin for a collision capsule");
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
    analyse(body, false);
    if (!body.fitStatus) body.anchorMesh = mesh;
    return body;
}

Status applyLandmarks(BodyAsset& body, const BodyLandmarkDesc& l) {
    const Vec3 forward(l.forward[0], 0.0, l.forward[2]);
    if (!isFinite(Vec3(l.forward[0], l.forward[1], l.forward[2])) || forward.norm() < 1e-9)
        return Status::invalidArgument("BodyLandmarkDesc.forward must be a finite, non-vertical direction");
    const double heights[] = {l.neckY, l.shoulderY, l.chestY, l.waistY, l.hipY};
    const char* names[] = {"neckY", "shoulderY", "chestY", "waistY", "hipY"};
    for (int k = 0; k < 5; ++k)
        if (!std::isfinite(heights[k])) return Status::invalidArgument(std::string("BodyLandmarkDesc.") + names[k] + " must be finite");
    for (double g : {l.neckGirth, l.chestGirth, l.waistGirth, l.hipGirth, l.shoulderWidth})
        if (!(std::isfinite(g) && g >= 0.0)) return Status::invalidArgument("BodyLandmarkDesc girths and widths must be >= 0");
    if (!(l.stride >= 0.0 && l.stride < 0.5 * kPi))
        return Status::invalidArgument("BodyLandmarkDesc.stride must be in [0, pi/2) rad, got " +
                                       std::to_string(l.stride));
    if (!(l.hipY < l.waistY && l.waistY < l.chestY && l.chestY < l.shoulderY && l.chestY < l.neckY))
        return Status::invalidArgument("BodyLandmarkDesc: heights must rise hipY < waistY < chestY < shoulderY, chestY < neckY");

    BodyMeasurements m = body.measurements;
    const std::vector<Vec3>& p = body.fitPositions.empty() ? body.restPositions : body.fitPositions;
    m.groundY = std::numeric_limits<double>::max();
    m.topY = std::numeric_limits<double>::lowest();
    for (const Vec3& q : p) m.groundY = std::min(m.groundY, q.y()), m.topY = std::max(m.topY, q.y());
    m.height = m.topY - m.groundY;
    if (!(l.hipY > m.groundY && l.neckY < m.topY))
        return Status::invalidArgument("BodyLandmarkDesc: the heights must lie within the body's (" + std::to_string(m.groundY) +
                                       " to " + std::to_string(m.topY) + " m)");
    m.forward = forward.normalized();
    m.left = Vec3::UnitY().cross(m.forward);
    // Rings by the measured regions when there are some, else by every triangle (a host's body
    // without any skeleton or a shape the geometry could not read).
    const bool regions = body.regions.vertices.size() == p.size();
    const auto& tris = body.mesh().triangles;
    const std::vector<uint8_t> all(tris.size(), 1);
    const auto mask = [&](std::initializer_list<BodyRegion> wanted) {
        return regions ? trianglesOf(tris, body.regions.vertices, wanted) : all;
    };
    const auto ring = [&](const std::vector<uint8_t>& keep, double y, double girth, const char* what) -> Result<BodyRing> {
        BodyRing r = measureRing(p, tris, keep, y, m.left, m.forward);
        if (!(r.girth > 0.0)) return Status::invalidArgument(std::string("BodyLandmarkDesc.") + what + ": the body has no section there");
        if (girth > 0.0) {
            // The host's girth wins; the section's shape is scaled to it about its centre.
            const double s = girth / r.girth;
            const Vec2 c(r.centre.x(), r.centre.z());
            for (Vec2& q : r.hull) q = c + s * (q - c);
            r.girth = girth, r.halfWidth *= s, r.halfDepth *= s;
        }
        return r;
    };
    const auto torso = mask({BodyRegion::Torso});
    const auto column = mask({BodyRegion::Torso, BodyRegion::Neck, BodyRegion::Head});
    const auto trunkLegs = mask({BodyRegion::Torso, BodyRegion::LeftLeg, BodyRegion::RightLeg});
    auto neck = ring(column, l.neckY, l.neckGirth, "neckY");
    auto chest = ring(torso, l.chestY, l.chestGirth, "chestY");
    auto waist = ring(torso, l.waistY, l.waistGirth, "waistY");
    auto hips = ring(trunkLegs, l.hipY, l.hipGirth, "hipY");
    for (const auto* r : {&neck, &chest, &waist, &hips})
        if (!r->isOk()) return r->status();
    m.neck = neck.value(), m.chest = chest.value(), m.waist = waist.value(), m.hips = hips.value();
    m.shoulderY = l.shoulderY;
    if (m.crotchY >= m.hips.height || m.crotchY <= m.groundY) m.crotchY = m.hips.height - 0.05 * m.height;
    const BodyRing shoulders = measureRing(p, tris, mask({BodyRegion::Torso, BodyRegion::LeftArm, BodyRegion::RightArm}),
                                           l.shoulderY - 0.03 * m.height, m.left, m.forward);
    m.shoulderWidth = l.shoulderWidth > 0.0 ? l.shoulderWidth : 2.0 * shoulders.halfWidth;
    const Vec3 centre = m.chest.centre;
    for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;
        const Vec3 tip = Vec3(centre.x(), l.shoulderY, centre.z()) + sign * 0.5 * m.shoulderWidth * m.left;
        (side == 0 ? m.leftShoulder : m.rightShoulder) = tip;
    }
    if (l.stride > 0.0) m.stride = l.stride; // else what the clips showed, if any
    m.method = "host landmarks";
    body.measurements = m;
    if (!regions) {
        // The torso skin: everything between the hips and the neck within the chest's width.
        body.regions.vertices.assign(p.size(), BodyRegion::LeftArm);
        body.regions.anchorWeight.assign(p.size(), 0.0);
        for (const auto& t : tris) {
            double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
            Vec3 centroid = Vec3::Zero();
            for (uint32_t v : t) lo = std::min(lo, p[v].y()), hi = std::max(hi, p[v].y()), centroid += p[v] / 3.0;
            if (hi < m.hips.height || lo > l.neckY || std::abs((centroid - m.chest.centre).dot(m.left)) > 1.1 * m.chest.halfWidth)
                continue;
            for (uint32_t v : t) {
                body.regions.vertices[v] = BodyRegion::Torso;
                body.regions.anchorWeight[v] = 1.0;
            }
        }
        body.regions.left = m.left;
        body.regions.forward = m.forward;
        body.regions.method = "host landmarks";
        makeAnchorMesh(body);
        if (body.anchorMesh.triangles.empty())
            return Status::invalidArgument("BodyLandmarkDesc: no body triangles between hipY and neckY");
    }
    body.fitStatus = Status::ok();
    ++body.landmarkRevision;
    return Status::ok();
}

BodyLandmarkDesc landmarksOf(const BodyAsset& body) {
    const BodyMeasurements& m = body.measurements;
    BodyLandmarkDesc l;
    for (int k = 0; k < 3; ++k) l.forward[k] = m.forward[k];
    l.neckY = m.neck.height, l.neckGirth = m.neck.girth;
    l.shoulderY = m.shoulderY, l.shoulderWidth = m.shoulderWidth;
    l.chestY = m.chest.height, l.chestGirth = m.chest.girth;
    l.waistY = m.waist.height, l.waistGirth = m.waist.girth;
    l.hipY = m.hips.height, l.hipGirth = m.hips.girth;
    l.stride = m.stride;
    return l;
}

Result<SkinBinding> bindToBody(const BodyAsset& body, Span<const Vec3> restPositions, const SkinBindingSettings& settings) {
    if (body.hostSkinned || body.restSkin.empty()) return SkinBinding::bind(body.anchorMesh, restPositions, settings);
    return SkinBinding::bindPosed(body.anchorMesh, body.restPositions, body.restSkin, restPositions, settings);
}

Status resolveClip(const BodyAsset& body, const CharacterDesc& desc, int& outClip, double& outClipTime) {
    outClip = -1;
    outClipTime = desc.clipTime;
    if (!std::isfinite(desc.clipTime)) return Status::invalidArgument("CharacterDesc.clipTime must be finite");
    if (!(desc.clipPhase >= 0.0 && desc.clipPhase <= 1.0)) return Status::invalidArgument("CharacterDesc.clipPhase must be in [0, 1]");
    if (desc.clipIndex < -1) return Status::invalidArgument("CharacterDesc.clipIndex must be -1 or a clip index");
    const std::vector<AnimationClip>& clips = body.character().clips;
    if (body.hostSkinned) {
        if (desc.clipIndex >= 0)
            return Status::invalidArgument("CharacterDesc.clipIndex: a host-skinned body has no clips (the host poses it)");
        return Status::ok();
    }
    const auto list = [&] {
        if (clips.empty()) return std::string("the body has no clips");
        std::string names = "the body's clips: ";
        for (std::size_t c = 0; c < clips.size(); ++c) names += (c ? ", " : "") + ("'" + clips[c].name + "'");
        return names;
    };
    if (desc.clipIndex >= 0) {
        if (std::size_t(desc.clipIndex) >= clips.size())
            return Status::invalidArgument("CharacterDesc.clipIndex " + std::to_string(desc.clipIndex) + " is out of range; " + list());
        outClip = desc.clipIndex;
    } else if (desc.clip && desc.clip[0] != '\0') {
        outClip = body.character().findClip(desc.clip);
        if (outClip < 0) {
            const std::string wanted = lower(desc.clip);
            for (std::size_t c = 0; c < clips.size() && outClip < 0; ++c)
                if (lower(clips[c].name) == wanted) outClip = int(c);
        }
        if (outClip < 0) return Status::invalidArgument(std::string("CharacterDesc.clip: no clip named '") + desc.clip + "'; " + list());
    }
    if (outClip >= 0) outClipTime += desc.clipPhase * clips[std::size_t(outClip)].duration;
    return Status::ok();
}

} // namespace cc::detail
