#include "crowdcloth/character/BodyRegions.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace cc {
namespace {

/// What a joint name says the joint is. Ordered from the most to the least specific, so a name
/// with several keywords ("LeftHandIndex1": hand and finger) takes the distal one.
enum class Kind : uint8_t { Unknown, Finger, Hand, Forearm, Clavicle, UpperArm, Toe, Foot, Shin, Thigh, Leg, Head, Neck, Hips, Spine };

struct Keyword {
    const char* word;
    Kind kind;
};

// Whole tokens (or two adjacent tokens run together: "upper" "arm" -> "upperarm"), never
// substrings: "Armature" is no arm. Conventions covered: Mixamo (LeftUpLeg, LeftLeg, LeftArm,
// LeftForeArm, LeftShoulder, Spine1), Unreal (pelvis, spine_01, clavicle_l, upperarm_l,
// lowerarm_l, thigh_l, calf_l, ball_l), Unity/VRM humanoid (hips, upperChest, leftUpperArm,
// leftLowerLeg, leftToes), Blender Rigify/metarig (spine.001, shoulder.L, upper_arm.L, forearm.L,
// thigh.L, shin.L), 3ds Max Biped (Bip01 L Clavicle, Bip01 L Calf, Bip01 Pelvis), and exporters
// that name joints after parts (arm_joint_L_1, leg_joint_R_2, torso_joint_3).
const Keyword kKeywords[] = {
    {"thumb", Kind::Finger},     {"index", Kind::Finger},     {"middle", Kind::Finger},  {"ring", Kind::Finger},
    {"pinky", Kind::Finger},     {"pinkie", Kind::Finger},    {"little", Kind::Finger},  {"finger", Kind::Finger},
    {"digit", Kind::Finger},     {"hand", Kind::Hand},        {"wrist", Kind::Hand},     {"palm", Kind::Hand},
    {"forearm", Kind::Forearm},  {"lowerarm", Kind::Forearm}, {"lowarm", Kind::Forearm}, {"elbow", Kind::Forearm},
    {"clavicle", Kind::Clavicle}, {"clav", Kind::Clavicle},   {"collar", Kind::Clavicle}, {"collarbone", Kind::Clavicle},
    {"shoulder", Kind::Clavicle}, {"scapula", Kind::Clavicle}, {"upperarm", Kind::UpperArm}, {"uparm", Kind::UpperArm},
    {"humerus", Kind::UpperArm}, {"arm", Kind::UpperArm},     {"toe", Kind::Toe},        {"toes", Kind::Toe},
    {"toebase", Kind::Toe},      {"ball", Kind::Toe},         {"foot", Kind::Foot},      {"ankle", Kind::Foot},
    {"heel", Kind::Foot},        {"calf", Kind::Shin},        {"shin", Kind::Shin},      {"knee", Kind::Shin},
    {"lowerleg", Kind::Shin},    {"lowleg", Kind::Shin},      {"tibia", Kind::Shin},     {"thigh", Kind::Thigh},
    {"upleg", Kind::Thigh},      {"upperleg", Kind::Thigh},   {"femur", Kind::Thigh},    {"leg", Kind::Leg},
    {"head", Kind::Head},        {"skull", Kind::Head},       {"jaw", Kind::Head},       {"eye", Kind::Head},
    {"face", Kind::Head},        {"hair", Kind::Head},        {"nose", Kind::Head},      {"neck", Kind::Neck},
    {"hips", Kind::Hips},        {"pelvis", Kind::Hips},      {"spine", Kind::Spine},    {"chest", Kind::Spine},
    {"upperchest", Kind::Spine}, {"torso", Kind::Spine},      {"abdomen", Kind::Spine},  {"belly", Kind::Spine},
    {"stomach", Kind::Spine},    {"waist", Kind::Spine},      {"breast", Kind::Spine},   {"ribs", Kind::Spine},
};

/// "mixamorig:LeftUpLeg" -> mixamorig, left, up, leg; "Bip01 L Thigh" -> bip, 01, l, thigh;
/// "upper_arm.L" -> upper, arm, l; "UpperArmL" -> upper, arm, l.
std::vector<std::string> tokenize(const std::string& name) {
    std::vector<std::string> tokens;
    std::string current;
    auto flush = [&] {
        if (!current.empty()) tokens.push_back(current);
        current.clear();
    };
    for (std::size_t i = 0; i < name.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(name[i]);
        if (!std::isalnum(c)) {
            flush();
            continue;
        }
        if (!current.empty()) {
            const unsigned char prev = static_cast<unsigned char>(name[i - 1]);
            const bool caseBreak = std::islower(prev) && std::isupper(c);
            const bool digitBreak = std::isdigit(prev) != std::isdigit(c);
            // "ABCDef" -> "ABC" "Def": an upper-case run ends before its last capital.
            const bool acronymBreak = i + 1 < name.size() && std::isupper(prev) && std::isupper(c) &&
                                      std::islower(static_cast<unsigned char>(name[i + 1]));
            if (caseBreak || digitBreak || acronymBreak) flush();
        }
        current.push_back(static_cast<char>(std::tolower(c)));
    }
    flush();
    return tokens;
}

struct NameClass {
    Kind kind = Kind::Unknown;
    int side = 0;  ///< +1 left, -1 right, 0 none
};

NameClass classifyName(const std::string& name) {
    NameClass out;
    const std::vector<std::string> tokens = tokenize(name);
    std::vector<std::string> words;
    for (const std::string& t : tokens) {
        if (t == "l" || t == "left" || t == "lft") {
            out.side = 1;
        } else if (t == "r" || t == "right" || t == "rgt") {
            out.side = -1;
        } else if (!std::isdigit(static_cast<unsigned char>(t[0]))) {
            words.push_back(t);
        }
    }
    const auto consider = [&](const std::string& word) {
        for (const Keyword& k : kKeywords) {
            if (word == k.word && (out.kind == Kind::Unknown || k.kind < out.kind)) out.kind = k.kind;
        }
        // A sided "hip" is a thigh root (BVH and mocap rigs), an unsided one the pelvis.
        if (word == "hip" && (out.kind == Kind::Unknown || Kind::Thigh < out.kind)) out.kind = Kind::Thigh;
    };
    for (std::size_t i = 0; i < words.size(); ++i) {
        consider(words[i]);
        if (i + 1 < words.size()) consider(words[i] + words[i + 1]);
    }
    if (out.kind == Kind::Thigh && out.side == 0) {
        for (const std::string& w : words)
            if (w == "hip") out.kind = Kind::Hips;
    }
    return out;
}

/// The region a name alone gives, or false when the name says nothing usable (an arm or leg
/// name without a side is not enough: it could be either).
bool regionOfName(const NameClass& c, BodyRegion& out) {
    switch (c.kind) {
    case Kind::Finger:
    case Kind::Hand:
    case Kind::Forearm:
    case Kind::UpperArm:
        if (c.side == 0) return false;
        out = c.side > 0 ? BodyRegion::LeftArm : BodyRegion::RightArm;
        return true;
    case Kind::Toe:
    case Kind::Foot:
    case Kind::Shin:
    case Kind::Thigh:
    case Kind::Leg:
        if (c.side == 0) return false;
        out = c.side > 0 ? BodyRegion::LeftLeg : BodyRegion::RightLeg;
        return true;
    case Kind::Head: out = BodyRegion::Head; return true;
    case Kind::Neck: out = BodyRegion::Neck; return true;
    case Kind::Clavicle:
    case Kind::Hips:
    case Kind::Spine: out = BodyRegion::Torso; return true;
    case Kind::Unknown: break;
    }
    return false;
}

int32_t dominantJoint(const SkinnedMesh& body, std::size_t v) {
    int best = 0;
    for (int k = 1; k < kMaxInfluences; ++k)
        if (body.jointWeights[v][k] > body.jointWeights[v][best]) best = k;
    return body.jointIndices[v][best];
}

bool isAncestor(const Skeleton& s, int32_t ancestor, int32_t joint) {
    for (int32_t j = joint; j >= 0; j = s.joints[j].parent)
        if (j == ancestor) return true;
    return false;
}

int32_t lowestCommonAncestor(const Skeleton& s, int32_t a, int32_t b) {
    for (int32_t x = a; x >= 0; x = s.joints[x].parent)
        if (isAncestor(s, x, b)) return x;
    return -1;
}

/// Child of `ancestor` on the way down to `joint` (or -1 when `joint` is not below it).
int32_t childTowards(const Skeleton& s, int32_t ancestor, int32_t joint) {
    for (int32_t j = joint; j >= 0; j = s.joints[j].parent)
        if (s.joints[j].parent == ancestor) return j;
    return -1;
}

void labelSubtree(const Skeleton& s, int32_t root, BodyRegion region, std::vector<BodyRegion>& labels) {
    for (std::size_t j = 0; j < s.jointCount(); ++j)
        if (isAncestor(s, root, int32_t(j))) labels[j] = region;
}

struct BodyBox {
    double minY = std::numeric_limits<double>::max(), maxY = std::numeric_limits<double>::lowest();
    double height() const { return maxY - minY; }
};

BodyBox boxOf(Span<const Vec3> p) {
    BodyBox b;
    for (const Vec3& q : p) b.minY = std::min(b.minY, q.y()), b.maxY = std::max(b.maxY, q.y());
    return b;
}

Vec3 horizontal(Vec3 v) {
    v.y() = 0.0;
    return v;
}

/// Vertex regions, anchor weights and the key joints from joint labels.
void labelVertices(const Character& ch, BodyRegions& r) {
    const SkinnedMesh& body = ch.body;
    r.vertices.resize(body.vertexCount());
    r.anchorWeight.resize(body.vertexCount());
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        std::array<double, 7> sum{};
        for (int k = 0; k < kMaxInfluences; ++k) sum[std::size_t(r.joints[body.jointIndices[v][k]])] += body.jointWeights[v][k];
        std::size_t best = 0;
        for (std::size_t i = 1; i < sum.size(); ++i)
            if (sum[i] > sum[best]) best = i;
        r.vertices[v] = BodyRegion(best);
        r.anchorWeight[v] = sum[std::size_t(BodyRegion::Torso)] + sum[std::size_t(BodyRegion::Neck)];
    }
}

/// The root joint of `region` whose subtree carries the most skin (a rig may have stray joints of
/// the same region elsewhere, like IK targets).
int32_t mainRoot(const Skeleton& s, const std::vector<BodyRegion>& labels, const std::vector<std::size_t>& carried,
                 BodyRegion region) {
    int32_t best = -1;
    std::size_t bestCount = 0;
    for (std::size_t j = 0; j < s.jointCount(); ++j) {
        if (labels[j] != region) continue;
        const int32_t parent = s.joints[j].parent;
        if (parent >= 0 && labels[std::size_t(parent)] == region) continue;
        std::size_t count = 0;
        for (std::size_t d = 0; d < s.jointCount(); ++d)
            if (isAncestor(s, int32_t(j), int32_t(d))) count += carried[d];
        if (count > bestCount) best = int32_t(j), bestCount = count;
    }
    return best;
}

/// Key joints, facing and the geometric checks every method must pass.
Status finish(const Character& ch, Span<const Vec3> positions, BodyRegions& r) {
    const SkinnedMesh& body = ch.body;
    const Skeleton& s = ch.skeleton;
    labelVertices(ch, r);
    std::vector<std::size_t> carried(s.jointCount(), 0);
    for (std::size_t v = 0; v < body.vertexCount(); ++v) ++carried[std::size_t(dominantJoint(body, v))];

    std::array<Vec3, 7> centroid;
    centroid.fill(Vec3::Zero());
    std::array<std::size_t, 7> count{};
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        centroid[std::size_t(r.vertices[v])] += positions[v];
        ++count[std::size_t(r.vertices[v])];
    }
    for (std::size_t i = 0; i < 7; ++i)
        if (count[i] > 0) centroid[i] /= double(count[i]);
    const auto has = [&](BodyRegion g) { return count[std::size_t(g)] > 0; };
    if (!has(BodyRegion::Torso)) return Status::invalidArgument("no torso skin found");
    if (!has(BodyRegion::LeftLeg) || !has(BodyRegion::RightLeg)) return Status::invalidArgument("no two legs found");
    if (!has(BodyRegion::Head)) return Status::invalidArgument("no head found");
    const BodyBox box = boxOf(positions);
    const double h = box.height();
    const Vec3 torso = centroid[std::size_t(BodyRegion::Torso)];
    if (!(centroid[std::size_t(BodyRegion::Head)].y() > torso.y() + 0.05 * h))
        return Status::invalidArgument("the head is not above the torso");
    for (BodyRegion leg : {BodyRegion::LeftLeg, BodyRegion::RightLeg})
        if (!(centroid[std::size_t(leg)].y() < torso.y() - 0.05 * h))
            return Status::invalidArgument(std::string("the ") + regionName(leg) + " is not below the torso");

    // Facing: the character's left from its sides, checked by its feet (toes point forward).
    Vec3 side = horizontal(centroid[std::size_t(BodyRegion::LeftLeg)] - centroid[std::size_t(BodyRegion::RightLeg)]);
    if (has(BodyRegion::LeftArm) && has(BodyRegion::RightArm))
        side += horizontal(centroid[std::size_t(BodyRegion::LeftArm)] - centroid[std::size_t(BodyRegion::RightArm)]);
    if (side.norm() < 0.02 * h) return Status::invalidArgument("the left and right legs are not side by side");
    r.left = side.normalized();
    r.forward = r.left.cross(Vec3::UnitY()).normalized();
    Vec3 toes = Vec3::Zero(), shins = Vec3::Zero();
    std::size_t toeCount = 0, shinCount = 0;
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        if (!isLeg(r.vertices[v])) continue;
        const double f = (positions[v].y() - box.minY) / h;
        if (f < 0.04) toes += positions[v], ++toeCount;
        else if (f > 0.12 && f < 0.25) shins += positions[v], ++shinCount;
    }
    if (toeCount > 0 && shinCount > 0) {
        const double ahead = (toes / double(toeCount) - shins / double(shinCount)).dot(r.forward);
        // Feet are the ground truth for facing; a rig whose "Left" is the viewer's left is mirrored.
        if (ahead < -0.01 * h) {
            r.forward = -r.forward;
            r.left = -r.left;
            const auto mirror = [](BodyRegion& g) {
                if (g == BodyRegion::LeftArm) g = BodyRegion::RightArm;
                else if (g == BodyRegion::RightArm) g = BodyRegion::LeftArm;
                else if (g == BodyRegion::LeftLeg) g = BodyRegion::RightLeg;
                else if (g == BodyRegion::RightLeg) g = BodyRegion::LeftLeg;
            };
            for (BodyRegion& g : r.joints) mirror(g);
            for (BodyRegion& g : r.vertices) mirror(g);
        }
    }

    r.head = mainRoot(s, r.joints, carried, BodyRegion::Head);
    r.neck = mainRoot(s, r.joints, carried, BodyRegion::Neck);
    for (int k = 0; k < 2; ++k) {
        r.upperArm[k] = mainRoot(s, r.joints, carried, k == 0 ? BodyRegion::LeftArm : BodyRegion::RightArm);
        r.thigh[k] = mainRoot(s, r.joints, carried, k == 0 ? BodyRegion::LeftLeg : BodyRegion::RightLeg);
    }
    if (r.thigh[0] >= 0 && r.thigh[1] >= 0) r.hips = lowestCommonAncestor(s, r.thigh[0], r.thigh[1]);
    if (r.upperArm[0] >= 0 && r.upperArm[1] >= 0) r.chest = lowestCommonAncestor(s, r.upperArm[0], r.upperArm[1]);
    // The spine above the joint the arms branch from is neck, whatever it is called (Rigify
    // numbers its neck joints on from the spine: spine.004 and spine.005 below the head).
    if (r.chest >= 0 && r.head >= 0 && isAncestor(s, r.chest, r.head)) {
        bool relabelled = false;
        for (int32_t j = s.joints[std::size_t(r.head)].parent; j >= 0 && j != r.chest; j = s.joints[std::size_t(j)].parent)
            if (r.joints[std::size_t(j)] == BodyRegion::Torso) {
                r.joints[std::size_t(j)] = BodyRegion::Neck;
                relabelled = true;
            }
        if (relabelled) {
            labelVertices(ch, r);
            r.neck = mainRoot(s, r.joints, carried, BodyRegion::Neck);
        }
    }
    return Status::ok();
}

/// Joint labels from names, or false when the names do not describe a humanoid.
bool labelByNames(const Character& ch, Span<const Vec3> positions, BodyRegions& r) {
    const Skeleton& s = ch.skeleton;
    r.joints.assign(s.jointCount(), BodyRegion::Torso);
    std::size_t named = 0;
    for (std::size_t j = 0; j < s.jointCount(); ++j) {
        BodyRegion own;
        if (regionOfName(classifyName(s.joints[j].name), own)) {
            r.joints[j] = own;
            ++named;
        } else if (s.joints[j].parent >= 0) {
            r.joints[j] = r.joints[std::size_t(s.joints[j].parent)];
        }
    }
    if (named == 0) return false;
    // Exporters that number their neck joints ("neck_joint_1", "neck_joint_2") leave the head
    // unnamed: the joint that carries the top of the body is the head.
    std::size_t top = 0;
    for (std::size_t v = 1; v < ch.body.vertexCount(); ++v)
        if (positions[v].y() > positions[top].y()) top = v;
    const int32_t topJoint = dominantJoint(ch.body, top);
    const BodyRegion topRegion = r.joints[std::size_t(topJoint)];
    if (topRegion == BodyRegion::Neck || topRegion == BodyRegion::Torso) {
        bool headCarriesSkin = false;
        for (std::size_t v = 0; v < ch.body.vertexCount() && !headCarriesSkin; ++v)
            headCarriesSkin = r.joints[std::size_t(dominantJoint(ch.body, v))] == BodyRegion::Head;
        if (!headCarriesSkin) labelSubtree(s, topJoint, BodyRegion::Head, r.joints);
    }
    return true;
}

/// Joint labels from the skeleton's branching and the skin: hands are the body's lateral
/// extremes, feet its lowest points on either side, the head its top; the arms branch where the
/// paths to both hands meet, the legs where the paths to both feet meet.
Status labelByStructure(const Character& ch, Span<const Vec3> positions, BodyRegions& r) {
    const Skeleton& s = ch.skeleton;
    const SkinnedMesh& body = ch.body;
    const BodyBox box = boxOf(positions);
    const double h = box.height();
    // The lateral axis: the main horizontal spread of the upper body (shoulders and arms are wider
    // than the chest is deep).
    Vec3 mean = Vec3::Zero();
    std::size_t n = 0;
    for (const Vec3& p : positions)
        if (p.y() > box.minY + 0.45 * h) mean += horizontal(p), ++n;
    if (n == 0) return Status::invalidArgument("the body has no upper half");
    mean /= double(n);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const Vec3& p : positions) {
        if (p.y() <= box.minY + 0.45 * h) continue;
        const Eigen::Vector2d d(p.x() - mean.x(), p.z() - mean.z());
        cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d major = eig.eigenvectors().col(1);
    const Vec3 lateral(major.x(), 0.0, major.y());
    std::array<std::size_t, 2> hand{0, 0}, foot{0, 0};
    std::array<double, 2> handReach{-1e300, -1e300}, footLow{1e300, 1e300};
    std::size_t top = 0;
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        const Vec3& p = positions[v];
        const double a = (p - mean).dot(lateral);
        if (p.y() > positions[top].y()) top = v;
        const int k = a >= 0.0 ? 0 : 1;
        if (p.y() > box.minY + 0.3 * h && std::abs(a) > handReach[k]) handReach[k] = std::abs(a), hand[k] = v;
        if (p.y() < footLow[k]) footLow[k] = p.y(), foot[k] = v;
    }
    const int32_t hands[2] = {dominantJoint(body, hand[0]), dominantJoint(body, hand[1])};
    const int32_t feet[2] = {dominantJoint(body, foot[0]), dominantJoint(body, foot[1])};
    const int32_t headTop = dominantJoint(body, top);
    const int32_t chest = lowestCommonAncestor(s, hands[0], hands[1]);
    const int32_t hips = lowestCommonAncestor(s, feet[0], feet[1]);
    if (chest < 0 || hips < 0 || chest == hands[0] || hips == feet[0])
        return Status::invalidArgument("the skeleton does not branch into two arms and two legs");
    if (!isAncestor(s, hips, chest)) return Status::invalidArgument("the arms do not branch above the hips");
    if (!isAncestor(s, chest, headTop) || headTop == chest)
        return Status::invalidArgument("no head joint above the chest");
    r.joints.assign(s.jointCount(), BodyRegion::Torso);
    std::vector<int32_t> path;  // chest (exclusive) -> head top (inclusive)
    for (int32_t j = headTop; j != chest; j = s.joints[std::size_t(j)].parent) path.push_back(j);
    std::reverse(path.begin(), path.end());
    const int32_t head = path.size() >= 2 ? path[1] : path[0];
    if (path.size() >= 2) r.joints[std::size_t(path[0])] = BodyRegion::Neck;
    labelSubtree(s, head, BodyRegion::Head, r.joints);
    for (int k = 0; k < 2; ++k) {
        // Side by the lateral axis for now; finish() decides which side is left.
        const int32_t arm = childTowards(s, chest, hands[k]);
        const int32_t leg = childTowards(s, hips, feet[k]);
        if (arm < 0 || leg < 0) return Status::invalidArgument("a limb does not hang from the skeleton");
        labelSubtree(s, arm, k == 0 ? BodyRegion::LeftArm : BodyRegion::RightArm, r.joints);
        labelSubtree(s, leg, k == 0 ? BodyRegion::LeftLeg : BodyRegion::RightLeg, r.joints);
    }
    return Status::ok();
}

} // namespace

const char* regionName(BodyRegion region) {
    switch (region) {
    case BodyRegion::Torso: return "torso";
    case BodyRegion::Neck: return "neck";
    case BodyRegion::Head: return "head";
    case BodyRegion::LeftArm: return "left arm";
    case BodyRegion::RightArm: return "right arm";
    case BodyRegion::LeftLeg: return "left leg";
    case BodyRegion::RightLeg: return "right leg";
    }
    return "?";
}

Result<BodyRegions> findBodyRegions(const Character& character, Span<const Vec3> restPositions) {
    if (character.skeleton.jointCount() == 0 || character.body.vertexCount() == 0)
        return Status::invalidArgument("the character has no skeleton or no body");
    if (restPositions.size() != character.body.vertexCount())
        return Status::invalidArgument("findBodyRegions: " + std::to_string(restPositions.size()) +
                                       " positions for a body of " + std::to_string(character.body.vertexCount()));
    std::string namesFailed;
    BodyRegions byNames;
    if (labelByNames(character, restPositions, byNames)) {
        byNames.method = "joint names";
        const Status s = finish(character, restPositions, byNames);
        if (s) return byNames;
        namesFailed = s.message();
    } else {
        namesFailed = "no joint name describes a body part";
    }
    BodyRegions byStructure;
    byStructure.method = "skeleton structure";
    Status s = labelByStructure(character, restPositions, byStructure);
    if (s) s = finish(character, restPositions, byStructure);
    if (s) return byStructure;
    return Status::invalidArgument("no humanoid found in the skeleton: by joint names, " + namesFailed +
                                   "; by skeleton structure, " + s.message());
}

} // namespace cc
