#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/import/CharacterIO.h"

namespace cc {
namespace {

namespace fs = std::filesystem;

fs::path tempDirPath() { return fs::temp_directory_path() / ("cc_import_tests_" + std::to_string(::getpid())); }

fs::path tempDir() {
    fs::path dir = tempDirPath();
    fs::create_directories(dir);
    return dir;
}

/// Removes the tests' folder (and every file in it) when the suite ends.
class TempDirCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(tempDirPath(), ignored);
    }
};
const ::testing::Environment* const kCleanup = ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

Mannequin mannequin() {
    Result<Mannequin> m = buildMannequin();
    EXPECT_TRUE(m.isOk()) << m.status().message();
    return std::move(m).value();
}

std::vector<Vec3> skinnedAt(const Character& ch, int clip, double t) {
    CharacterPose pose(ch);
    EXPECT_TRUE(pose.evaluate(ch, clip, t, ClipWrap::Clamp).isOk());
    std::vector<Vec3> p(ch.body.vertexCount());
    EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    return p;
}

// For each vertex of `a`, the vertex of `b` at the same bind position (brute force).
std::vector<std::size_t> matchVertices(const SkinnedMesh& a, const SkinnedMesh& b, double& outWorst) {
    std::vector<std::size_t> match(a.vertexCount());
    outWorst = 0.0;
    for (std::size_t i = 0; i < a.vertexCount(); ++i) {
        double best = 1e300;
        for (std::size_t j = 0; j < b.vertexCount(); ++j) {
            const double d = (a.bindPositions[i] - b.bindPositions[j]).squaredNorm();
            if (d < best) {
                best = d;
                match[i] = j;
            }
        }
        outWorst = std::max(outWorst, std::sqrt(best));
    }
    return match;
}

void expectRoundTrip(const std::string& extension) {
    const Mannequin m = mannequin();
    const Character& original = m.character;
    const fs::path file = tempDir() / ("mannequin." + extension);
    Status s = exportCharacter(original, file.string());
    ASSERT_TRUE(s.isOk()) << s.message();
    Result<Character> read = importCharacter(file.string());
    ASSERT_TRUE(read.isOk()) << read.status().message();
    const Character& back = read.value();
    // The mannequin has no two vertices with equal position and normal, so joining keeps them all.
    EXPECT_EQ(back.body.vertexCount(), original.body.vertexCount()) << extension;
    EXPECT_EQ(back.body.triangles.size(), original.body.triangles.size()) << extension;
    double bindGap = 0.0;
    const std::vector<std::size_t> match = matchVertices(original.body, back.body, bindGap);
    EXPECT_LT(bindGap, 1e-5) << extension;
    ASSERT_EQ(back.clips.size(), original.clips.size()) << extension;
    for (std::size_t c = 0; c < original.clips.size(); ++c) {
        const int bc = back.findClip(original.clips[c].name);
        ASSERT_GE(bc, 0) << extension << ": clip " << original.clips[c].name << " lost";
        EXPECT_NEAR(back.clips[static_cast<std::size_t>(bc)].duration, original.clips[c].duration, 1e-3) << extension;
        double worst = 0.0;
        for (double f : {0.0, 0.13, 0.37, 0.5, 0.81, 1.0}) {
            const double t = f * original.clips[c].duration;
            const std::vector<Vec3> a = skinnedAt(original, static_cast<int>(c), t);
            const std::vector<Vec3> b = skinnedAt(back, bc, t);
            for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, (a[v] - b[match[v]]).norm());
        }
        std::printf("%s round trip, clip %s: worst skinned gap %.3g m\n", extension.c_str(),
                    original.clips[c].name.c_str(), worst);
        EXPECT_LT(worst, 1e-4) << extension << " clip " << original.clips[c].name;
    }
}

TEST(Import, MannequinRoundTripsThroughGlb) { expectRoundTrip("glb"); }
TEST(Import, MannequinRoundTripsThroughGltf) { expectRoundTrip("gltf"); }

// Writes the mannequin as .glb, reads it back with assimp, drops the clips (assimp 5.2.5 cannot
// carry skinned animation through its FBX and Collada writers) and writes `format`.
std::string convertWithAssimp(const Character& ch, const std::string& ext, const char* format) {
    const fs::path dir = tempDir();
    const std::string glb = (dir / "for_conversion.glb").string();
    EXPECT_TRUE(exportCharacter(ch, glb).isOk());
    Assimp::Importer importer;
    EXPECT_NE(importer.ReadFile(glb, 0), nullptr) << importer.GetErrorString();
    aiScene* scene = importer.GetOrphanedScene();
    for (unsigned int a = 0; a < scene->mNumAnimations; ++a) delete scene->mAnimations[a];
    delete[] scene->mAnimations;
    scene->mAnimations = nullptr;
    scene->mNumAnimations = 0;
    std::string out = (dir / ("converted." + ext)).string();
    Assimp::Exporter exporter;
    EXPECT_EQ(exporter.Export(scene, format, out), aiReturn_SUCCESS) << exporter.GetErrorString();
    delete scene;
    return out;
}

// The same pose (a few joints turned, by name) skins both characters alike.
void expectSamePosedSkin(const Character& a, const Character& b, const char* what) {
    double bindGap = 0.0;
    const std::vector<std::size_t> match = matchVertices(a.body, b.body, bindGap);
    EXPECT_LT(bindGap, 1e-5) << what;
    CharacterPose pa(a), pb(b);
    const std::vector<std::pair<const char*, Quat>> turns = {
        {"thigh_l", Quat(Eigen::AngleAxisd(-0.7, Vec3::UnitX()))},
        {"forearm_r", Quat(Eigen::AngleAxisd(-1.1, Vec3::UnitX()))},
        {"hips", Quat(Eigen::AngleAxisd(0.4, Vec3::UnitY()))},
        {"head", Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()))}};
    for (const auto& [name, q] : turns) {
        const int32_t ja = a.skeleton.findJoint(name), jb = b.skeleton.findJoint(name);
        ASSERT_GE(ja, 0) << name;
        ASSERT_GE(jb, 0) << what << ": joint " << name << " lost";
        pa.localPose()[static_cast<std::size_t>(ja)].rotation = q * pa.localPose()[static_cast<std::size_t>(ja)].rotation;
        pb.localPose()[static_cast<std::size_t>(jb)].rotation = q * pb.localPose()[static_cast<std::size_t>(jb)].rotation;
    }
    pa.update(a);
    pb.update(b);
    std::vector<Vec3> xa(a.body.vertexCount()), xb(b.body.vertexCount());
    ASSERT_TRUE(skinVertices(a.body, pa.skinMatrices(), xa, {}).isOk());
    ASSERT_TRUE(skinVertices(b.body, pb.skinMatrices(), xb, {}).isOk());
    double worst = 0.0;
    for (std::size_t v = 0; v < xa.size(); ++v) worst = std::max(worst, (xa[v] - xb[match[v]]).norm());
    std::printf("%s: posed skin gap %.3g m\n", what, worst);
    EXPECT_LT(worst, 1e-4) << what;
}

TEST(Import, FbxSkinAndSkeletonMatchTheMannequin) {
    const Mannequin m = mannequin();
    const std::string fbx = convertWithAssimp(m.character, "fbx", "fbxa");
    // assimp's FBX writer stores metres but labels them centimetres (UnitScaleFactor 1), so by
    // the FBX convention the file holds a 1.8 cm mannequin; forcing the unit gives it back.
    Result<Character> asFile = importCharacter(fbx);
    ASSERT_TRUE(asFile.isOk()) << asFile.status().message();
    double hi = 0.0;
    for (const Vec3& p : asFile.value().body.bindPositions) hi = std::max(hi, p.y());
    EXPECT_NEAR(hi, 0.018, 1e-4) << "UnitScaleFactor (cm per unit) applied";
    ImportSettings metres;
    metres.unitScale = 1.0;
    Result<Character> r = importCharacter(fbx, metres);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    expectSamePosedSkin(m.character, r.value(), "fbx");
}

// The same file declared Z up, front -Y, in metres (UnitScaleFactor 100 cm per unit): the
// importer turns it to Y up, so every posed vertex is the original rotated by file Z -> +Y.
TEST(Import, FbxAxisAndUnitMetadataAreApplied) {
    const Mannequin m = mannequin();
    const std::string fbx = convertWithAssimp(m.character, "fbx", "fbxa");
    std::ifstream in(fbx);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const auto patch = [&](const std::string& from, const std::string& to) {
        const auto at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
    };
    patch("\"UpAxis\", \"int\", \"Integer\", \"\", 1", "\"UpAxis\", \"int\", \"Integer\", \"\", 2");
    patch("\"FrontAxis\", \"int\", \"Integer\", \"\", 2", "\"FrontAxis\", \"int\", \"Integer\", \"\", 1");
    patch("\"FrontAxisSign\", \"int\", \"Integer\", \"\", 1", "\"FrontAxisSign\", \"int\", \"Integer\", \"\", -1");
    patch("\"UnitScaleFactor\", \"double\", \"Number\", \"\", 1", "\"UnitScaleFactor\", \"double\", \"Number\", \"\", 100");
    const std::string zUp = (tempDir() / "z_up.fbx").string();
    std::ofstream(zUp) << text;
    Result<Character> r = importCharacter(zUp);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    // Expected: (x, y, z) -> (x, z, -y) applied to the original mannequin.
    Character rotated = m.character;
    Mat3 rot;
    rot << 1, 0, 0, 0, 0, 1, 0, -1, 0;
    ASSERT_TRUE(changeBasis(rotated, 1.0, rot).isOk());
    expectSamePosedSkin(rotated, r.value(), "fbx z-up");
}

TEST(Import, ColladaSkinAndSkeletonMatchTheMannequin) {
    const Mannequin m = mannequin();
    const std::string dae = convertWithAssimp(m.character, "dae", "collada");
    Result<Character> r = importCharacter(dae);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    expectSamePosedSkin(m.character, r.value(), "collada");
}

TEST(Import, SharedHumanoidsLoadAndAnimate) {
    const fs::path dir = CC_HUMANOIDS_DIR;
    if (!fs::is_directory(dir)) GTEST_SKIP() << "shared humanoids folder absent: " << dir;
    for (const char* name : {"CesiumMan.glb", "RiggedFigure.glb", "RobotExpressive.glb"}) {
        const fs::path file = dir / name;
        if (!fs::exists(file)) {
            ADD_FAILURE() << file << " missing from the shared folder";
            continue;
        }
        Result<Character> r = importCharacter(file.string());
        ASSERT_TRUE(r.isOk()) << r.status().message();
        const Character& ch = r.value();
        ASSERT_FALSE(ch.clips.empty()) << name;
        // Rest-pose height: the assets are 1.5 m (CesiumMan, RiggedFigure) and 4.5 m
        // (RobotExpressive, authored at that size); every pose stays within a sane band of it.
        const auto height = [](const std::vector<Vec3>& p) {
            double lo = 1e9, hi = -1e9;
            for (const Vec3& q : p) {
                lo = std::min(lo, q.y());
                hi = std::max(hi, q.y());
            }
            return hi - lo;
        };
        const double rest = height(skinnedAt(ch, -1, 0.0));
        EXPECT_GT(rest, 1.0) << name;
        EXPECT_LT(rest, 5.0) << name;
        double minH = 1e9, maxH = 0.0, maxMotion = 0.0;
        for (std::size_t c = 0; c < ch.clips.size(); ++c) {
            const std::vector<Vec3> first = skinnedAt(ch, static_cast<int>(c), 0.0);
            for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) {
                const std::vector<Vec3> p = skinnedAt(ch, static_cast<int>(c), f * ch.clips[c].duration);
                for (std::size_t v = 0; v < p.size(); ++v) {
                    ASSERT_TRUE(isFinite(p[v])) << name << " clip " << ch.clips[c].name << " vertex " << v;
                    maxMotion = std::max(maxMotion, (p[v] - first[v]).norm());
                }
                minH = std::min(minH, height(p));
                maxH = std::max(maxH, height(p));
            }
        }
        std::printf("%s: %zu vertices, %zu triangles, %zu joints, %zu clips, rest height %.2f, posed %.2f-%.2f, "
                    "motion %.2f (file units = m)\n", name, ch.body.vertexCount(), ch.body.triangles.size(),
                    ch.skeleton.jointCount(), ch.clips.size(), rest, minH, maxH, maxMotion);
        EXPECT_GT(minH, 0.3 * rest) << name;
        EXPECT_LT(maxH, 1.5 * rest) << name;
        EXPECT_GT(maxMotion, 0.05) << name << " does not animate";
    }
}

TEST(Import, JoinIdenticalVerticesChangesCesiumManCount) {
    const fs::path file = fs::path(CC_HUMANOIDS_DIR) / "CesiumMan.glb";
    if (!fs::exists(file)) GTEST_SKIP() << "shared humanoids folder absent: " << file;
    ImportSettings joined, raw;
    raw.joinIdenticalVertices = false;
    Result<Character> a = importCharacter(file.string(), joined);
    Result<Character> b = importCharacter(file.string(), raw);
    ASSERT_TRUE(a.isOk() && b.isOk());
    // ECOSYSTEM.md pitfall 15: 3273 vertices in the file, 2612 after joining.
    EXPECT_EQ(a.value().body.vertexCount(), 2612u);
    EXPECT_EQ(b.value().body.vertexCount(), 3273u);
}

void expectError(const Result<Character>& r, const std::string& path, const std::string& fragment) {
    ASSERT_FALSE(r.isOk()) << path << " was accepted";
    EXPECT_NE(r.status().message().find(path), std::string::npos) << r.status().message();
    if (!fragment.empty()) {
        EXPECT_NE(r.status().message().find(fragment), std::string::npos) << r.status().message();
    }
}

TEST(Import, MissingEmptyAndUnsupportedFilesAreNamed) {
    const fs::path dir = tempDir();
    const std::string missing = (dir / "nope.glb").string();
    expectError(importCharacter(missing), missing, "not found");
    const std::string empty = (dir / "empty.glb").string();
    std::ofstream(empty).close();
    expectError(importCharacter(empty), empty, "empty");
    const std::string unknown = (dir / "thing.xyz").string();
    std::ofstream(unknown) << "v 0 0 0\n";
    expectError(importCharacter(unknown), unknown, "unsupported");
    const std::string obj = (dir / "thing.obj").string();
    std::ofstream(obj) << "v 0 0 0\n";
    expectError(importCharacter(obj), obj, "");  // a supported format, but no triangle in it
    expectError(importCharacter(dir.string()), dir.string(), "regular file");
}

TEST(Import, RandomBytesGiveErrorsNamingTheFile) {
    const fs::path dir = tempDir();
    std::mt19937 rng(5);
    for (const char* ext : {"glb", "gltf", "fbx", "dae"}) {
        for (int trial = 0; trial < 3; ++trial) {
            const std::string path = (dir / ("random" + std::to_string(trial) + "." + ext)).string();
            std::ofstream out(path, std::ios::binary);
            const std::size_t n = 64u << (3 * trial);
            for (std::size_t i = 0; i < n; ++i) out.put(static_cast<char>(rng() & 0xff));
            out.close();
            expectError(importCharacter(path), path, "");
        }
    }
    // Random bytes behind a valid signature reach assimp's parsers, which must fail cleanly too.
    for (const auto& [ext, header] : std::vector<std::pair<std::string, std::string>>{
             {"gltf", "{\"asset\":{\"version\":\"2.0\"},"}, {"dae", "<?xml version=\"1.0\"?><COLLADA "},
             {"fbx", std::string("Kaydara FBX Binary  \0\x1a\0", 23)}}) {
        const std::string path = (dir / ("signed_random." + ext)).string();
        std::ofstream out(path, std::ios::binary);
        out << header;
        for (int i = 0; i < 4096; ++i) out.put(static_cast<char>(rng() & 0xff));
        out.close();
        expectError(importCharacter(path), path, "");
    }
}

TEST(Import, TruncatedFilesGiveErrorsNamingTheFile) {
    const Mannequin m = mannequin();
    const fs::path dir = tempDir();
    for (const char* ext : {"glb", "gltf", "fbx", "dae"}) {
        fs::path full = dir / (std::string("full.") + ext);
        if (std::string(ext) == "fbx" || std::string(ext) == "dae") {
            full = convertWithAssimp(m.character, ext, std::string(ext) == "fbx" ? "fbxa" : "collada");
        } else {
            ASSERT_TRUE(exportCharacter(m.character, full.string()).isOk()) << ext;
        }
        std::ifstream in(full, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        for (double fraction : {0.02, 0.5, 0.97}) {
            const std::string path = (dir / ("cut" + std::to_string(static_cast<int>(fraction * 100)) + "." + ext)).string();
            std::ofstream out(path, std::ios::binary);
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() * fraction));
            out.close();
            // A .gltf keeps its buffers in the .bin beside it; cutting the JSON must still fail.
            expectError(importCharacter(path), path, "");
        }
    }
    // A .gltf whose .bin is cut short.
    const fs::path gltf = dir / "full.gltf";
    const fs::path bin = dir / "full.bin";
    if (fs::exists(bin)) {
        fs::resize_file(bin, fs::file_size(bin) / 2);
        expectError(importCharacter(gltf.string()), gltf.string(), "");
    }
}

// A one-triangle scene whose skin weights sum to 0.5, written with assimp's own exporter.
TEST(Import, WeightsNotSummingToOneAreRejected) {
    const fs::path dir = tempDir();
    const std::string path = (dir / "half_weights.glb").string();
    {
        // Each object goes into its owner's array as it is made: ~aiScene deletes the tree.
        aiScene scene;
        scene.mRootNode = new aiNode("root");
        scene.mRootNode->mNumChildren = 2;
        scene.mRootNode->mChildren = new aiNode*[2]{};
        aiNode* boneNode = scene.mRootNode->mChildren[0] = new aiNode("bone");
        aiNode* meshNode = scene.mRootNode->mChildren[1] = new aiNode("mesh");
        meshNode->mNumMeshes = 1;
        meshNode->mMeshes = new unsigned int[1]{0};
        boneNode->mParent = scene.mRootNode;
        meshNode->mParent = scene.mRootNode;
        scene.mNumMeshes = 1;
        scene.mMeshes = new aiMesh*[1]{};
        aiMesh* mesh = scene.mMeshes[0] = new aiMesh();
        mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
        mesh->mNumVertices = 3;
        mesh->mVertices = new aiVector3D[3]{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        mesh->mNormals = new aiVector3D[3]{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
        mesh->mNumFaces = 1;
        mesh->mFaces = new aiFace[1];
        mesh->mFaces[0].mNumIndices = 3;
        mesh->mFaces[0].mIndices = new unsigned int[3]{0, 1, 2};
        mesh->mNumBones = 1;
        mesh->mBones = new aiBone*[1]{};
        aiBone* bone = mesh->mBones[0] = new aiBone();
        bone->mName = aiString("bone");
        bone->mNumWeights = 3;
        bone->mWeights = new aiVertexWeight[3]{{0, 0.5f}, {1, 0.5f}, {2, 0.5f}};
        scene.mNumMaterials = 1;
        scene.mMaterials = new aiMaterial*[1]{};
        scene.mMaterials[0] = new aiMaterial();
        Assimp::Exporter exporter;
        ASSERT_EQ(exporter.Export(&scene, "glb2", path), aiReturn_SUCCESS) << exporter.GetErrorString();
    }
    expectError(importCharacter(path), path, "sum to 0.5");
    // With weights summing to 1 the same scene is accepted (the test above is not vacuous).
    ImportSettings lenient;
    lenient.weightSumTolerance = 0.5;
    EXPECT_TRUE(importCharacter(path, lenient).isOk());
}

TEST(Import, ExportRefusesBadCharactersAndFormats) {
    Mannequin m = mannequin();
    const fs::path dir = tempDir();
    const std::string obj = (dir / "x.obj").string();
    Status s = exportCharacter(m.character, obj);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find(obj), std::string::npos);
    m.character.body.jointWeights[0] = {0.3, 0, 0, 0};
    const std::string glb = (dir / "bad.glb").string();
    s = exportCharacter(m.character, glb);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("vertex 0"), std::string::npos) << s.message();
}

} // namespace
} // namespace cc
