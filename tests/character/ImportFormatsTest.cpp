// Every skinned format assimp 5.2.5 reads, through the one import gate: files the tests write
// themselves (never downloaded), in each format's own units, up axis, handedness, rotation
// encoding and key rate, must give back the same skinned motion in metres, Y up, seconds; formats
// assimp can write round-trip; truncated and random-byte files of every format give errors that
// name the file (the parser runs isolated, so even one that crashes only costs an error).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "character/FormatRig.h"
#include "fuzz/ImportInput.h"
#include "crowdcloth/import/CharacterIO.h"

namespace cc {
namespace {

namespace fs = std::filesystem;

/// A folder for one test's files, removed with everything in it when the test ends.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / ("cc_formats_" + name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
    std::string operator/(const std::string& file) const { return (path / file).string(); }
};

std::vector<Vec3> skinnedAt(const Character& ch, int clip, double t) {
    CharacterPose pose(ch);
    EXPECT_TRUE(pose.evaluate(ch, clip, t, ClipWrap::Clamp).isOk());
    std::vector<Vec3> p(ch.body.vertexCount());
    EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    return p;
}

/// Largest distance between the rig's skinned vertices and the imported ones (matched by rest
/// position) over the clip, at the same times in seconds; the rest pose alone when `withClip` is
/// false. Also checks the clip's duration.
double gapToRig(const Character& rig, const Character& got, bool withClip, const std::string& what) {
    const std::vector<Vec3> a0 = skinnedAt(rig, -1, 0.0), b0 = skinnedAt(got, -1, 0.0);
    std::vector<std::size_t> match(a0.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < a0.size(); ++i) {
        double best = 1e300;
        for (std::size_t j = 0; j < b0.size(); ++j) {
            const double d = (a0[i] - b0[j]).norm();
            if (d < best) best = d, match[i] = j;
        }
        worst = std::max(worst, best);
    }
    if (!withClip) return worst;
    if (got.clips.empty()) {
        ADD_FAILURE() << what << ": the clip was lost";
        return 1e300;
    }
    EXPECT_NEAR(got.clips[0].duration, rig.clips[0].duration, 1e-3) << what << ": clip length in seconds";
    for (double t : {0.0, 0.2, 0.35, 0.5, 0.8, 1.0}) {
        const std::vector<Vec3> a = skinnedAt(rig, 0, t), b = skinnedAt(got, 0, t);
        for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i] - b[match[i]]).norm());
    }
    return worst;
}

void expectRig(const std::string& file, bool withClip, const std::string& what) {
    const Character rig = test::formatRig();
    Result<Character> r = importCharacter(file);
    ASSERT_TRUE(r.isOk()) << what << ": " << r.status().message();
    const double gap = gapToRig(rig, r.value(), withClip, what);
    std::printf("%s: %zu joints, %zu vertices, %zu clips, largest gap to the rig %.3g m\n", what.c_str(),
                r.value().skeleton.jointCount(), r.value().body.vertexCount(), r.value().clips.size(), gap);
    EXPECT_LT(gap, 1e-4) << what;
}

TEST(ImportFormats, Doom3Md5InchesZUpAtItsFrameRate) {
    TempDir dir("md5");
    test::FileSpace space;
    space.metresPerUnit = 0.0254;
    space.axes = test::zUpAxes();
    test::writeMd5(test::formatRig(), dir / "rig", space);
    expectRig(dir / "rig.md5mesh", true, "md5");
}

TEST(ImportFormats, ValveSmdInchesZUpAt30FramesPerSecond) {
    TempDir dir("smd");
    test::FileSpace space;
    space.metresPerUnit = 0.0254;
    space.axes = test::zUpAxes();
    test::writeSmd(test::formatRig(), dir / "rig.smd", space, true);
    expectRig(dir / "rig.smd", true, "smd");
}

TEST(ImportFormats, Blitz3dLeftHanded) {
    TempDir dir("b3d");
    test::FileSpace space;
    space.axes = Vec3(1.0, 1.0, -1.0).asDiagonal();
    test::writeB3d(test::formatRig(), dir / "rig.b3d", space);
    expectRig(dir / "rig.b3d", true, "b3d");
}

TEST(ImportFormats, OgreXmlWithItsSkeleton) {
    TempDir dir("ogre");
    test::writeOgreXml(test::formatRig(), dir / "rig", "rig.skeleton");
    expectRig(dir / "rig.mesh.xml", true, "ogre xml");
}

TEST(ImportFormats, OpenGexUnitsAndUpAxisFromItsMetrics) {
    TempDir dir("ogex");
    test::FileSpace space;
    space.metresPerUnit = 0.01;
    space.axes = test::zUpAxes();
    test::writeOpenGex(test::formatRig(), dir / "rig.ogex", space, "z");
    expectRig(dir / "rig.ogex", false, "ogex (static)");
}

TEST(ImportFormats, AnimationOnlyFilesAreNoBodies) {
    TempDir dir("bvh");
    test::writeBvh(test::formatRig(), dir / "rig.bvh");
    Result<Character> r = importCharacter(dir / "rig.bvh");
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find(dir / "rig.bvh"), std::string::npos);
    EXPECT_NE(r.status().message().find("animation only"), std::string::npos) << r.status().message();
}

/// The rig written as .glb, read by assimp and written again as `format`.
std::string throughAssimp(const TempDir& dir, const char* format, const char* ext, bool dropClips) {
    const std::string glb = dir / "rig.glb";
    EXPECT_TRUE(exportCharacter(test::formatRig(), glb).isOk());
    Assimp::Importer importer;
    EXPECT_NE(importer.ReadFile(glb, 0), nullptr) << importer.GetErrorString();
    aiScene* scene = importer.GetOrphanedScene();
    if (dropClips) {
        for (unsigned int a = 0; a < scene->mNumAnimations; ++a) delete scene->mAnimations[a];
        delete[] scene->mAnimations;
        scene->mAnimations = nullptr;
        scene->mNumAnimations = 0;
    }
    std::string out = dir / (std::string("rig_") + format + "." + ext);
    Assimp::Exporter exporter;
    EXPECT_EQ(exporter.Export(scene, format, out), aiReturn_SUCCESS) << exporter.GetErrorString();
    delete scene;
    return out;
}

// Every format assimp 5.2.5 writes that can hold a body: skin and clips where its writer keeps
// them (glTF, assbin), skin only where its writer loses them (DirectX writes none; Collada's
// animation output does not read back; ASCII FBX keeps one key per channel; binary FBX does not
// read back at all), the mesh alone for static formats.
TEST(ImportFormats, WritableFormatsRoundTrip) {
    TempDir dir("roundtrip");
    const Character rig = test::formatRig();
    for (const char* ext : {"glb", "gltf"}) {
        const std::string path = dir / (std::string("rig.") + ext);
        ASSERT_TRUE(exportCharacter(rig, path).isOk());
        expectRig(path, true, ext);
    }
    expectRig(throughAssimp(dir, "assbin", "assbin", false), true, "assbin");
    expectRig(throughAssimp(dir, "x", "x", true), false, "x (assimp writes no clips)");
    expectRig(throughAssimp(dir, "collada", "dae", true), false, "collada (skin)");
    {
        // assimp's FBX writer stores metres labelled centimetres: read it as it is meant.
        ImportSettings metres;
        metres.unitScale = 1.0;
        const std::string fbx = throughAssimp(dir, "fbxa", "fbx", true);
        Result<Character> r = importCharacter(fbx, metres);
        ASSERT_TRUE(r.isOk()) << r.status().message();
        EXPECT_LT(gapToRig(rig, r.value(), false, "fbx (skin)"), 1e-4);
    }
    for (const auto& [format, ext] : std::vector<std::pair<const char*, const char*>>{
             {"obj", "obj"}, {"stl", "stl"}, {"stlb", "stl"}, {"ply", "ply"}, {"plyb", "ply"}})
        expectRig(throughAssimp(dir, format, ext, true), false, std::string(format) + " (static)");
}

/// Every file the other tests can make, one per format.
std::vector<std::string> sampleFiles(const TempDir& dir) {
    const Character rig = test::formatRig();
    std::vector<std::string> files;
    test::FileSpace inches;
    inches.metresPerUnit = 0.0254;
    inches.axes = test::zUpAxes();
    test::writeMd5(rig, dir / "rig", inches);
    test::writeSmd(rig, dir / "rig.smd", inches, true);
    test::FileSpace leftHanded;
    leftHanded.axes = Vec3(1.0, 1.0, -1.0).asDiagonal();
    test::writeB3d(rig, dir / "rig.b3d", leftHanded);
    test::writeOgreXml(rig, dir / "rig", "rig.skeleton");
    test::writeOpenGex(rig, dir / "rig.ogex", inches, "z");
    files = {dir / "rig.md5mesh", dir / "rig.smd", dir / "rig.b3d", dir / "rig.mesh.xml", dir / "rig.ogex"};
    for (const char* ext : {"glb", "gltf"}) {
        files.push_back(dir / (std::string("rig.") + ext));
        EXPECT_TRUE(exportCharacter(rig, files.back()).isOk());
    }
    files.push_back(throughAssimp(dir, "assbin", "assbin", false));
    files.push_back(throughAssimp(dir, "x", "x", true));
    files.push_back(throughAssimp(dir, "collada", "dae", true));
    files.push_back(throughAssimp(dir, "fbxa", "fbx", false));
    files.push_back(throughAssimp(dir, "stlb", "stl", true));
    files.push_back(throughAssimp(dir, "plyb", "ply", true));
    for (const std::string& f : files) EXPECT_TRUE(importCharacter(f).isOk()) << f << " does not even read whole";
    return files;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void expectNamedError(const Result<Character>& r, const std::string& path, const std::string& why) {
    ASSERT_FALSE(r.isOk()) << path << " (" << why << ") was accepted";
    EXPECT_EQ(r.status().message().rfind(path, 0), 0u) << "the error starts with the file: " << r.status().message();
}

// Cut short, a file of any format is refused naming it: by the gate's structure checks for the
// binary formats (chunks, counts, declared lengths), by the parser for the text formats (their
// closing braces, tags and "end"s are gone). A cut exactly at a line break of a text format can
// leave a complete smaller file; the cuts here fall inside the text.
TEST(ImportFormats, TruncatedFilesOfEveryFormatGiveErrorsNamingTheFile) {
    TempDir dir("truncated");
    for (const std::string& file : sampleFiles(dir)) {
        const std::string bytes = readBytes(file);
        for (double fraction : {0.03, 0.37, 0.71, 0.96}) {
            std::size_t cut = std::size_t(double(bytes.size()) * fraction);
            // Inside a token of a text file, never just after a line break.
            while (cut > 1 && (bytes[cut - 1] == '\n' || bytes[cut - 1] == '\r')) --cut;
            const std::string path = dir / ("cut" + std::to_string(int(100 * fraction)) + "_" + file.substr(file.find_last_of('/') + 1));
            std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(cut));
            // The .md5anim and .skeleton.xml beside a cut .md5mesh / .mesh.xml stay whole.
            if (path.size() > 8 && path.compare(path.size() - 8, 8, ".md5mesh") == 0)
                fs::copy_file(dir / "rig.md5anim", path.substr(0, path.size() - 4) + "anim", fs::copy_options::overwrite_existing);
            expectNamedError(importCharacter(path), path, "cut at " + std::to_string(cut) + " of " + std::to_string(bytes.size()));
        }
    }
}

TEST(ImportFormats, RandomBytesOfEveryFormatGiveErrorsNamingTheFile) {
    TempDir dir("random");
    std::mt19937 rng(11);
    const std::vector<std::string> files = sampleFiles(dir);
    for (const std::string& file : files) {
        const std::string name = file.substr(file.find_last_of('/') + 1);
        const std::string ext = name.substr(name.find('.'));
        const std::string original = readBytes(file);
        for (int trial = 0; trial < 3; ++trial) {
            // Pure noise, then noise behind the format's first 32 bytes (past its magic).
            const std::size_t n = 64u << (3 * trial);
            std::string noise(n, '\0');
            for (char& c : noise) c = char(rng() & 0xff);
            const std::string pure = dir / ("noise" + std::to_string(trial) + ext);
            std::ofstream(pure, std::ios::binary) << noise;
            expectNamedError(importCharacter(pure), pure, "random bytes");
            const std::string signed_ = dir / ("signed" + std::to_string(trial) + ext);
            std::ofstream(signed_, std::ios::binary) << original.substr(0, std::min<std::size_t>(32, original.size())) << noise;
            expectNamedError(importCharacter(signed_), signed_, "random bytes behind a signature");
        }
    }
}

// The import fuzzer's seeds (tests/fuzz/import_corpus) are the sample files of every format that
// is one file on its own, and each reads whole: a fuzz run starts from real files of every format.
// CC_REWRITE_IMPORT_SEEDS=1 in the environment writes them anew first.
TEST(ImportFormats, TheImportFuzzersSeedsAreSampleFilesThatReadWhole) {
    TempDir dir("seeds");
    std::vector<std::string> files = sampleFiles(dir);
    files.push_back(throughAssimp(dir, "obj", "obj", true));
    const fs::path seeds = CC_IMPORT_SEEDS_DIR;
    const bool rewrite = std::getenv("CC_REWRITE_IMPORT_SEEDS") != nullptr;
    int checked = 0;
    for (const std::string& file : files) {
        const std::string name = fs::path(file).filename().string();
        const std::string ext = name.substr(name.find('.') + 1);
        // Formats that come in several files (mesh + clips, skeleton, buffers) cannot be one input.
        if (ext == "md5mesh" || ext == "mesh.xml" || ext == "gltf") continue;
        const fs::path seed = seeds / ("seed-" + ext);
        if (rewrite) {
            const std::string input = fuzz::encodeImportInput(ext, readBytes(file));
            ASSERT_FALSE(input.empty()) << ext << " is not in the fuzzer's extension table";
            std::ofstream(seed, std::ios::binary) << input;
        }
        const std::string bytes = readBytes(seed.string());
        ASSERT_FALSE(bytes.empty()) << seed << " is missing (CC_REWRITE_IMPORT_SEEDS=1 writes it)";
        const fuzz::ImportInput in =
            fuzz::decodeImportInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
        EXPECT_EQ(in.extension, ext) << seed;
        const std::string path = dir / (std::string("seed.") + in.extension);
        std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(in.bytes), std::streamsize(in.size));
        const Result<Character> r = importCharacter(path);
        EXPECT_TRUE(r.isOk()) << seed << ": " << r.status().message();
        ++checked;
    }
    EXPECT_GE(checked, 11) << "a seed per single-file format";
}

TEST(ImportFormats, AFileNotWhatItsExtensionSaysIsRefused) {
    TempDir dir("mismatch");
    const std::string glb = dir / "rig.glb";
    ASSERT_TRUE(exportCharacter(test::formatRig(), glb).isOk());
    for (const char* ext : {"b3d", "md5mesh", "smd", "x", "ms3d", "mesh.xml", "stl", "fbx"}) {
        const std::string path = dir / (std::string("really_glb.") + ext);
        fs::copy_file(glb, path);
        expectNamedError(importCharacter(path), path, "a .glb renamed");
    }
    const std::string unknown = dir / "rig.xyz";
    fs::copy_file(glb, unknown);
    Result<Character> r = importCharacter(unknown);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("unsupported format '.xyz'"), std::string::npos) << r.status().message();
}

TEST(ImportFormats, ForcedUnitsAxesAndKeyRatesWin) {
    TempDir dir("forced");
    test::writeSmd(test::formatRig(), dir / "rig.smd", test::FileSpace{}, true);  // metres, Y up
    ImportSettings asIs;
    asIs.unitScale = 1.0;
    asIs.upAxis = ImportUpAxis::Y;
    asIs.ticksPerSecond = 30.0;
    Result<Character> r = importCharacter(dir / "rig.smd", asIs);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_LT(gapToRig(test::formatRig(), r.value(), true, "smd forced"), 1e-4);
    ImportSettings bad;
    bad.ticksPerSecond = -1.0;
    EXPECT_NE(importCharacter(dir / "rig.smd", bad).status().message().find("ticksPerSecond"), std::string::npos);
}

} // namespace
} // namespace cc
