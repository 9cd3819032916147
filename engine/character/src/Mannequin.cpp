#include "crowdcloth/character/Mannequin.h"

#include "TopWeights.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace cc {
namespace {

using J = MannequinJoint;

int32_t idx(J j) { return static_cast<int32_t>(j); }

Status checkRange(const char* field, double v, double lo, double hi) {
    if (!std::isfinite(v) || v < lo || v > hi) {
        return Status::invalidArgument(std::string("MannequinParams.") + field + " = " + std::to_string(v) +
                                       " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return Status::ok();
}

double smoothstep01(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

// Weight of the downstream joint across a boundary plane through q with normal d (pointing
// downstream): 0 at distance -band, 1 at +band, smooth in between. Parts on both sides of a joint
// use the same function, so overlapping parts deform alike there.
double downstreamWeight(const Vec3& p, const Vec3& q, const Vec3& d, double band) {
    return smoothstep01(((p - q).dot(d) / band + 1.0) * 0.5);
}

// Cross-section ring of a part: centre, two in-plane axes and their radii.
struct Ring {
    Vec3 centre;
    double ru, rw;
};

// Body-part surface builder. A part is a lat-long closed surface: a pole, rings, a pole. The
// rings come from an axis A->B with a radius profile, plus elliptical caps of lengths capA/capB
// beyond the ends (sphere topology, hence watertight and 2-manifold by construction).
struct PartSpec {
    std::string name;
    int32_t joint;
    Vec3 a, b;              // axis end points (bind space)
    Vec3 u;                 // first cross-section axis (made orthogonal to the axis)
    double capA, capB;      // [m] cap lengths
    int segments;           // vertices per ring (multiple of 4)
    int bodyRings;          // rings between A and B (>= 1 means A and B rings both present)
    int capRings;           // rings per cap (excluding the end ring)
    // Profile over s in [0, 1]: radii along u and w and an offset of the centre along w.
    std::function<void(double s, double& ru, double& rw, double& offsetW)> profile;
    // Skin weights of a bind-space point: up to four (joint, weight) pairs.
    std::function<void(const Vec3& p, std::array<uint16_t, 4>& joints, std::array<double, 4>& weights)> weights;
};

class BodyBuilder {
public:
    explicit BodyBuilder(SkinnedMesh& mesh) : mMesh(mesh) {}

    BodyPart add(const PartSpec& spec) {
        BodyPart part;
        part.name = spec.name;
        part.joint = spec.joint;
        part.firstVertex = static_cast<uint32_t>(mMesh.bindPositions.size());
        part.firstTriangle = static_cast<uint32_t>(mMesh.triangles.size());

        Vec3 d = spec.b - spec.a;
        const double length = d.norm();
        d = length > 0.0 ? Vec3(d / length) : Vec3::UnitY();
        const Vec3 u = (spec.u - spec.u.dot(d) * d).normalized();
        const Vec3 w = d.cross(u);

        std::vector<Ring> rings;
        double ru0, rw0, o0, ru1, rw1, o1;
        spec.profile(0.0, ru0, rw0, o0);
        spec.profile(1.0, ru1, rw1, o1);
        for (int j = 1; j < spec.capRings + 1; ++j) { // cap at A, from the pole outwards
            const double phi = 0.5 * kPi * j / (spec.capRings + 1);
            rings.push_back({spec.a + o0 * w - spec.capA * std::cos(phi) * d, ru0 * std::sin(phi), rw0 * std::sin(phi)});
        }
        for (int i = 0; i <= spec.bodyRings; ++i) {
            const double s = spec.bodyRings > 0 ? static_cast<double>(i) / spec.bodyRings : 0.0;
            double ru, rw, o;
            spec.profile(s, ru, rw, o);
            rings.push_back({spec.a + s * length * d + o * w, ru, rw});
        }
        for (int j = spec.capRings; j >= 1; --j) { // cap at B, towards the pole
            const double phi = 0.5 * kPi * j / (spec.capRings + 1);
            rings.push_back({spec.b + o1 * w + spec.capB * std::cos(phi) * d, ru1 * std::sin(phi), rw1 * std::sin(phi)});
        }

        const uint32_t base = part.firstVertex;
        const int n = spec.segments;
        addVertex(spec, spec.a + o0 * w - spec.capA * d); // pole A
        for (const Ring& r : rings) {
            for (int k = 0; k < n; ++k) {
                const double th = 2.0 * kPi * k / n;
                addVertex(spec, r.centre + r.ru * std::cos(th) * u + r.rw * std::sin(th) * w);
            }
        }
        addVertex(spec, spec.b + o1 * w + spec.capB * d); // pole B
        const uint32_t poleB = static_cast<uint32_t>(mMesh.bindPositions.size() - 1);
        const auto ringVertex = [&](std::size_t ring, int k) {
            return base + 1 + static_cast<uint32_t>(ring * n + static_cast<std::size_t>((k + n) % n));
        };
        // Windings are consistent within the part; buildMannequin settles which side is out by
        // the part's signed volume.
        for (int k = 0; k < n; ++k) add(base, ringVertex(0, k + 1), ringVertex(0, k));
        for (std::size_t r = 0; r + 1 < rings.size(); ++r) {
            for (int k = 0; k < n; ++k) {
                add(ringVertex(r, k), ringVertex(r, k + 1), ringVertex(r + 1, k + 1));
                add(ringVertex(r, k), ringVertex(r + 1, k + 1), ringVertex(r + 1, k));
            }
        }
        for (int k = 0; k < n; ++k) add(poleB, ringVertex(rings.size() - 1, k), ringVertex(rings.size() - 1, k + 1));

        part.vertexCount = static_cast<uint32_t>(mMesh.bindPositions.size()) - part.firstVertex;
        part.triangleCount = static_cast<uint32_t>(mMesh.triangles.size()) - part.firstTriangle;
        return part;
    }

private:
    void addVertex(const PartSpec& spec, const Vec3& p) {
        std::array<uint16_t, 4> joints{};
        std::array<double, 4> weights{};
        spec.weights(p, joints, weights);
        mMesh.bindPositions.push_back(p);
        mMesh.jointIndices.push_back(joints);
        mMesh.jointWeights.push_back(weights);
    }
    void add(uint32_t a, uint32_t b, uint32_t c) { mMesh.triangles.push_back({a, b, c}); }

    SkinnedMesh& mMesh;
};

using WeightSet = detail::TopWeights;

// Piecewise-linear interpolation in a table of (key, values...) rows sorted by key.
template <std::size_t N>
std::array<double, N> tableLookup(const std::vector<std::pair<double, std::array<double, N>>>& table, double key) {
    if (key <= table.front().first) return table.front().second;
    if (key >= table.back().first) return table.back().second;
    for (std::size_t i = 0; i + 1 < table.size(); ++i) {
        if (key <= table[i + 1].first) {
            const double f = (key - table[i].first) / (table[i + 1].first - table[i].first);
            std::array<double, N> r{};
            for (std::size_t k = 0; k < N; ++k) r[k] = table[i].second[k] + f * (table[i + 1].second[k] - table[i].second[k]);
            return r;
        }
    }
    return table.back().second;
}

Quat eulerYZX(double yaw, double roll, double pitch) {
    return (Eigen::AngleAxisd(yaw, Vec3::UnitY()) * Eigen::AngleAxisd(roll, Vec3::UnitZ()) *
            Eigen::AngleAxisd(pitch, Vec3::UnitX())).normalized();
}

// Joint angles of one procedural gait, as functions of the cycle angle phi (radians).
struct GaitShape {
    double hipSwing;      // [rad] thigh flexion amplitude
    double kneeStance;    // [rad] knee flexion during stance
    double kneeSwing;     // [rad] extra knee flexion at mid-swing
    double ankle;         // [rad] ankle amplitude
    double armSwing;      // [rad] upper-arm swing amplitude
    double elbowBase;     // [rad] mean elbow flexion
    double elbowSwing;    // [rad] elbow flexion amplitude
    double bob;           // [m] pelvis vertical bob amplitude (twice per cycle)
    double pelvisYaw;     // [rad]
    double lean;          // [rad] forward lean of the spine
};

} // namespace

Status MannequinParams::validate() const {
    Status s = checkRange("height", height, 1.0, 2.5);
    if (s) s = checkRange("shoulderWidth", shoulderWidth, 0.25, 0.6);
    if (s) s = checkRange("hipWidth", hipWidth, 0.22, 0.55);
    if (s) s = checkRange("waistWidth", waistWidth, 0.18, std::min(0.5, hipWidth + 0.1));
    if (s) s = checkRange("limbGirth", limbGirth, 0.6, 1.6);
    if (s) s = checkRange("torsoDepth", torsoDepth, 0.7, 1.5);
    if (s) s = checkRange("headSize", headSize, 0.8, 1.2);
    if (s) s = checkRange("armAbduction", armAbduction, 0.15, 0.8);
    if (s) s = checkRange("walkSpeed", walkSpeed, 0.5, 2.5);
    if (s) s = checkRange("runSpeed", runSpeed, 2.0, 7.0);
    if (s && (!std::isfinite(phase) || phase < 0.0 || phase >= 1.0)) {
        s = Status::invalidArgument("MannequinParams.phase = " + std::to_string(phase) + " outside [0, 1)");
    }
    return s;
}

double mannequinIdlePeriod(const MannequinParams&) { return 4.0; }
double mannequinWalkPeriod(const MannequinParams& p) { return 1.1 * std::sqrt(p.height / 1.8); }
double mannequinRunPeriod(const MannequinParams& p) { return 0.7 * std::sqrt(p.height / 1.8); }

Result<Mannequin> buildMannequin(const MannequinParams& p) {
    Status status = p.validate();
    if (!status) return status;

    const double H = p.height;
    const double k = H / 1.8;        // length scale
    const double g = p.limbGirth * k;
    const double depth = p.torsoDepth * k;

    // --- Skeleton (bind pose = rest pose; all joint rotations identity) -------------------------
    std::vector<Vec3> pos(static_cast<std::size_t>(J::Count));
    const auto at = [&](J j) -> Vec3& { return pos[static_cast<std::size_t>(j)]; };
    const double upperArmRadius = 0.050 * g;
    const double shoulderX = 0.5 * p.shoulderWidth - upperArmRadius;
    const Vec3 armDir(std::sin(p.armAbduction), -std::cos(p.armAbduction), 0.0); // left arm
    const double thighX = 0.27 * p.hipWidth;
    at(J::Hips) = {0, 0.53 * H, 0};
    at(J::Spine) = {0, 0.61 * H, 0};
    at(J::Chest) = {0, 0.70 * H, 0};
    at(J::Neck) = {0, 0.82 * H, 0};
    at(J::Head) = {0, 0.875 * H, 0};
    for (int side = 0; side < 2; ++side) {
        const double sx = side == 0 ? 1.0 : -1.0;
        const Vec3 dir(sx * armDir.x(), armDir.y(), 0.0);
        const std::size_t o = side == 0 ? 0 : 4;
        pos[static_cast<std::size_t>(idx(J::LeftShoulder)) + o] = {sx * 0.03 * k, 0.80 * H, 0};
        const Vec3 shoulder(sx * shoulderX, 0.805 * H, 0);
        pos[static_cast<std::size_t>(idx(J::LeftUpperArm)) + o] = shoulder;
        pos[static_cast<std::size_t>(idx(J::LeftForearm)) + o] = shoulder + 0.17 * H * dir;
        pos[static_cast<std::size_t>(idx(J::LeftHand)) + o] = shoulder + 0.315 * H * dir;
        const std::size_t l = side == 0 ? 0 : 3;
        pos[static_cast<std::size_t>(idx(J::LeftThigh)) + l] = {sx * thighX, 0.515 * H, 0};
        pos[static_cast<std::size_t>(idx(J::LeftShin)) + l] = {sx * thighX, 0.285 * H, 0};
        pos[static_cast<std::size_t>(idx(J::LeftFoot)) + l] = {sx * thighX, 0.048 * H, 0};
    }
    static const char* kNames[] = {"hips", "spine", "chest", "neck", "head",
                                   "shoulder_l", "upper_arm_l", "forearm_l", "hand_l",
                                   "shoulder_r", "upper_arm_r", "forearm_r", "hand_r",
                                   "thigh_l", "shin_l", "foot_l", "thigh_r", "shin_r", "foot_r"};
    static const J kParents[] = {J::Count, J::Hips, J::Spine, J::Chest, J::Neck,
                                 J::Chest, J::LeftShoulder, J::LeftUpperArm, J::LeftForearm,
                                 J::Chest, J::RightShoulder, J::RightUpperArm, J::RightForearm,
                                 J::Hips, J::LeftThigh, J::LeftShin, J::Hips, J::RightThigh, J::RightShin};
    Mannequin man;
    Character& ch = man.character;
    ch.name = "mannequin";
    const std::size_t jointCount = static_cast<std::size_t>(J::Count);
    for (std::size_t j = 0; j < jointCount; ++j) {
        Joint joint;
        joint.name = kNames[j];
        joint.parent = kParents[j] == J::Count ? -1 : idx(kParents[j]);
        joint.restLocal.translation = joint.parent < 0 ? pos[j] : Vec3(pos[j] - pos[static_cast<std::size_t>(joint.parent)]);
        ch.skeleton.joints.push_back(joint);
        Mat4 inv = Mat4::Identity();
        inv.topRightCorner<3, 1>() = -pos[j];
        ch.body.inverseBindMatrices.push_back(inv);
    }

    // --- Body surface ---------------------------------------------------------------------------
    BodyBuilder builder(ch.body);
    const double hw = 0.5 * p.hipWidth, ww = 0.5 * p.waistWidth, sw = p.shoulderWidth;
    // Torso cross-sections by height: (y/H) -> half-width, half-depth, forward offset of centre.
    const std::vector<std::pair<double, std::array<double, 3>>> torso = {
        {0.47, {0.80 * hw, 0.090 * depth, -0.005 * k}},
        {0.50, {hw, 0.105 * depth, -0.012 * k}},
        {0.54, {0.96 * hw, 0.100 * depth, -0.008 * k}},
        {0.61, {ww, 0.090 * depth, 0.0}},
        {0.68, {0.5 * (ww + 0.43 * sw), 0.105 * depth, 0.010 * k}},
        {0.73, {0.43 * sw, 0.112 * depth, 0.015 * k}},
        {0.78, {0.45 * sw, 0.095 * depth, 0.005 * k}},
        {0.81, {0.36 * sw, 0.070 * depth, 0.0}},
    };
    const double torsoBottom = 0.47 * H, torsoTop = 0.81 * H;
    const std::array<J, 4> spineJoints = {J::Hips, J::Spine, J::Chest, J::Neck};
    const auto torsoWeights = [&](const Vec3& q, std::array<uint16_t, 4>& outJ, std::array<double, 4>& outW) {
        // Hat functions over the spine joints' heights (a partition of unity along Y).
        WeightSet ws;
        const double y = q.y();
        if (y <= at(J::Hips).y()) {
            ws.add(idx(J::Hips), 1.0);
        } else if (y >= at(J::Neck).y()) {
            ws.add(idx(J::Neck), 1.0);
        } else {
            for (std::size_t i = 0; i + 1 < spineJoints.size(); ++i) {
                const double y0 = at(spineJoints[i]).y(), y1 = at(spineJoints[i + 1]).y();
                if (y >= y0 && y <= y1) {
                    const double f = (y - y0) / (y1 - y0);
                    ws.add(idx(spineJoints[i]), 1.0 - f);
                    ws.add(idx(spineJoints[i + 1]), f);
                    break;
                }
            }
        }
        ws.write(outJ, outW);
    };
    man.parts.push_back(builder.add(PartSpec{
        "torso", idx(J::Chest), {0, torsoBottom, 0}, {0, torsoTop, 0}, Vec3::UnitX(), 0.025 * k, 0.025 * k, 24, 16, 3,
        [&](double s, double& ru, double& rw, double& o) {
            const auto r = tableLookup(torso, 0.47 + s * (0.81 - 0.47));
            ru = r[0];
            rw = r[1];
            o = -r[2]; // w = d x u = Y x X = -Z: negate so positive offsets point forward (+Z)
        },
        torsoWeights}));

    // A chain part: joint `self` from A to B, blending into `parent` across A and into `child`
    // across B within `band`.
    const auto chainWeights = [&](J parent, J self, J child, const Vec3& a, const Vec3& b, double bandA, double bandB) {
        return [=](const Vec3& q, std::array<uint16_t, 4>& outJ, std::array<double, 4>& outW) {
            const Vec3 d = (b - a).normalized();
            const double wChild = child == J::Count ? 0.0 : downstreamWeight(q, b, d, bandB);
            const double wParent = parent == J::Count ? 0.0 : 1.0 - downstreamWeight(q, a, d, bandA);
            WeightSet ws;
            ws.add(idx(self), std::max(0.0, 1.0 - wChild - wParent));
            if (child != J::Count) ws.add(idx(child), wChild);
            if (parent != J::Count) ws.add(idx(parent), wParent);
            if (ws.count() == 0) ws.add(idx(self), 1.0);
            ws.write(outJ, outW);
        };
    };
    const auto taper = [](double r0, double rMid, double r1) {
        return [=](double s, double& ru, double& rw, double& o) {
            const double r = s < 0.4 ? r0 + (rMid - r0) * (s / 0.4) : rMid + (r1 - rMid) * ((s - 0.4) / 0.6);
            ru = r;
            rw = r;
            o = 0.0;
        };
    };

    // Neck and head.
    const Vec3 neckA(0, 0.80 * H, 0), neckB(0, 0.885 * H, 0);
    const double neckRadius = 0.058 * k;
    man.parts.push_back(builder.add(PartSpec{
        "neck", idx(J::Neck), neckA, neckB, Vec3::UnitX(), 0.02 * k, 0.02 * k, 12, 3, 2, taper(neckRadius, neckRadius, 0.9 * neckRadius),
        chainWeights(J::Chest, J::Neck, J::Head, at(J::Neck), at(J::Head), 0.02 * k, 0.02 * k)}));
    const double headRy = 0.118 * k * p.headSize;
    const Vec3 headCentre(0, H - headRy, 0.01 * k);
    man.parts.push_back(builder.add(PartSpec{
        "head", idx(J::Head), headCentre, headCentre, Vec3::UnitX(), headRy, headRy, 16, 0, 5,
        [&](double, double& ru, double& rw, double& o) {
            ru = 0.078 * k * p.headSize;
            rw = -0.098 * k * p.headSize; // w = -Z here; the sign only mirrors the ring
            o = 0.0;
        },
        [&](const Vec3&, std::array<uint16_t, 4>& outJ, std::array<double, 4>& outW) {
            outJ = {static_cast<uint16_t>(idx(J::Head)), 0, 0, 0};
            outW = {1.0, 0.0, 0.0, 0.0};
        }}));

    for (int side = 0; side < 2; ++side) {
        const bool left = side == 0;
        const double sx = left ? 1.0 : -1.0;
        const std::string sfx = left ? "_l" : "_r";
        const J shoulder = left ? J::LeftShoulder : J::RightShoulder;
        const J upper = left ? J::LeftUpperArm : J::RightUpperArm;
        const J fore = left ? J::LeftForearm : J::RightForearm;
        const J hand = left ? J::LeftHand : J::RightHand;
        const J thigh = left ? J::LeftThigh : J::RightThigh;
        const J shin = left ? J::LeftShin : J::RightShin;
        const J foot = left ? J::LeftFoot : J::RightFoot;
        const Vec3 dir(sx * armDir.x(), armDir.y(), 0.0);

        man.parts.push_back(builder.add(PartSpec{
            "upper_arm" + sfx, idx(upper), at(upper), at(fore), Vec3::UnitZ(), upperArmRadius, 0.01 * k, 12, 8, 3,
            taper(upperArmRadius, 0.047 * g, 0.040 * g),
            chainWeights(shoulder, upper, fore, at(upper), at(fore), 0.03 * k, 0.04 * k)}));
        man.parts.push_back(builder.add(PartSpec{
            "forearm" + sfx, idx(fore), at(fore), at(hand), Vec3::UnitZ(), 0.02 * k, 0.01 * k, 12, 7, 2,
            taper(0.040 * g, 0.040 * g, 0.028 * g),
            chainWeights(upper, fore, hand, at(fore), at(hand), 0.04 * k, 0.02 * k)}));
        const Vec3 handEnd = at(hand) + 0.10 * H * dir;
        man.parts.push_back(builder.add(PartSpec{
            "hand" + sfx, idx(hand), at(hand), handEnd, Vec3::UnitZ(), 0.01 * k, 0.02 * k, 10, 4, 2,
            [=](double s, double& ru, double& rw, double& o) {
                ru = (0.036 + 0.012 * std::sin(kPi * std::min(1.0, s * 1.3))) * g; // palm width
                rw = 0.017 * g;                                                      // thickness
                o = 0.0;
            },
            chainWeights(fore, hand, J::Count, at(hand), handEnd, 0.02 * k, 0.0)}));

        man.parts.push_back(builder.add(PartSpec{
            "thigh" + sfx, idx(thigh), at(thigh), at(shin), Vec3::UnitX(), 0.05 * k, 0.01 * k, 14, 10, 3,
            taper(0.082 * g, 0.072 * g, 0.052 * g),
            chainWeights(J::Hips, thigh, shin, at(thigh), at(shin), 0.03 * k, 0.05 * k)}));
        man.parts.push_back(builder.add(PartSpec{
            "shin" + sfx, idx(shin), at(shin), at(foot), Vec3::UnitX(), 0.01 * k, 0.035 * k, 14, 9, 3,
            taper(0.050 * g, 0.054 * g, 0.032 * g),
            chainWeights(thigh, shin, foot, at(shin), at(foot), 0.05 * k, 0.03 * k)}));
        // Foot: axis from heel to toe along +Z; its sole lies on y = 0.
        const double footRv = 0.036 * k;
        const Vec3 heel(at(foot).x(), footRv, -0.03 * k), toe(at(foot).x(), footRv, 0.17 * k);
        man.parts.push_back(builder.add(PartSpec{
            "foot" + sfx, idx(foot), heel, toe, Vec3::UnitX(), 0.03 * k, 0.035 * k, 12, 6, 3,
            [=](double s, double& ru, double& rw, double& o) {
                ru = (0.034 + 0.012 * s) * g;                 // widens towards the toes
                rw = footRv * (1.0 - 0.35 * s * s);           // thinner at the toes
                o = footRv - rw;                              // w = Z x X = +Y: keep the sole flat
            },
            [=](const Vec3&, std::array<uint16_t, 4>& outJ, std::array<double, 4>& outW) {
                outJ = {static_cast<uint16_t>(idx(foot)), 0, 0, 0};
                outW = {1.0, 0.0, 0.0, 0.0};
            }}));
    }

    // Every part must face outwards: flip a part whose signed volume comes out negative (the
    // ring direction depends on the handedness of the part's axes).
    for (const BodyPart& part : man.parts) {
        double volume = 0.0;
        for (uint32_t t = part.firstTriangle; t < part.firstTriangle + part.triangleCount; ++t) {
            const auto& tri = ch.body.triangles[t];
            volume += ch.body.bindPositions[tri[0]].dot(ch.body.bindPositions[tri[1]].cross(ch.body.bindPositions[tri[2]]));
        }
        if (volume < 0.0) {
            for (uint32_t t = part.firstTriangle; t < part.firstTriangle + part.triangleCount; ++t) {
                std::swap(ch.body.triangles[t][1], ch.body.triangles[t][2]);
            }
        }
    }
    ch.body.computeBindNormals();

    // --- Capsules: limb axes with the median vertex distance as radius; three across the torso --
    for (const BodyPart& part : man.parts) {
        if (part.name == "torso") continue;
        const int32_t j = part.joint;
        // The part's extent along its axis: the two poles are its first and last vertices.
        const Vec3 poleA = ch.body.bindPositions[part.firstVertex];
        const Vec3 poleB = ch.body.bindPositions[part.firstVertex + part.vertexCount - 1];
        std::vector<double> dist;
        const Vec3 axis = (poleB - poleA).normalized();
        // Radius: median distance of the part's vertices from its axis; the segment is then
        // shortened so the capsule's caps reach the poles.
        const Vec3 mid = 0.5 * (poleA + poleB);
        for (uint32_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v) {
            const Vec3& q = ch.body.bindPositions[v];
            const Vec3 rel = q - mid;
            dist.push_back((rel - rel.dot(axis) * axis).norm());
        }
        std::nth_element(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(dist.size() / 2), dist.end());
        const double radius = dist[dist.size() / 2];
        const double half = std::max(0.0, 0.5 * (poleB - poleA).norm() - radius);
        man.capsules.push_back({j, mid - half * axis, mid + half * axis, radius});
    }
    for (const auto& [yFrac, joint] : std::vector<std::pair<double, J>>{{0.50, J::Hips}, {0.61, J::Spine}, {0.73, J::Chest}}) {
        const auto r = tableLookup(torso, yFrac);
        const double radius = r[1];
        const double half = std::max(0.0, r[0] - radius);
        const Vec3 c(0, yFrac * H, r[2]);
        man.capsules.push_back({idx(joint), c - half * Vec3::UnitX(), c + half * Vec3::UnitX(), radius});
    }

    // --- Landmarks --------------------------------------------------------------------------------
    BodyLandmarks& lm = man.landmarks;
    const auto waist = tableLookup(torso, 0.61);
    lm.waistJoint = idx(J::Spine);
    lm.waistCentre = {0, 0.61 * H, waist[2]};
    lm.waistRadiusX = waist[0];
    lm.waistRadiusZ = waist[1];
    const auto hip = tableLookup(torso, 0.50);
    lm.hipJoint = idx(J::Hips);
    lm.hipCentre = {0, 0.50 * H, hip[2]};
    lm.hipRadiusX = hip[0];
    lm.hipRadiusZ = hip[1];
    lm.neckJoint = idx(J::Neck);
    lm.neckBase = at(J::Neck);
    lm.neckRadius = neckRadius;
    for (int side = 0; side < 2; ++side) {
        const double sx = side == 0 ? shoulderX : -shoulderX;
        Vec3 best(sx, -1.0, 0.0);
        for (std::size_t v = 0; v < ch.body.vertexCount(); ++v) {
            const Vec3& q = ch.body.bindPositions[v];
            if (std::abs(q.x() - sx) < 0.03 * k && std::abs(q.z()) < 0.05 * k && q.y() < 0.86 * H && q.y() > best.y()) best = q;
        }
        (side == 0 ? lm.leftShoulder : lm.rightShoulder) = best;
    }

    // --- Clips ------------------------------------------------------------------------------------
    const auto makeClip = [&](const std::string& name, double period, double speed, int samples,
                              const std::function<void(double phi, std::vector<Transform>& local)>& pose) {
        AnimationClip clip;
        clip.name = name;
        clip.duration = period;
        clip.rootVelocity = {0, 0, speed};
        std::vector<std::vector<Transform>> keys;
        for (int i = 0; i < samples; ++i) {
            std::vector<Transform> local(jointCount);
            ch.skeleton.restPose(local);
            pose(2.0 * kPi * (static_cast<double>(i) / samples + p.phase), local);
            keys.push_back(std::move(local));
        }
        keys.push_back(keys.front()); // the last key repeats the first: seamless loop
        for (std::size_t j = 0; j < jointCount; ++j) {
            JointChannel c;
            c.joint = static_cast<int32_t>(j);
            for (int i = 0; i <= samples; ++i) {
                const double t = period * i / samples;
                c.rotationTimes.push_back(t);
                c.rotations.push_back(keys[static_cast<std::size_t>(i)][j].rotation);
                if (j == static_cast<std::size_t>(idx(J::Hips))) {
                    c.translationTimes.push_back(t);
                    c.translations.push_back(keys[static_cast<std::size_t>(i)][j].translation);
                }
            }
            clip.channels.push_back(std::move(c));
        }
        ch.clips.push_back(std::move(clip));
    };
    const auto rot = [&](std::vector<Transform>& local, J j, double yaw, double roll, double pitch) {
        local[static_cast<std::size_t>(j)].rotation = eulerYZX(yaw, roll, pitch);
    };
    const auto gait = [&](const GaitShape& s) {
        return [=, &rot](double phi, std::vector<Transform>& local) {
            local[static_cast<std::size_t>(idx(J::Hips))].translation.y() += s.bob * std::cos(2.0 * phi);
            rot(local, J::Hips, s.pelvisYaw * std::sin(phi), 0.0, 0.0);
            rot(local, J::Spine, -0.5 * s.pelvisYaw * std::sin(phi), 0.0, s.lean);
            rot(local, J::Chest, -0.5 * s.pelvisYaw * std::sin(phi), 0.0, 0.0);
            rot(local, J::Neck, 0.0, 0.0, -0.5 * s.lean);
            rot(local, J::Head, 0.0, 0.0, -0.5 * s.lean);
            for (int side = 0; side < 2; ++side) {
                const double ph = phi + (side == 0 ? 0.0 : kPi);
                const bool left = side == 0;
                // Thigh flexion h > 0 swings the leg forward (a downward limb turns by -h about X).
                const double h = s.hipSwing * std::sin(ph);
                // The knee bends most in mid-swing, while the thigh moves forward (cos > 0).
                const double swing = std::max(0.0, std::cos(ph - 0.35));
                const double knee = s.kneeStance + s.kneeSwing * swing * swing;
                const double ankle = s.ankle * std::sin(ph - 0.6);
                rot(local, left ? J::LeftThigh : J::RightThigh, 0.0, 0.0, -h);
                rot(local, left ? J::LeftShin : J::RightShin, 0.0, 0.0, knee);
                rot(local, left ? J::LeftFoot : J::RightFoot, 0.0, 0.0, -ankle);
                // Arms swing against the leg of the same side.
                rot(local, left ? J::LeftUpperArm : J::RightUpperArm, 0.0, 0.0, s.armSwing * std::sin(ph));
                rot(local, left ? J::LeftForearm : J::RightForearm, 0.0, 0.0,
                    -(s.elbowBase + s.elbowSwing * std::sin(ph + kPi)));
            }
        };
    };
    const double idleT = mannequinIdlePeriod(p);
    makeClip("idle", idleT, 0.0, 40, [&](double phi, std::vector<Transform>& local) {
        local[static_cast<std::size_t>(idx(J::Hips))].translation.x() += 0.01 * k * std::sin(phi);
        rot(local, J::Chest, 0.0, 0.0, 0.02 * std::sin(2.0 * phi));
        rot(local, J::Head, 0.06 * std::sin(phi), 0.0, 0.02 * std::sin(2.0 * phi));
        rot(local, J::LeftUpperArm, 0.0, 0.0, 0.03 * std::sin(phi));
        rot(local, J::RightUpperArm, 0.0, 0.0, -0.03 * std::sin(phi));
        rot(local, J::LeftForearm, 0.0, 0.0, -0.15);
        rot(local, J::RightForearm, 0.0, 0.0, -0.15);
    });
    const double legLength = at(J::Hips).y();
    const double walkT = mannequinWalkPeriod(p);
    const double runT = mannequinRunPeriod(p);
    // Thigh amplitude so that the stance foot moves backwards at about the locomotion speed
    // (leg length * amplitude * angular frequency = speed): the feet roughly stay planted.
    const double walkHip = p.walkSpeed * walkT / (2.0 * kPi * legLength);
    const double runHip = p.runSpeed * runT / (2.0 * kPi * legLength);
    makeClip("walk", walkT, p.walkSpeed, 48,
             gait(GaitShape{walkHip, 0.08, 0.6, 0.2, 0.35, 0.25, 0.12, 0.015 * k, 0.08, 0.03}));
    makeClip("run", runT, p.runSpeed, 48,
             gait(GaitShape{runHip, 0.25, 1.3, 0.35, 0.85, 1.35, 0.3, 0.035 * k, 0.15, 0.18}));

    status = ch.validate();
    if (!status) return Status::invalidArgument("buildMannequin: " + status.message());
    return man;
}

} // namespace cc
