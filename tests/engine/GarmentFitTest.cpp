// Garments fitted to the body: sizes derived from the body unless given, sizes too small refused
// naming the size, attachments only on the torso's skin, flared cuts that clear the legs in a
// stride (the body's clips' or the host's), and clear errors for bodies garments cannot be fitted
// to.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "BodyAsset.h"
#include "GarmentFit.h"
#include "crowdcloth/World.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/import/CharacterIO.h"

namespace cc {
namespace {

namespace fs = std::filesystem;

using test::WorldPtr;

WorldPtr makeFittingWorld() {
    WorldDesc d;
    d.fixedCostModel = true;
    return WorldPtr(World::create(d).value());
}


/// The cut a World fits `design` to on `body` (through a character wearing it).
Result<ClothAssetDesc> fitOn(World& world, BodyId body, const ClothAssetDesc& design) {
    auto asset = world.addClothAsset(design);
    if (!asset.isOk()) return asset.status();
    CharacterDesc c;
    c.body = body;
    c.clip = nullptr;  // the rest pose: bodies without clips too
    auto character = world.addCharacter(c);
    if (!character.isOk()) return character.status();
    auto garment = world.addGarment(asset.value(), character.value(), {});
    if (!garment.isOk()) return garment.status();
    return world.garmentFit(garment.value());
}

TEST(GarmentFit, SizesDeriveFromTheBody) {
    WorldPtr world = makeFittingWorld();
    MannequinDesc wide;
    wide.hipWidth = 0.44, wide.waistWidth = 0.38, wide.shoulderWidth = 0.5;
    MannequinDesc small;
    small.height = 1.5;
    for (const MannequinDesc& md : {MannequinDesc{}, wide, small}) {
        const BodyId body = world->addMannequinBody(md).value();
        const BodyLandmarkDesc l = world->bodyLandmarks(body).value();
        for (GarmentKind kind : test::kGarmentKinds) {
            ClothAssetDesc d;
            d.kind = kind;
            auto fit = fitOn(*world, body, d);
            ASSERT_TRUE(fit.isOk()) << test::kindName(kind) << ": " << fit.status().message();
            const ClothAssetDesc& f = fit.value();
            std::printf("%.2f m mannequin, %s: width %.3f, length %.3f, hem %.3f\n", md.height, test::kindName(kind), f.width, f.length,
                        f.hemWidth);
            // Round the body at the collision thickness, plus ease.
            const double round = 2.0 * M_PI * d.thickness + d.ease;
            switch (kind) {
            case GarmentKind::Skirt:
                EXPECT_NEAR(f.width, l.waistGirth + round, 0.02) << "the waistband is the waist plus ease";
                EXPECT_NEAR(f.length, 0.3 * md.height, 1e-6);
                break;
            case GarmentKind::Dress:
                EXPECT_NEAR(f.width, l.chestGirth + round, 0.02) << "the top is the chest under the arms plus ease";
                EXPECT_NEAR(f.length, 0.45 * md.height, 1e-6);
                break;
            case GarmentKind::Cape:
                EXPECT_GT(f.width, 0.9 * l.shoulderWidth) << "a cape is as wide as the shoulders";
                EXPECT_LT(f.width, 1.3 * l.shoulderWidth);
                EXPECT_NEAR(f.length, 0.5 * md.height, 1e-6);
                break;
            case GarmentKind::Poncho:
                EXPECT_GT(f.width, 2.0 * l.shoulderWidth) << "a poncho goes round the shoulders";
                EXPECT_NEAR(f.length, 0.3 * md.height, 1e-6);
                break;
            }
            EXPECT_GE(f.hemWidth, f.width) << "an A-line cut widens to the hem";
        }
    }
}

TEST(GarmentFit, GivenSizesAreKeptOrRefusedWhenTooSmall) {
    WorldPtr world = makeFittingWorld();
    const BodyId body = world->addMannequinBody({}).value();
    const BodyLandmarkDesc l = world->bodyLandmarks(body).value();
    {
        ClothAssetDesc d;
        d.kind = GarmentKind::Skirt;
        d.width = 1.2;
        d.length = 0.4;
        auto fit = fitOn(*world, body, d);
        ASSERT_TRUE(fit.isOk()) << fit.status().message();
        EXPECT_DOUBLE_EQ(fit.value().width, 1.2);
        EXPECT_DOUBLE_EQ(fit.value().length, 0.4);
        d.relativeLength = 0.5;
        d.length = 0.0;
        EXPECT_NEAR(fitOn(*world, body, d).value().length, 0.9, 1e-6) << "lengths in body heights";
    }
    const struct {
        GarmentKind kind;
        double width;
        const char* why;
    } tooSmall[] = {{GarmentKind::Skirt, 0.5 * l.waistGirth, "too small to fit"},
                    {GarmentKind::Dress, 0.6 * l.chestGirth, "too small to fit"},
                    {GarmentKind::Poncho, 0.5, "too small to fit"},
                    {GarmentKind::Cape, 0.05, "too small to fit"}};
    for (const auto& t : tooSmall) {
        ClothAssetDesc d;
        d.kind = t.kind;
        d.width = t.width;
        auto fit = fitOn(*world, body, d);
        ASSERT_FALSE(fit.isOk()) << test::kindName(t.kind) << " of " << t.width << " m fits a " << l.waistGirth << " m waist";
        const std::string& m = fit.status().message();
        EXPECT_NE(m.find(t.why), std::string::npos) << m;
        EXPECT_NE(m.find(test::kindName(t.kind)), std::string::npos) << "names the garment: " << m;
        std::printf("%s\n", m.c_str());
    }
    // A straight skirt whose hem cannot pass the hips.
    ClothAssetDesc narrowHem;
    narrowHem.kind = GarmentKind::Skirt;
    narrowHem.cut = GarmentCut::Straight;
    narrowHem.width = l.waistGirth + 0.1;
    narrowHem.hemWidth = narrowHem.width;
    auto fit = fitOn(*world, body, narrowHem);
    ASSERT_FALSE(fit.isOk());
    EXPECT_NE(fit.status().message().find("cannot pass the body below"), std::string::npos) << fit.status().message();
}

TEST(GarmentFit, BodiesGarmentsCannotFitSayWhy) {
    WorldPtr world = makeFittingWorld();
    // A pole carrying a box: a skinned character, but no humanoid.
    Character pole;
    pole.name = "pole";
    pole.skeleton.joints.push_back(Joint{"pole", -1, {}});
    const double corners[8][3] = {{-0.2, 0, -0.1}, {0.2, 0, -0.1}, {0.2, 1.5, -0.1}, {-0.2, 1.5, -0.1},
                                  {-0.2, 0, 0.1},  {0.2, 0, 0.1},  {0.2, 1.5, 0.1},  {-0.2, 1.5, 0.1}};
    for (const auto& p : corners) pole.body.bindPositions.push_back(Vec3(p[0], p[1], p[2]));
    pole.body.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                           {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    pole.body.computeBindNormals();
    pole.body.jointIndices.assign(8, {0, 0, 0, 0});
    pole.body.jointWeights.assign(8, {1, 0, 0, 0});
    pole.body.inverseBindMatrices.assign(1, Mat4::Identity());
    auto body = world->addCharacterBody(pole);
    ASSERT_TRUE(body.isOk()) << "a body garments cannot fit is still a body: " << body.status().message();
    auto fit = fitOn(*world, body.value(), {});
    ASSERT_FALSE(fit.isOk());
    const std::string& m = fit.status().message();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find("no torso found"), std::string::npos) << m;
    EXPECT_NE(m.find("'pole'"), std::string::npos) << "names the body: " << m;
    EXPECT_FALSE(world->bodyLandmarks(body.value()).isOk());

    // Clips: an unknown name lists the body's clips, an index out of range says so.
    const BodyId man = world->addMannequinBody({}).value();
    CharacterDesc c;
    c.body = man;
    c.clip = "moonwalk";
    auto unknown = world->addCharacter(c);
    ASSERT_FALSE(unknown.isOk());
    EXPECT_NE(unknown.status().message().find("'walk'"), std::string::npos) << unknown.status().message();
    c.clip = nullptr;
    c.clipIndex = 3;
    auto outOfRange = world->addCharacter(c);
    ASSERT_FALSE(outOfRange.isOk());
    EXPECT_NE(outOfRange.status().message().find("clipIndex 3 is out of range"), std::string::npos) << outOfRange.status().message();
    c.clip = "RUN";
    c.clipIndex = -1;
    EXPECT_TRUE(world->addCharacter(c).isOk()) << "names match ignoring case";
    EXPECT_EQ(std::string(world->bodyClipName(man, 2).value()), "run");
}

/// Attachment points of a fitted garment, where they start (the body's rest pose).
std::vector<Vec3> attachmentPoints(const detail::FittedGarment& fit) {
    std::vector<Vec3> out;
    for (const detail::PatternPoint& a : fit.attached) {
        const lod::PanelDesc& d = fit.pattern.panels[a.panel];
        out.push_back(fit.placement[a.panel].at(double(a.i) / d.columns, double(a.j) / d.rows));
    }
    return out;
}

TEST(GarmentFit, AttachmentsBindOnlyToTheTorsosSkin) {
    // The mannequin's parts say exactly which skin is torso: every body triangle an attachment is
    // bound to must belong to the torso or the neck, never to an arm, a hand or the head.
    {
        const detail::BodyAsset body = detail::makeMannequinBody({}).value();
        std::vector<std::string> partOf(body.mesh().vertexCount());
        for (const BodyPart& part : body.mannequin.parts)
            for (uint32_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v) partOf[v] = part.name;
        for (GarmentKind kind : test::kGarmentKinds) {
            ClothAssetDesc d;
            d.kind = kind;
            auto fit = detail::fitGarment(d, body);
            ASSERT_TRUE(fit.isOk()) << fit.status().message();
            const std::vector<Vec3> points = attachmentPoints(fit.value());
            EXPECT_GE(points.size(), 3u) << test::kindName(kind);
            auto binding = detail::bindToBody(body, points, {});
            ASSERT_TRUE(binding.isOk()) << binding.status().message();
            for (std::size_t a = 0; a < points.size(); ++a) {
                const auto& t = body.anchorMesh.triangles[binding.value().vertices()[a].triangle];
                for (uint32_t v : t)
                    EXPECT_TRUE(partOf[v] == "torso" || partOf[v] == "neck")
                        << test::kindName(kind) << " attachment " << a << " is bound to the " << partOf[v];
            }
        }
    }
}

/// The shared humanoids found in the shared folder, with their fitted bodies (none when absent).
std::vector<std::pair<std::string, detail::BodyAsset>> sharedHumanoidBodies() {
    std::vector<std::pair<std::string, detail::BodyAsset>> out;
    const fs::path dir = CC_HUMANOIDS_DIR;
    for (const char* name : {"CesiumMan.glb", "RiggedFigure.glb", "RobotExpressive.glb"}) {
        if (!fs::exists(dir / name)) continue;
        auto ch = importCharacter((dir / name).string());
        EXPECT_TRUE(ch.isOk()) << ch.status().message();
        if (!ch.isOk()) continue;
        auto body = detail::makeCharacterBody(ch.value(), {});
        EXPECT_TRUE(body.isOk()) << body.status().message();
        if (body.isOk()) out.emplace_back(name, std::move(body).value());
    }
    return out;
}

TEST(GarmentFit, AttachmentsOnSharedHumanoidsBindToTorsoSkinOnly) {
    const fs::path dir = CC_HUMANOIDS_DIR;
    if (!fs::is_directory(dir)) GTEST_SKIP() << "shared humanoids folder absent: " << dir;
    for (const auto& [name, b] : sharedHumanoidBodies()) {
        ASSERT_TRUE(b.fitStatus.isOk()) << name << ": " << b.fitStatus.message();
        const double h = b.measurements.height;
        for (GarmentKind kind : test::kGarmentKinds) {
            ClothAssetDesc d;
            d.kind = kind;
            auto fit = detail::fitGarment(d, b);
            ASSERT_TRUE(fit.isOk()) << name << ": " << fit.status().message();
            const std::vector<Vec3> points = attachmentPoints(fit.value());
            auto binding = detail::bindToBody(b, points, {});
            ASSERT_TRUE(binding.isOk()) << binding.status().message();
            double nearestArm = 1e300, highest = -1e300;
            for (std::size_t a = 0; a < points.size(); ++a) {
                const BoundVertex& bound = binding.value().vertices()[a];
                // Skin weights of the bound point: all on torso and neck joints.
                double torsoWeight = 0.0;
                for (int k = 0; k < kMaxInfluences; ++k) {
                    const BodyRegion g = b.regions.joints[bound.joints[std::size_t(k)]];
                    if (g == BodyRegion::Torso || g == BodyRegion::Neck) torsoWeight += bound.weights[std::size_t(k)];
                }
                EXPECT_GT(torsoWeight, 0.9 - 1e-9) << name << " " << test::kindName(kind) << " attachment " << a;
                for (std::size_t v = 0; v < b.fitPositions.size(); ++v)
                    if (isArm(b.regions.vertices[v])) nearestArm = std::min(nearestArm, (b.fitPositions[v] - points[a]).norm());
                highest = std::max(highest, points[a].y());
            }
            std::printf("%s %s: %zu attachments, nearest arm skin %.3f m (%.1f %% of the height), highest %.3f m (neck at %.3f)\n",
                        name.c_str(), test::kindName(kind), points.size(), nearestArm, 100.0 * nearestArm / h, highest,
                        b.measurements.neck.height);
            // Over the shoulders the top line keeps clear of the arms (a swinging arm would tear
            // it); a waistband may pass a hanging arm, it is bound to the torso's skin.
            if (kind == GarmentKind::Cape || kind == GarmentKind::Poncho) {
                EXPECT_GE(nearestArm, 0.02 * h - 1e-9) << name << " " << test::kindName(kind);
            }
            EXPECT_GE(points.size(), 3u) << name << " " << test::kindName(kind);
            EXPECT_LT(highest, b.measurements.neck.height + 0.02 * h) << name << " " << test::kindName(kind) << ": nothing on the head";
        }
    }
}

/// Convex hull perimeter of where the plane y = height cuts the triangles (x, z).
double hullPerimeterAt(const std::vector<Vec3>& p, const std::vector<std::array<uint32_t, 3>>& triangles, double height) {
    std::vector<Vec2> points;
    for (const auto& t : triangles)
        for (int e = 0; e < 3; ++e) {
            const Vec3& a = p[t[std::size_t(e)]];
            const Vec3& b = p[t[std::size_t((e + 1) % 3)]];
            if ((a.y() - height) * (b.y() - height) >= 0.0) continue;
            const double s = (height - a.y()) / (b.y() - a.y());
            const Vec3 q = a + s * (b - a);
            points.push_back(Vec2(q.x(), q.z()));
        }
    if (points.size() < 3) return 0.0;
    std::sort(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
    const auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
        return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    std::vector<Vec2> hull(2 * points.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);
    double perimeter = 0.0;
    for (std::size_t i = 0; i < hull.size(); ++i) perimeter += (hull[(i + 1) % hull.size()] - hull[i]).norm();
    return perimeter;
}

TEST(GarmentFit, FlaredSkirtsClearTheLegsInAStride) {
    // Over the walk and the run, the legs at the hem's height need a ring this long round them;
    // an A-line or circle skirt's hem must be longer, a straight one is not.
    const detail::BodyAsset body = detail::makeMannequinBody({}).value();
    const Character& ch = body.character();
    ClothAssetDesc d;
    d.kind = GarmentKind::Skirt;
    d.relativeLength = 0.3;
    const double hemY = body.measurements.waist.height - d.relativeLength * body.measurements.height;
    double need = 0.0;
    CharacterPose pose(ch);
    std::vector<Vec3> posed(ch.body.vertexCount());
    for (std::size_t c = 0; c < ch.clips.size(); ++c) {
        if (ch.clips[c].name != "walk" && ch.clips[c].name != "run") continue;
        for (int k = 0; k < 24; ++k) {
            ASSERT_TRUE(pose.evaluate(ch, int(c), ch.clips[c].duration * k / 24.0, ClipWrap::Loop).isOk());
            ASSERT_TRUE(skinVertices(ch.body, pose.skinMatrices(), posed, {}).isOk());
            // Only the legs: the hands swing at the hem's height too, outside the skirt.
            std::vector<std::array<uint32_t, 3>> legs;
            for (const auto& t : ch.body.triangles)
                if (isLeg(body.regions.vertices[t[0]])) legs.push_back(t);
            need = std::max(need, hullPerimeterAt(posed, legs, hemY));
        }
    }
    std::printf("the legs need %.3f m round at the hem (y = %.3f m)\n", need, hemY);
    for (GarmentCut cut : {GarmentCut::Straight, GarmentCut::ALine, GarmentCut::Circle}) {
        d.cut = cut;
        auto fit = detail::fitGarment(d, body);
        ASSERT_TRUE(fit.isOk()) << fit.status().message();
        const double hem = fit.value().desc.hemWidth;
        std::printf("cut %d: hem %.3f m\n", int(cut), hem);
        if (cut != GarmentCut::Straight) {
            EXPECT_GT(hem, need + 2.0 * M_PI * d.thickness) << "cut " << int(cut);
        }
        // The pattern stays panels of 4-8 base grids, so every level works.
        EXPECT_TRUE(fit.value().pattern.validate().isOk()) << fit.value().pattern.validate().message();
    }
}

/// Whether a clip is a stride: named for walking or running (any case), or a body's only clip.
bool isStrideClip(const Character& ch, std::size_t c) {
    std::string name = ch.clips[c].name;
    for (char& k : name) k = char(std::tolower(static_cast<unsigned char>(k)));
    return ch.clips.size() == 1 || name.find("walk") != std::string::npos ||
           name.find("run") != std::string::npos;
}

// The stride the fit clears is the widest of the body's own clips (CesiumMan's walk reaches 47
// degrees, RobotExpressive's run 68). Checked by posing each body over its walks and runs and
// measuring the ring the legs need at the hem's height, independently of the fit's own stride
// measure: a hem shorter than that ring stretched by the strain limit must stretch past the limit
// or let a knee through. Cut for 30 degrees, CesiumMan's hem was 1.240 m round legs that need
// 1.149 (1.264 with the limit), and its legs tore through the hem on every step.
TEST(GarmentFit, FlaredSkirtsClearTheLegsInTheStridesOfTheirBody) {
    std::vector<std::pair<std::string, detail::BodyAsset>> bodies = sharedHumanoidBodies();
    bodies.emplace(bodies.begin(), "mannequin", detail::makeMannequinBody({}).value());
    for (const auto& [name, body] : bodies) {
        const Character& ch = body.character();
        ClothAssetDesc d;
        d.kind = GarmentKind::Skirt;
        d.cut = GarmentCut::ALine;
        auto fit = detail::fitGarment(d, body);
        ASSERT_TRUE(fit.isOk()) << name << ": " << fit.status().message();
        const double hemY = body.measurements.waist.height - fit.value().desc.length;
        std::vector<std::array<uint32_t, 3>> legs;
        for (const auto& t : ch.body.triangles)
            if (isLeg(body.regions.vertices[t[0]])) legs.push_back(t);
        double need = 0.0;
        CharacterPose pose(ch);
        std::vector<Vec3> posed(ch.body.vertexCount());
        for (std::size_t c = 0; c < ch.clips.size(); ++c) {
            if (!isStrideClip(ch, c)) continue;
            for (int k = 0; k < 48; ++k) {
                ASSERT_TRUE(
                    pose.evaluate(ch, int(c), ch.clips[c].duration * k / 48.0, ClipWrap::Loop)
                        .isOk());
                ASSERT_TRUE(skinVertices(ch.body, pose.skinMatrices(), posed, {}).isOk());
                need = std::max(need, hullPerimeterAt(posed, legs, hemY));
            }
        }
        const double hem = fit.value().desc.hemWidth;
        std::printf("[ stride ] %s: widest stride %.0f degrees; the legs need %.3f m round at the "
                    "hem, the A-line "
                    "skirt's is %.3f m\n",
                    name.c_str(), body.measurements.stride * 180.0 / M_PI, need, hem);
        EXPECT_GT(hem, (1.0 + WorldDesc{}.strainLimit) * need) << name;
    }
}

TEST(GarmentFit, AStrideTheHostGivesWidensTheSkirtsItCuts) {
    // A host-skinned body has no clips to measure a stride from: its host can give one, and the
    // landmarks report the one the clips showed.
    WorldPtr world = makeFittingWorld();
    const BodyId body = world->addMannequinBody({}).value();
    BodyLandmarkDesc l = world->bodyLandmarks(body).value();
    const double measured = l.stride;
    EXPECT_GE(measured, 20.0 * M_PI / 180.0) << "the mannequin's walk and run are strides";
    ClothAssetDesc design;
    design.kind = GarmentKind::Skirt;
    design.cut = GarmentCut::ALine;
    const double hemMeasured = fitOn(*world, body, design).value().hemWidth;
    l.stride = 60.0 * M_PI / 180.0; // wider than the mannequin's own (and the 30 degree floor)
    ASSERT_TRUE(world->setBodyLandmarks(body, l).isOk());
    EXPECT_EQ(world->bodyLandmarks(body).value().stride, l.stride);
    const double hemWide = fitOn(*world, body, design).value().hemWidth;
    std::printf("[ stride ] the mannequin's %.0f degrees: hem %.3f m; given 60: %.3f m\n",
                measured * 180.0 / M_PI, hemMeasured, hemWide);
    EXPECT_GT(hemWide, hemMeasured * 1.05) << "a wider stride needs a wider hem";
    // 0 keeps what is known; a stride out of range is refused by name, and changes nothing.
    l.stride = 0.0;
    ASSERT_TRUE(world->setBodyLandmarks(body, l).isOk());
    EXPECT_EQ(world->bodyLandmarks(body).value().stride, 60.0 * M_PI / 180.0);
    for (double bad : {-0.1, 0.5 * M_PI, std::nan("")}) {
        l.stride = bad;
        const Status refused = world->setBodyLandmarks(body, l);
        EXPECT_FALSE(refused.isOk()) << bad;
        EXPECT_NE(refused.message().find("stride"), std::string::npos) << refused.message();
    }
    EXPECT_EQ(world->bodyLandmarks(body).value().stride, 60.0 * M_PI / 180.0);
}

/// How far the torso and arms of `body`, posed over one walk cycle, need more round than a poncho
/// fitted to it has, at any height down to its hem (negative: the cloth has more).
double ponchoShortfallOverAWalk(const detail::BodyAsset& body, int walk, ClothAssetDesc& outCut) {
    const Character& ch = body.character();
    ClothAssetDesc d;
    d.kind = GarmentKind::Poncho;
    auto fit = detail::fitGarment(d, body);
    EXPECT_TRUE(fit.isOk()) << fit.status().message();
    if (!fit.isOk()) return 0.0;
    outCut = fit.value().desc;
    std::vector<std::array<uint32_t, 3>> torsoArms;
    for (const auto& t : ch.body.triangles) {
        const BodyRegion g = body.regions.vertices[t[0]];
        if (g == BodyRegion::Torso || isArm(g)) torsoArms.push_back(t);
    }
    CharacterPose pose(ch);
    std::vector<Vec3> posed(ch.body.vertexCount());
    double worst = -1e300;
    for (int k = 0; k < 24; ++k) {
        EXPECT_TRUE(pose.evaluate(ch, walk, ch.clips[std::size_t(walk)].duration * k / 24.0, ClipWrap::Loop).isOk());
        EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), posed, {}).isOk());
        const double h = body.measurements.height;
        for (double depth = 0.05 * h; depth <= outCut.length + 1e-9; depth += 0.05 * h) {
            // The cloth's row that far down its slant length lies at least that high: a lower
            // bound of the cloth's circumference at that height.
            const double cloth = outCut.width + (outCut.hemWidth - outCut.width) * depth / outCut.length;
            const double need = hullPerimeterAt(posed, torsoArms, body.measurements.shoulderY - depth);
            worst = std::max(worst, need - cloth);
        }
    }
    return worst;
}

TEST(GarmentFit, PonchosClearTheArmsInTheirSwing) {
    // Over a walk, what hangs from the shoulders must go round the torso and both arms at every
    // height down to its hem, with the arms wherever the walk swings them, though the clip need not
    // hold the arms where the fit did (a rig authored in an A pose is fitted with its arms
    // lowered). A run bends the elbows and swings the forearms up to the chest: they lift a
    // poncho, as they would a real one.
    struct Walker {
        std::string name;
        detail::BodyAsset body;
        int walk = -1;
    };
    std::vector<Walker> walkers;
    {
        Walker w{"mannequin", detail::makeMannequinBody({}).value()};
        for (std::size_t c = 0; c < w.body.character().clips.size(); ++c)
            if (w.body.character().clips[c].name == "walk") w.walk = int(c);
        walkers.push_back(std::move(w));
    }
    const fs::path dir = CC_HUMANOIDS_DIR;
    if (fs::is_directory(dir)) {
        for (const char* name : {"CesiumMan.glb", "RiggedFigure.glb", "RobotExpressive.glb"}) {
            if (!fs::exists(dir / name)) continue;
            auto ch = importCharacter((dir / name).string());
            ASSERT_TRUE(ch.isOk()) << ch.status().message();
            Walker w{name, detail::makeCharacterBody(ch.value(), {}).value()};
            const auto& clips = w.body.character().clips;
            for (std::size_t c = 0; c < clips.size(); ++c)
                if (clips[c].name == "Walking") w.walk = int(c);
            if (w.walk < 0 && !clips.empty()) w.walk = 0;  // the other two play one walk each
            if (w.walk >= 0) walkers.push_back(std::move(w));
        }
    } else {
        std::printf("shared humanoids folder absent (%s): the mannequin only\n", dir.c_str());
    }
    for (const Walker& w : walkers) {
        ClothAssetDesc cut;
        const double worst = ponchoShortfallOverAWalk(w.body, w.walk, cut);
        std::printf("poncho on %s: top %.3f m, hem %.3f m; over the walk the body and arms need at most %.3f m more than the "
                    "cloth has\n",
                    w.name.c_str(), cut.width, cut.hemWidth, worst);
        // The cut allows a 35 degree swing of the upper arms, as much as the mannequin's walk
        // swings them. Imported clips may swing farther (the shared RiggedFigure's walk does, and
        // the long arms of RobotExpressive swing wider than any poncho goes round: its fit falls
        // back to clearing them where they hang): their figures are printed, not asserted.
        if (w.name == "mannequin") {
            EXPECT_LT(worst, 0.0) << w.name << ": the arms swing out of the poncho";
        }
    }
}

/// Largest edge strain of a cooked level where the fit placed it.
double placedStrain(const detail::CookedLevel& level) {
    const cloth::ClothLevel& cloth = *level.cloth;
    const std::vector<Vec3>& x = level.active.mesh.positions;
    double worst = 0.0;
    for (const cloth::LimitedEdge& e : cloth.limitedEdges())
        worst = std::max(worst, (x[cloth.vertexOfNode()[e.b]] - x[cloth.vertexOfNode()[e.a]]).norm() / e.restLength - 1.0);
    return worst;
}

// A garment starts where the fit places it: stretched there, its first step snaps it back at
// metres per second (a circle skirt placed at 320 % strain flew up round the arms; capes and
// ponchos started at 35-66 % on every body, RobotExpressive's cape at 1,138 %). Every kind and
// cut, every level, on the mannequin and on the shared humanoids. Measured after the relaxation:
// 15 % at most on the mannequin; 31 % on RobotExpressive's cape and 25 % on RiggedFigure's
// A-line dress, where rows wrap arms and shoulders wider than the cloth between them allows.
TEST(GarmentFit, PlacedGarmentsStartWithinTheStrainLimit) {
    std::vector<std::pair<std::string, detail::BodyAsset>> bodies = sharedHumanoidBodies();
    bodies.emplace(bodies.begin(), "mannequin", detail::makeMannequinBody({}).value());
    const double limit = 0.35;
    for (const auto& [name, body] : bodies) {
        for (GarmentKind kind : test::kGarmentKinds) {
            for (GarmentCut cut : {GarmentCut::Straight, GarmentCut::ALine, GarmentCut::Circle}) {
                ClothAssetDesc d;
                d.kind = kind;
                d.cut = cut;
                auto cooked = detail::cookFittedGarment(d, body);
                if (!cooked.isOk()) continue;  // a cut that cannot fit this body says so (tested above)
                double worst = 0.0;
                for (const detail::CookedLevel& level : cooked.value().levels) worst = std::max(worst, placedStrain(level));
                std::printf("[ placed ] %s %s cut %d: largest edge strain %.1f %%\n", name.c_str(), test::kindName(kind), int(cut),
                            100.0 * worst);
                EXPECT_LE(worst, limit) << name << " " << test::kindName(kind) << " cut " << int(cut);
            }
        }
    }
}

} // namespace
} // namespace cc
