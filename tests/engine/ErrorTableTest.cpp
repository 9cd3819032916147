// Error tables (crowdcloth/ErrorTable.h): measured per design, exact on disk, keyed to what they
// measure, cooked deterministically, and what the scheduler predicts from once handed to a World.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/ErrorTable.h"
#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

/// A table of `levels` levels, every error `perRadius` (the median half of it).
ErrorTable uniformTable(uint32_t levels, double perRadius) {
    ErrorTable t;
    t.windows = 4;
    t.errorPerRadius.assign(levels * ErrorTable::kMotions, perRadius);
    t.medianErrorPerRadius.assign(levels * ErrorTable::kMotions, 0.5 * perRadius);
    return t;
}

/// A small design and a cook short enough for a test (2 windows per motion, a light reference).
ClothAssetDesc smallCape() {
    ClothAssetDesc d;
    d.levelCount = 2;
    d.renderLevel = 2;
    d.cellSize = 0.25;
    return d;
}
ErrorCookDesc shortCook() {
    ErrorCookDesc c;
    c.seconds = 1.0;
    c.referenceSubsteps = 8;
    c.referenceIterations = 4;
    return c;
}

bool contains(const Status& s, const std::string& part) { return s.message().find(part) != std::string::npos; }

TEST(ErrorTable, TextReadsBackBitForBit) {
    ErrorTable t = uniformTable(3, 0.0);
    const double awkward[] = {0.1, 1.0 / 3.0, 1e-300, 0.0, 7.25, 2.0 / 7.0};
    for (std::size_t k = 0; k < t.errorPerRadius.size(); ++k) {
        t.errorPerRadius[k] = awkward[k];
        t.medianErrorPerRadius[k] = awkward[k] / 3.0;
    }
    t.key = 0x0123456789abcdefull;
    t.cook.seconds = 2.5;
    t.speeds[0] = 0.1;
    t.windows = 17;
    const std::string text = t.toText();
    auto back = ErrorTable::fromText(text);
    ASSERT_TRUE(back.isOk()) << back.status().message();
    EXPECT_EQ(back.value().key, t.key);
    EXPECT_EQ(back.value().errorPerRadius, t.errorPerRadius);
    EXPECT_EQ(back.value().medianErrorPerRadius, t.medianErrorPerRadius);
    EXPECT_EQ(back.value().speeds[0], t.speeds[0]);
    EXPECT_EQ(back.value().cook.seconds, 2.5);
    EXPECT_EQ(back.value().windows, 17u);
    EXPECT_EQ(back.value().toText(), text);
}

TEST(ErrorTable, BadTextIsRefusedNamingWhat) {
    const std::string good = uniformTable(2, 0.1).toText();
    EXPECT_TRUE(ErrorTable::fromText(good).isOk());
    EXPECT_TRUE(contains(ErrorTable::fromText("").status(), "not an error table"));
    EXPECT_TRUE(contains(ErrorTable::fromText("hello world").status(), "not an error table"));
    std::string later = good;
    later.replace(later.find(" 1\n"), 3, " 9\n");
    EXPECT_TRUE(contains(ErrorTable::fromText(later).status(), "format version 9"));
    // Cut anywhere, even inside the last number (which would still read as one): refused.
    for (std::size_t keep = 0; keep + 1 < good.size(); keep += 7) {
        const Status cut = ErrorTable::fromText(good.substr(0, keep)).status();
        EXPECT_FALSE(cut.isOk()) << "kept " << keep << " of " << good.size();
    }
    EXPECT_TRUE(contains(ErrorTable::fromText(good.substr(0, good.size() - 4)).status(), "truncated"));
    EXPECT_TRUE(contains(ErrorTable::fromText(good.substr(0, good.find("\nlevel ") + 1)).status(), "level 0"));
    std::string nan = good;
    const std::string tenth = "0x1.999999999999ap-4";  // 0.1, the first level's first error
    ASSERT_NE(nan.find(tenth), std::string::npos);
    nan.replace(nan.find(tenth), tenth.size(), "nan");
    EXPECT_TRUE(contains(ErrorTable::fromText(nan).status(), "finite and >= 0"));
    std::string word = good;
    word.replace(word.find(tenth), tenth.size(), "lots");
    EXPECT_TRUE(contains(ErrorTable::fromText(word).status(), "not a number: lots"));
    std::string hugeCount = good;
    hugeCount.replace(hugeCount.find(" 64 40\n"), 7, " -1e300 40\n");
    EXPECT_TRUE(contains(ErrorTable::fromText(hugeCount).status(), "must be counts"));
    ErrorTable negative = uniformTable(2, 0.1);
    negative.errorPerRadius[3] = -0.1;
    EXPECT_TRUE(contains(negative.validate(), "finite and >= 0"));
    EXPECT_TRUE(contains(ErrorTable::fromText(negative.toText()).status(), "finite and >= 0"));
    ErrorTable backwards = uniformTable(2, 0.1);
    backwards.speeds[1] = backwards.speeds[0];
    EXPECT_TRUE(contains(backwards.validate(), "ascending"));
    ErrorTable ragged = uniformTable(2, 0.1);
    ragged.errorPerRadius.pop_back();
    EXPECT_TRUE(contains(ragged.validate(), "levels x 2"));
}

TEST(ErrorTable, DamagedTextReadsAsATableOrAnErrorNeverACrash) {
    // A cache file is input: mutated copies of a valid text (bytes flipped, cut, spliced; under
    // ASan + UBSan in CI) must give a valid table or an error, never a crash or undefined behaviour.
    const std::string good = uniformTable(3, 0.1).toText();
    std::mt19937 rng(12345);
    int accepted = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::string text = good;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 4) {
            case 0: text[at] = char(rng() % 256); break;
            case 1: text.erase(at, 1 + rng() % 8); break;
            case 2: text.insert(at, std::string(1 + rng() % 3, "0123456789abcdefxp.-+e \n"[rng() % 25])); break;
            default: text.resize(at); break;
            }
            if (text.empty()) text = "x";
        }
        auto read = ErrorTable::fromText(text);
        if (read.isOk()) {
            ++accepted;
            EXPECT_TRUE(read.value().validate().isOk());
        } else {
            EXPECT_FALSE(read.status().message().empty());
        }
    }
    EXPECT_LT(accepted, 3000) << "some damage must be caught";
}

TEST(ErrorTable, FitNonIncreasingPoolsAdjacentViolators) {
    ErrorTable t = uniformTable(4, 0.0);
    const double walk[] = {0.3, 0.1, 0.2, 0.05}, run[] = {0.4, 0.3, 0.2, 0.1};
    for (uint32_t l = 0; l < 4; ++l) t.errorPerRadius[2 * l] = walk[l], t.errorPerRadius[2 * l + 1] = run[l];
    const ErrorTable fit = t.nonIncreasingInLevel();
    const double walkFit[] = {0.3, 0.15, 0.15, 0.05};
    for (uint32_t l = 0; l < 4; ++l) {
        EXPECT_DOUBLE_EQ(fit.error(l, 0), walkFit[l]) << "level " << l;
        EXPECT_EQ(fit.error(l, 1), run[l]) << "already non-increasing: unchanged";
    }
    // Everything increasing pools into one mean.
    for (uint32_t l = 0; l < 4; ++l) t.errorPerRadius[2 * l] = 0.1 * (l + 1);
    for (uint32_t l = 0; l < 4; ++l) EXPECT_DOUBLE_EQ(t.nonIncreasingInLevel().error(l, 0), 0.25);
}

TEST(ErrorTable, KeyNamesTheDesignTheEffortAndTheCook) {
    const ClothAssetDesc design;
    const WorldDesc world;
    const ErrorCookDesc cook;
    const uint64_t key = errorTableKey(design, world, cook);
    EXPECT_EQ(key, errorTableKey(design, world, cook));
    ClothAssetDesc longer = design;
    longer.relativeLength = 0.4;
    EXPECT_NE(errorTableKey(longer, world, cook), key);
    WorldDesc faster = world;
    ASSERT_TRUE(faster.applyPreset(QualityPreset::Fast).isOk());
    EXPECT_NE(errorTableKey(design, faster, cook), key);
    WorldDesc moon = world;
    moon.gravity[1] = -1.62;
    EXPECT_NE(errorTableKey(design, moon, cook), key);
    ErrorCookDesc longerCook = cook;
    longerCook.seconds = 6.0;
    EXPECT_NE(errorTableKey(design, world, longerCook), key);
    WorldDesc otherBudget = world;  // what the scheduler does with errors is not what they are
    otherBudget.frameBudgetMs = 3.0;
    otherBudget.pixelTolerance = 4.0;
    EXPECT_EQ(errorTableKey(design, otherBudget, cook), key);
}

TEST(ErrorTable, CookIsDeterministicAndMeasuresEveryLevel) {
    const WorldDesc world;
    auto first = cookErrorTable(smallCape(), world, shortCook());
    ASSERT_TRUE(first.isOk()) << first.status().message();
    auto second = cookErrorTable(smallCape(), world, shortCook());
    ASSERT_TRUE(second.isOk()) << second.status().message();
    EXPECT_EQ(first.value().toText(), second.value().toText());
    const ErrorTable& t = first.value();
    EXPECT_EQ(t.key, errorTableKey(smallCape(), world, shortCook()));
    EXPECT_EQ(t.levelCount(), 2u);
    EXPECT_EQ(t.windows, 2u) << "windows at 0.5 and 0.75 s of a 1 s run";
    for (uint32_t l = 0; l < 2; ++l)
        for (uint32_t m = 0; m < ErrorTable::kMotions; ++m) {
            // Every shipped level is another discretisation and solve than the reference's: it
            // differs, by less than the garment's size.
            EXPECT_GT(t.error(l, m), 0.0) << "level " << l << " motion " << m;
            EXPECT_LT(t.error(l, m), 1.0) << "level " << l << " motion " << m;
            EXPECT_LE(t.medianErrorPerRadius[l * ErrorTable::kMotions + m], t.error(l, m));
        }
    ErrorCookDesc bad = shortCook();
    bad.seconds = 0.5;
    EXPECT_TRUE(contains(cookErrorTable(smallCape(), world, bad).status(), "ErrorCookDesc.seconds"));
    ClothAssetDesc tooFine = smallCape();
    tooFine.levelCount = 10;
    tooFine.renderLevel = 10;
    EXPECT_TRUE(contains(cookErrorTable(tooFine, world, shortCook()).status(), "levelCount must be < 10"));
}

TEST(ErrorTable, LoadOrCookCachesByKeyAndReplacesWhatDoesNotRead) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("cc_error_tables_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::remove_all(dir);
    const WorldDesc world;
    auto cooked = loadOrCookErrorTable(dir.string(), smallCape(), world, shortCook());
    ASSERT_TRUE(cooked.isOk()) << cooked.status().message();
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
    ASSERT_EQ(files.size(), 1u) << "one file per key, no partial file left";
    // A cached table is read, not cooked again: plant one with other values under the same key.
    ErrorTable planted = uniformTable(2, 0.5);
    planted.key = cooked.value().key;
    planted.cook = shortCook();
    std::ofstream(files[0], std::ios::trunc) << planted.toText();
    auto read = loadOrCookErrorTable(dir.string(), smallCape(), world, shortCook());
    ASSERT_TRUE(read.isOk());
    EXPECT_EQ(read.value().errorPerRadius, planted.errorPerRadius);
    // A damaged file is cooked again and replaced.
    std::ofstream(files[0], std::ios::trunc) << "crowdcloth-error-table 1\nkey 00";
    auto again = loadOrCookErrorTable(dir.string(), smallCape(), world, shortCook());
    ASSERT_TRUE(again.isOk());
    EXPECT_EQ(again.value().toText(), cooked.value().toText());
    fs::remove_all(dir);
}

/// The predicted error of a cape walking 2.5 m from the camera after 20 frames, with `table`
/// handed to the World (none: the formula).
double predictedErrorPx(const ErrorTable* table) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.maxThreads = 1;
    desc.maxUpdateInterval = 1;
    test::WorldPtr world(World::create(desc).value());
    ClothAssetDesc cape;
    cape.levelCount = 3;
    const AssetId asset = world->addClothAsset(cape).value();
    if (table) {
        const Status s = world->setErrorTable(asset, *table);
        EXPECT_TRUE(s.isOk()) << s.message();
    }
    test::WalkingCrowd crowd = test::addWalkingCrowd(*world, asset, 1);
    double predicted = 0.0;
    for (int frame = 1; frame <= 20; ++frame) {
        test::walkCrowd(*world, crowd, frame / 60.0);
        const Vec3 chest = crowd.starts[0] + Vec3(0, 1.2, crowd.speed * frame / 60.0);
        const CameraDesc camera = test::cameraLookingAt(chest + Vec3(-0.3, 0.2, -2.5), chest);
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        EXPECT_TRUE(world->step(1.0 / 60.0).isOk());
        predicted = world->garmentStats(crowd.garments[0]).value().predictedErrorPx;
    }
    return predicted;
}

TEST(ErrorTable, TheWorldPredictsFromAHandedTableInPlaceOfItsFormula) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.maxThreads = 1;
    desc.maxUpdateInterval = 1;
    ClothAssetDesc cape;
    cape.levelCount = 3;
    ErrorTable table = uniformTable(3, 0.05);
    table.key = errorTableKey(cape, desc, table.cook);
    const double formula = predictedErrorPx(nullptr);
    const double measured = predictedErrorPx(&table);
    for (double& e : table.errorPerRadius) e *= 2.0;
    const double doubled = predictedErrorPx(&table);
    EXPECT_GT(measured, 1.0) << "5 % of a cape's radius close up is many pixels";
    EXPECT_NE(measured, formula);
    EXPECT_NEAR(doubled / measured, 2.0, 1e-9) << "the prediction is the table's error times the garment's size";

    // Refused: another design's or effort's table, the wrong level count, a stale asset.
    test::WorldPtr world(World::create(desc).value());
    const AssetId asset = world->addClothAsset(cape).value();
    ErrorTable other = table;
    other.key ^= 1;
    EXPECT_TRUE(contains(world->setErrorTable(asset, other), "another design or World effort"));
    ErrorTable fewer = uniformTable(2, 0.05);
    fewer.key = table.key;
    EXPECT_TRUE(contains(world->setErrorTable(asset, fewer), "2 levels, the design 3"));
    EXPECT_TRUE(contains(world->setErrorTable(AssetId{}, table), "stale"));
    EXPECT_TRUE(world->setErrorTable(asset, table).isOk());
}

TEST(ErrorTable, LoadErrorTableReadsTheCacheForTheWorldsEffortInCAndCpp) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("cc_error_tables_c_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    // A table planted under the key of the default design and World: read, never cooked (a cook
    // at the defaults takes half a minute).
    ErrorTable planted = uniformTable(ClothAssetDesc{}.levelCount, 0.02);
    planted.key = errorTableKey(ClothAssetDesc{}, WorldDesc{});
    char name[40];
    std::snprintf(name, sizeof name, "%016llx.errors", static_cast<unsigned long long>(planted.key));
    std::ofstream(dir / name) << planted.toText();

    test::WorldPtr world(World::create({}).value());
    const AssetId asset = world->addClothAsset({}).value();
    EXPECT_TRUE(world->loadErrorTable(asset, dir.string().c_str()).isOk());
    EXPECT_TRUE(contains(world->loadErrorTable(asset, ""), "directory is null or empty"));
    EXPECT_TRUE(contains(world->loadErrorTable(AssetId{}, dir.string().c_str()), "stale"));

    cc_world_desc wd;
    cc_world_desc_init(&wd);
    cc_world* c = nullptr;
    ASSERT_EQ(cc_world_create(&wd, &c), CC_OK);
    cc_cloth_asset_desc ad;
    cc_cloth_asset_desc_init(&ad);
    cc_asset_id id{};
    ASSERT_EQ(cc_world_add_cloth_asset(c, &ad, &id), CC_OK);
    EXPECT_EQ(cc_world_load_error_table(c, id, dir.string().c_str()), CC_OK) << cc_world_last_error(c);
    EXPECT_EQ(cc_world_load_error_table(c, id, nullptr), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(c)).find("directory is null"), std::string::npos);
    cc_world_destroy(c);
    fs::remove_all(dir);
}

} // namespace
} // namespace cc
