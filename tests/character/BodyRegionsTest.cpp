// Body regions (torso, neck, head, arms, legs) from joint names of every common rig convention,
// from the skeleton's structure alone, and from the geometry alone; and clear errors for bodies
// that are not humanoids.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/BodyRegions.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/import/CharacterIO.h"
#include "support/RestPose.h"

namespace cc {
namespace {

namespace fs = std::filesystem;

/// Regions coarse enough that every method must agree: what garments may hang from (torso and
/// neck), the head, the arms, the legs.
int coarse(BodyRegion g) {
    if (g == BodyRegion::Torso || g == BodyRegion::Neck) return 0;
    if (g == BodyRegion::Head) return 1;
    if (isArm(g)) return 2;
    return 3;
}

/// The mannequin's own regions, known exactly from its body parts. Two kinds of vertices may
/// honestly be given another region: those hidden inside another part (the parts overlap at the
/// joints: the top of a thigh or an arm lies inside the torso, the top of the neck inside the
/// head, the bottom of the head inside the neck), and those whose skin moves mostly with a joint of another region (the top of the arm
/// moves with the clavicle, a torso joint; the top of the thigh with the hips).
struct Truth {
    std::vector<BodyRegion> own;          ///< the region of the vertex's part
    std::vector<BodyRegion> hiddenIn;     ///< the region of the part it lies inside (= own if none)
    std::vector<BodyRegion> movesWith;    ///< the region of the joint with most of its skin weight
};

/// Region of every mannequin joint (MannequinJoint order): the clavicles belong to the torso.
std::vector<BodyRegion> mannequinJointRegions() {
    using R = BodyRegion;
    return {R::Torso,   R::Torso,   R::Torso,    R::Neck,    R::Head,                 // hips .. head
            R::Torso,   R::LeftArm, R::LeftArm,  R::LeftArm,                          // left shoulder .. hand
            R::Torso,   R::RightArm, R::RightArm, R::RightArm,                        // right
            R::LeftLeg, R::LeftLeg, R::LeftLeg,  R::RightLeg, R::RightLeg, R::RightLeg};
}

BodyRegion regionOfPart(const std::string& name) {
    const bool left = name.size() > 2 && name.compare(name.size() - 2, 2, "_l") == 0;
    if (name == "torso") return BodyRegion::Torso;
    if (name == "head") return BodyRegion::Head;
    if (name == "neck") return BodyRegion::Neck;
    if (name.find("arm") != std::string::npos || name.find("hand") != std::string::npos)
        return left ? BodyRegion::LeftArm : BodyRegion::RightArm;
    return left ? BodyRegion::LeftLeg : BodyRegion::RightLeg;
}

/// Generalised winding number of one closed, outward-oriented part at p (Jacobson et al. 2013).
double windingNumber(const SkinnedMesh& body, const BodyPart& part, const Vec3& p) {
    double total = 0.0;
    for (uint32_t t = part.firstTriangle; t < part.firstTriangle + part.triangleCount; ++t) {
        const Vec3 a = body.bindPositions[body.triangles[t][0]] - p;
        const Vec3 b = body.bindPositions[body.triangles[t][1]] - p;
        const Vec3 c = body.bindPositions[body.triangles[t][2]] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        total += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
    }
    return total / (4.0 * M_PI);
}

Truth truthOf(const Mannequin& m) {
    const SkinnedMesh& body = m.character.body;
    Truth t;
    t.own.assign(body.vertexCount(), BodyRegion::Torso);
    for (const BodyPart& part : m.parts)
        for (uint32_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v) t.own[v] = regionOfPart(part.name);
    t.hiddenIn = t.own;
    t.movesWith = t.own;
    const std::vector<BodyRegion> jointRegion = mannequinJointRegions();
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        const auto& w = body.jointWeights[v];
        const std::size_t k = std::size_t(std::max_element(w.begin(), w.end()) - w.begin());
        t.movesWith[v] = jointRegion[body.jointIndices[v][k]];
    }
    for (const BodyPart& part : m.parts) {
        if (part.name != "torso" && part.name != "neck" && part.name != "head") continue;
        for (std::size_t v = 0; v < body.vertexCount(); ++v)
            if ((v < part.firstVertex || v >= part.firstVertex + part.vertexCount) &&
                windingNumber(body, part, body.bindPositions[v]) > 0.5)
                t.hiddenIn[v] = regionOfPart(part.name);
    }
    return t;
}

bool agrees(const Truth& truth, std::size_t v, BodyRegion found) {
    return coarse(found) == coarse(truth.own[v]) || coarse(found) == coarse(truth.hiddenIn[v]) ||
           coarse(found) == coarse(truth.movesWith[v]);
}

/// Fraction of vertices whose coarse region agrees with the truth.
double agreement(const BodyRegions& found, const Truth& truth) {
    std::size_t same = 0;
    for (std::size_t v = 0; v < found.vertices.size(); ++v) same += agrees(truth, v, found.vertices[v]);
    return double(same) / double(found.vertices.size());
}

TEST(BodyRegions, MannequinByItsJointNames) {
    const Mannequin m = buildMannequin().value();
    auto r = findBodyRegions(m.character, test::restPositionsOf(m.character));
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r.value().method, "joint names");
    EXPECT_GT(agreement(r.value(), truthOf(m)), 0.99);
    const std::vector<BodyRegion> expected = mannequinJointRegions();
    ASSERT_EQ(r.value().joints.size(), expected.size());
    for (std::size_t j = 0; j < expected.size(); ++j)
        EXPECT_EQ(r.value().joints[j], expected[j]) << m.character.skeleton.joints[j].name;
    EXPECT_NEAR(r.value().forward.z(), 1.0, 1e-6) << "the mannequin faces +Z";
    EXPECT_NEAR(r.value().left.x(), 1.0, 1e-6) << "its left is +X";
    EXPECT_EQ(m.character.skeleton.joints[std::size_t(r.value().upperArm[0])].name, "upper_arm_l")
        << "the clavicle (shoulder_l) is torso, the arm starts after it";
    EXPECT_EQ(m.character.skeleton.joints[std::size_t(r.value().thigh[1])].name, "thigh_r");
}

/// The mannequin with its joints renamed to another convention (mannequin name -> new name).
Character renamed(const std::vector<std::pair<const char*, const char*>>& names) {
    Character c = buildMannequin().value().character;
    for (Joint& j : c.skeleton.joints)
        for (const auto& [from, to] : names)
            if (j.name == from) j.name = to;
    return c;
}

TEST(BodyRegions, EveryCommonRigNamingConvention) {
    const Mannequin m = buildMannequin().value();
    const Truth truth = truthOf(m);
    const std::vector<std::pair<const char*, std::vector<std::pair<const char*, const char*>>>> conventions = {
        {"Mixamo", {{"hips", "mixamorig:Hips"}, {"spine", "mixamorig:Spine"}, {"chest", "mixamorig:Spine2"},
                    {"neck", "mixamorig:Neck"}, {"head", "mixamorig:Head"}, {"shoulder_l", "mixamorig:LeftShoulder"},
                    {"upper_arm_l", "mixamorig:LeftArm"}, {"forearm_l", "mixamorig:LeftForeArm"}, {"hand_l", "mixamorig:LeftHand"},
                    {"shoulder_r", "mixamorig:RightShoulder"}, {"upper_arm_r", "mixamorig:RightArm"},
                    {"forearm_r", "mixamorig:RightForeArm"}, {"hand_r", "mixamorig:RightHand"}, {"thigh_l", "mixamorig:LeftUpLeg"},
                    {"shin_l", "mixamorig:LeftLeg"}, {"foot_l", "mixamorig:LeftFoot"}, {"thigh_r", "mixamorig:RightUpLeg"},
                    {"shin_r", "mixamorig:RightLeg"}, {"foot_r", "mixamorig:RightFoot"}}},
        {"Unreal", {{"hips", "pelvis"}, {"spine", "spine_01"}, {"chest", "spine_03"}, {"neck", "neck_01"}, {"head", "head"},
                    {"shoulder_l", "clavicle_l"}, {"upper_arm_l", "upperarm_l"}, {"forearm_l", "lowerarm_l"}, {"hand_l", "hand_l"},
                    {"shoulder_r", "clavicle_r"}, {"upper_arm_r", "upperarm_r"}, {"forearm_r", "lowerarm_r"}, {"hand_r", "hand_r"},
                    {"thigh_l", "thigh_l"}, {"shin_l", "calf_l"}, {"foot_l", "foot_l"}, {"thigh_r", "thigh_r"},
                    {"shin_r", "calf_r"}, {"foot_r", "foot_r"}}},
        {"Unity/VRM", {{"hips", "J_Bip_C_Hips"}, {"spine", "J_Bip_C_Spine"}, {"chest", "J_Bip_C_UpperChest"},
                       {"neck", "J_Bip_C_Neck"}, {"head", "J_Bip_C_Head"}, {"shoulder_l", "J_Bip_L_Shoulder"},
                       {"upper_arm_l", "J_Bip_L_UpperArm"}, {"forearm_l", "J_Bip_L_LowerArm"}, {"hand_l", "J_Bip_L_Hand"},
                       {"shoulder_r", "J_Bip_R_Shoulder"}, {"upper_arm_r", "J_Bip_R_UpperArm"}, {"forearm_r", "J_Bip_R_LowerArm"},
                       {"hand_r", "J_Bip_R_Hand"}, {"thigh_l", "J_Bip_L_UpperLeg"}, {"shin_l", "J_Bip_L_LowerLeg"},
                       {"foot_l", "J_Bip_L_Foot"}, {"thigh_r", "J_Bip_R_UpperLeg"}, {"shin_r", "J_Bip_R_LowerLeg"},
                       {"foot_r", "J_Bip_R_Foot"}}},
        {"VRM humanoid", {{"hips", "hips"}, {"spine", "spine"}, {"chest", "upperChest"}, {"neck", "neck"}, {"head", "head"},
                          {"shoulder_l", "leftShoulder"}, {"upper_arm_l", "leftUpperArm"}, {"forearm_l", "leftLowerArm"},
                          {"hand_l", "leftHand"}, {"shoulder_r", "rightShoulder"}, {"upper_arm_r", "rightUpperArm"},
                          {"forearm_r", "rightLowerArm"}, {"hand_r", "rightHand"}, {"thigh_l", "leftUpperLeg"},
                          {"shin_l", "leftLowerLeg"}, {"foot_l", "leftFoot"}, {"thigh_r", "rightUpperLeg"},
                          {"shin_r", "rightLowerLeg"}, {"foot_r", "rightFoot"}}},
        {"Blender Rigify", {{"hips", "DEF-spine"}, {"spine", "DEF-spine.001"}, {"chest", "DEF-spine.003"},
                            {"neck", "DEF-spine.004"}, {"head", "DEF-spine.006"}, {"shoulder_l", "DEF-shoulder.L"},
                            {"upper_arm_l", "DEF-upper_arm.L"}, {"forearm_l", "DEF-forearm.L"}, {"hand_l", "DEF-hand.L"},
                            {"shoulder_r", "DEF-shoulder.R"}, {"upper_arm_r", "DEF-upper_arm.R"}, {"forearm_r", "DEF-forearm.R"},
                            {"hand_r", "DEF-hand.R"}, {"thigh_l", "DEF-thigh.L"}, {"shin_l", "DEF-shin.L"}, {"foot_l", "DEF-foot.L"},
                            {"thigh_r", "DEF-thigh.R"}, {"shin_r", "DEF-shin.R"}, {"foot_r", "DEF-foot.R"}}},
        {"3ds Max Biped", {{"hips", "Bip01 Pelvis"}, {"spine", "Bip01 Spine"}, {"chest", "Bip01 Spine2"}, {"neck", "Bip01 Neck"},
                           {"head", "Bip01 Head"}, {"shoulder_l", "Bip01 L Clavicle"}, {"upper_arm_l", "Bip01 L UpperArm"},
                           {"forearm_l", "Bip01 L Forearm"}, {"hand_l", "Bip01 L Hand"}, {"shoulder_r", "Bip01 R Clavicle"},
                           {"upper_arm_r", "Bip01 R UpperArm"}, {"forearm_r", "Bip01 R Forearm"}, {"hand_r", "Bip01 R Hand"},
                           {"thigh_l", "Bip01 L Thigh"}, {"shin_l", "Bip01 L Calf"}, {"foot_l", "Bip01 L Foot"},
                           {"thigh_r", "Bip01 R Thigh"}, {"shin_r", "Bip01 R Calf"}, {"foot_r", "Bip01 R Foot"}}},
        {"glTF exporter", {{"hips", "torso_joint_1"}, {"spine", "torso_joint_2"}, {"chest", "torso_joint_3"},
                           {"neck", "neck_joint_1"}, {"head", "neck_joint_2"}, {"shoulder_l", "torso_joint_L"},
                           {"upper_arm_l", "arm_joint_L_1"}, {"forearm_l", "arm_joint_L_2"}, {"hand_l", "arm_joint_L_3"},
                           {"shoulder_r", "torso_joint_R"}, {"upper_arm_r", "arm_joint_R_1"}, {"forearm_r", "arm_joint_R_2"},
                           {"hand_r", "arm_joint_R_3"}, {"thigh_l", "leg_joint_L_1"}, {"shin_l", "leg_joint_L_2"},
                           {"foot_l", "leg_joint_L_3"}, {"thigh_r", "leg_joint_R_1"}, {"shin_r", "leg_joint_R_2"},
                           {"foot_r", "leg_joint_R_3"}}},
    };
    for (const auto& [convention, names] : conventions) {
        const Character c = renamed(names);
        auto r = findBodyRegions(c, test::restPositionsOf(c));
        ASSERT_TRUE(r.isOk()) << convention << ": " << r.status().message();
        EXPECT_EQ(r.value().method, "joint names") << convention;
        const double a = agreement(r.value(), truth);
        std::printf("%s: %.1f %% of vertices in the right region\n", convention, 100.0 * a);
        EXPECT_GT(a, 0.99) << convention;
        const std::vector<BodyRegion> expected = mannequinJointRegions();
        ASSERT_EQ(r.value().joints.size(), expected.size());
        for (std::size_t j = 0; j < expected.size(); ++j)
            EXPECT_EQ(r.value().joints[j], expected[j]) << convention << ": " << c.skeleton.joints[j].name;
        EXPECT_NEAR(r.value().forward.z(), 1.0, 1e-6) << convention;
    }
}

TEST(BodyRegions, SkeletonStructureWhenTheNamesSayNothing) {
    const Mannequin m = buildMannequin().value();
    Character c = m.character;
    for (std::size_t j = 0; j < c.skeleton.jointCount(); ++j) c.skeleton.joints[j].name = "bone" + std::to_string(j);
    auto r = findBodyRegions(c, test::restPositionsOf(c));
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r.value().method, "skeleton structure");
    const double a = agreement(r.value(), truthOf(m));
    std::printf("skeleton structure: %.1f %% of vertices in the right region\n", 100.0 * a);
    EXPECT_GT(a, 0.95) << "without names the clavicles count as arms, the rest must agree";
    EXPECT_NEAR(r.value().forward.z(), 1.0, 1e-6) << "facing comes from the feet";
}

TEST(BodyRegions, GeometryAloneFindsTorsoArmsLegsAndHead) {
    const Mannequin m = buildMannequin().value();
    auto r = findBodyRegionsFromGeometry(m.character.body);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r.value().method, "geometry");
    const double a = agreement(r.value(), truthOf(m));
    std::printf("geometry: %.1f %% of vertices in the right region\n", 100.0 * a);
    EXPECT_GT(a, 0.85);
    // What matters most: nothing of an arm or the head is taken for torso skin.
    const Truth truth = truthOf(m);
    std::size_t wrongAnchor = 0, anchor = 0;
    for (std::size_t v = 0; v < truth.own.size(); ++v) {
        if (r.value().anchorWeight[v] < 0.9) continue;  // what garments bind to (BodyAsset)
        ++anchor;
        wrongAnchor += !agrees(truth, v, BodyRegion::Torso);
    }
    EXPECT_GT(anchor, 100u);
    EXPECT_LT(double(wrongAnchor) / double(anchor), 0.05) << wrongAnchor << " of " << anchor << " torso vertices are not torso";
    EXPECT_NEAR(r.value().forward.z(), 1.0, 1e-3);
}

TEST(BodyRegions, TurnedBodiesKeepTheirRegionsAndFacing) {
    Character c = buildMannequin().value().character;
    const Mat3 turn = Eigen::AngleAxisd(2.0, Vec3::UnitY()).toRotationMatrix();  // facing elsewhere
    ASSERT_TRUE(changeBasis(c, 1.0, turn).isOk());
    auto r = findBodyRegions(c, test::restPositionsOf(c));
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_LT((r.value().forward - turn * Vec3::UnitZ()).norm(), 1e-6);
    auto g = findBodyRegionsFromGeometry(c.body);
    ASSERT_TRUE(g.isOk()) << g.status().message();
    EXPECT_LT((g.value().forward - turn * Vec3::UnitZ()).norm(), 0.05);
}

TEST(BodyRegions, NotAHumanoidSaysWhy) {
    // A box: no legs, no head.
    SkinnedMesh box;
    const double corners[8][3] = {{-0.2, 0, -0.1}, {0.2, 0, -0.1}, {0.2, 1.5, -0.1}, {-0.2, 1.5, -0.1},
                                  {-0.2, 0, 0.1},  {0.2, 0, 0.1},  {0.2, 1.5, 0.1},  {-0.2, 1.5, 0.1}};
    for (const auto& p : corners) box.bindPositions.push_back(Vec3(p[0], p[1], p[2]));
    box.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                     {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    auto r = findBodyRegionsFromGeometry(box);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("torso"), std::string::npos) << r.status().message();

    // One joint carrying a box: neither names nor structure describe a humanoid.
    Character c;
    c.skeleton.joints.push_back(Joint{"pole", -1, {}});
    c.body = box;
    c.body.computeBindNormals();
    c.body.jointIndices.assign(8, {0, 0, 0, 0});
    c.body.jointWeights.assign(8, {1, 0, 0, 0});
    c.body.inverseBindMatrices.assign(1, Mat4::Identity());
    auto s = findBodyRegions(c, c.body.bindPositions);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.status().message().find("no humanoid found"), std::string::npos) << s.status().message();
}

TEST(BodyRegions, SharedHumanoidsByJointNamesAndByGeometry) {
    const fs::path dir = CC_HUMANOIDS_DIR;
    if (!fs::is_directory(dir)) GTEST_SKIP() << "shared humanoids folder absent: " << dir;
    for (const char* name : {"CesiumMan.glb", "RiggedFigure.glb", "RobotExpressive.glb"}) {
        if (!fs::exists(dir / name)) continue;
        auto ch = importCharacter((dir / name).string());
        ASSERT_TRUE(ch.isOk()) << ch.status().message();
        auto r = findBodyRegions(ch.value(), test::restPositionsOf(ch.value()));
        ASSERT_TRUE(r.isOk()) << name << ": " << r.status().message();
        std::array<std::size_t, 7> count{};
        for (BodyRegion g : r.value().vertices) ++count[std::size_t(g)];
        std::printf("%s (%s): torso %zu, neck %zu, head %zu, arms %zu + %zu, legs %zu + %zu vertices\n", name,
                    r.value().method.c_str(), count[0], count[1], count[2], count[3], count[4], count[5], count[6]);
        for (std::size_t k = 0; k < count.size(); ++k)
            if (k != std::size_t(BodyRegion::Neck)) {
                EXPECT_GT(count[k], 0u) << name << ": " << regionName(BodyRegion(k));
            }
        EXPECT_GT(r.value().forward.z(), 0.9) << name << " faces +Z";

        // The same body as a host would hand it in, without its skeleton: geometry alone.
        SkinnedMesh posed = ch.value().body;
        posed.bindPositions = test::restPositionsOf(ch.value());
        auto g = findBodyRegionsFromGeometry(posed);
        ASSERT_TRUE(g.isOk()) << name << " by geometry: " << g.status().message();
        std::size_t same = 0, anchors = 0, wrongAnchors = 0;
        for (std::size_t v = 0; v < posed.vertexCount(); ++v) {
            same += coarse(g.value().vertices[v]) == coarse(r.value().vertices[v]);
            if (g.value().anchorWeight[v] < 0.9) continue;
            ++anchors;
            wrongAnchors += coarse(r.value().vertices[v]) != 0;
        }
        std::printf("%s by geometry: %.1f %% agree with the joint names, %zu of %zu torso vertices are not torso\n", name,
                    100.0 * double(same) / double(posed.vertexCount()), wrongAnchors, anchors);
        // Geometry cannot know what the rig skins to the arm: a low-poly figure skins its
        // shoulder blades to the upper arm. Most of the torso skin must still be torso.
        EXPECT_LT(double(wrongAnchors), 0.2 * double(anchors)) << name;
        EXPECT_GT(double(same), 0.75 * double(posed.vertexCount())) << name;
        EXPECT_GT(g.value().forward.z(), 0.9) << name;
    }
}

} // namespace
} // namespace cc
