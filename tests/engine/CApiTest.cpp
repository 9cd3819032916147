#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "crowdcloth/World.h"
#include "crowdcloth/character/Mannequin.h"
#include "crowdcloth/crowdcloth.h"
#include "crowdcloth/crowdcloth_import.h"
#include "crowdcloth/import/CharacterIO.h"
#include "support/CWorldScenes.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

TEST(CApi, DescDefaultsAreTheCppDefaults) {
    cc_world_desc w;
    cc_world_desc_init(&w);
    const WorldDesc cw;
    EXPECT_EQ(w.version, CC_DESC_VERSION);
    EXPECT_EQ(w.max_threads, cw.maxThreads);
    EXPECT_EQ(w.frame_budget_ms, cw.frameBudgetMs);
    EXPECT_EQ(w.pixel_tolerance, cw.pixelTolerance);
    EXPECT_EQ(w.fixed_cost_model != 0, cw.fixedCostModel);
    EXPECT_EQ(w.max_update_interval, cw.maxUpdateInterval);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(w.gravity[k], cw.gravity[k]);
    EXPECT_EQ(w.budget_threads, cw.budgetThreads);
    EXPECT_EQ(w.task_runner, cw.taskRunner);
    EXPECT_EQ(w.task_runner_user_data, cw.taskRunnerUserData);
    EXPECT_EQ(w.substeps, cw.substeps);
    EXPECT_EQ(w.solver_iterations, cw.solverIterations);
    EXPECT_EQ(w.batch_size, cw.batchSize);
    EXPECT_EQ(w.strain_limit, cw.strainLimit);
    EXPECT_EQ(w.self_collision != 0, cw.selfCollision);
    EXPECT_EQ(w.spend_slack != 0, cw.spendSlack);

    cc_cloth_asset_desc a;
    cc_cloth_asset_desc_init(&a);
    const ClothAssetDesc ca;
    EXPECT_EQ(a.kind, cc_garment_kind(ca.kind));
    EXPECT_EQ(a.width, ca.width);
    EXPECT_EQ(a.length, ca.length);
    EXPECT_EQ(a.cell_size, ca.cellSize);
    EXPECT_EQ(a.level_count, ca.levelCount);
    EXPECT_EQ(a.render_level, ca.renderLevel);
    EXPECT_EQ(a.areal_density, ca.arealDensity);
    EXPECT_EQ(a.stretch_stiffness, ca.stretchStiffness);
    EXPECT_EQ(a.shear_stiffness, ca.shearStiffness);
    EXPECT_EQ(a.bend_stiffness, ca.bendStiffness);
    EXPECT_EQ(a.damping, ca.damping);
    EXPECT_EQ(a.thickness, ca.thickness);
    EXPECT_EQ(a.friction, ca.friction);
    EXPECT_EQ(a.fold_radius, ca.foldRadius);
    EXPECT_EQ(a.cut, cc_garment_cut(ca.cut));
    EXPECT_EQ(a.relative_length, ca.relativeLength);
    EXPECT_EQ(a.hem_width, ca.hemWidth);
    EXPECT_EQ(a.ease, ca.ease);

    cc_mannequin_desc m;
    cc_mannequin_desc_init(&m);
    const MannequinDesc cm;
    EXPECT_EQ(m.height, cm.height);
    EXPECT_EQ(m.shoulder_width, cm.shoulderWidth);
    EXPECT_EQ(m.hip_width, cm.hipWidth);
    EXPECT_EQ(m.waist_width, cm.waistWidth);
    EXPECT_EQ(m.limb_girth, cm.limbGirth);

    cc_character_desc c;
    cc_character_desc_init(&c);
    const CharacterDesc cc;
    EXPECT_STREQ(c.clip, cc.clip);
    EXPECT_EQ(c.clip_time, cc.clipTime);
    EXPECT_EQ(c.playback_rate, cc.playbackRate);
    EXPECT_EQ(c.yaw, cc.yaw);
    EXPECT_EQ(c.clip_index, cc.clipIndex);
    EXPECT_EQ(c.clip_phase, cc.clipPhase);

    cc_body_desc b;
    cc_body_desc_init(&b);
    EXPECT_EQ(b.height, BodyDesc{}.height);
    cc_body_landmarks l;
    cc_body_landmarks_init(&l);
    const BodyLandmarkDesc cl;
    EXPECT_EQ(l.waist_y, cl.waistY);
    EXPECT_EQ(l.forward[2], cl.forward[2]);
    cc_import_settings is;
    cc_import_settings_init(&is);
    const ImportSettings cis;
    EXPECT_EQ(is.isolate != 0, cis.isolate);
    EXPECT_EQ(is.unit_scale, cis.unitScale);
    EXPECT_EQ(is.timeout_seconds, cis.timeoutSeconds);

    cc_garment_desc g;
    cc_garment_desc_init(&g);
    EXPECT_EQ(g.importance, GarmentDesc{}.importance);
    EXPECT_EQ(g.force_level, GarmentDesc{}.forceLevel);
    cc_camera_desc cam;
    cc_camera_desc_init(&cam);
    const CameraDesc ccam;
    for (int k = 0; k < 16; ++k) EXPECT_EQ(cam.view_projection[k], ccam.viewProjection[k]) << "element " << k;
}

/// A character file through the C API: a body the world skins, its clips by index, a garment
/// fitted to it, and errors that name the file or the clip.
TEST(CApi, BodiesFromFilesWearFittedGarments) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("cc_capi_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ignored;
            fs::remove_all(dir, ignored);
        }
    } cleanup{dir};
    const std::string file = (dir / "mannequin.glb").string();
    ASSERT_TRUE(exportCharacter(buildMannequin().value().character, file).isOk());

    cc_world_desc wd;
    cc_world_desc_init(&wd);
    wd.fixed_cost_model = 1;
    cc_world* world = nullptr;
    ASSERT_EQ(cc_world_create(&wd, &world), CC_OK);
    cc_body_id body;
    const std::string missing = (dir / "nobody.fbx").string();
    EXPECT_EQ(cc_world_add_body_from_file(world, missing.c_str(), nullptr, nullptr, &body), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find(missing), std::string::npos) << cc_world_last_error(world);
    cc_import_settings is;
    cc_import_settings_init(&is);
    cc_body_desc bd;
    cc_body_desc_init(&bd);
    bd.height = 1.6;
    ASSERT_EQ(cc_world_add_body_from_file(world, file.c_str(), &is, &bd, &body), CC_OK) << cc_world_last_error(world);
    uint32_t clips = 0;
    ASSERT_EQ(cc_world_get_body_clip_count(world, body, &clips), CC_OK);
    ASSERT_EQ(clips, 3u);
    int walk = -1;
    for (uint32_t c = 0; c < clips; ++c) {
        const char* name = nullptr;
        ASSERT_EQ(cc_world_get_body_clip_name(world, body, c, &name), CC_OK);
        if (std::string(name) == "walk") walk = int(c);
    }
    ASSERT_GE(walk, 0);
    cc_body_landmarks landmarks;
    ASSERT_EQ(cc_world_get_body_landmarks(world, body, &landmarks), CC_OK) << cc_world_last_error(world);
    EXPECT_GT(landmarks.waist_girth, 0.4);
    EXPECT_LT(landmarks.neck_y, 1.6);

    cc_character_desc cd;
    cc_character_desc_init(&cd);
    cd.body = body;
    cd.clip = "moonwalk";
    cc_character_id character;
    EXPECT_EQ(cc_world_add_character(world, &cd, &character), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find("no clip named 'moonwalk'"), std::string::npos);
    cd.clip_index = walk;
    cd.clip_phase = 0.25;
    ASSERT_EQ(cc_world_add_character(world, &cd, &character), CC_OK) << cc_world_last_error(world);
    EXPECT_EQ(cc_world_set_character_playback_rate(world, character, 11.0), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find("playbackRate"), std::string::npos);
    ASSERT_EQ(cc_world_set_character_playback_rate(world, character, 0.8), CC_OK) << cc_world_last_error(world);
    cc_cloth_asset_desc ad;
    cc_cloth_asset_desc_init(&ad);
    ad.kind = CC_GARMENT_SKIRT;
    cc_asset_id asset;
    ASSERT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_OK);
    cc_garment_desc gd;
    cc_garment_desc_init(&gd);
    cc_garment_id garment;
    ASSERT_EQ(cc_world_add_garment(world, asset, character, &gd, &garment), CC_OK) << cc_world_last_error(world);
    cc_cloth_asset_desc fit;
    ASSERT_EQ(cc_world_get_garment_fit(world, garment, &fit), CC_OK);
    EXPECT_NEAR(fit.width, landmarks.waist_girth + ad.ease, 0.15) << "the waist ring is the waist plus ease";
    EXPECT_NEAR(fit.length, 0.3 * 1.6, 0.05) << "the default skirt is 0.3 body heights long";
    for (int f = 0; f < 10; ++f) ASSERT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK) << cc_world_last_error(world);
    cc_garment_stats gs;
    ASSERT_EQ(cc_world_get_garment_stats(world, garment, &gs), CC_OK);
    EXPECT_EQ(gs.failed, 0);
    EXPECT_LT(gs.max_attachment_error, 1e-3);
    cc_world_destroy(world);
}

/// The same walk through the C API and the C++ API gives the same state hash.
TEST(CApi, RoundTripMatchesTheCppApi) {
    const CameraDesc camera = test::cameraLookingAt(Vec3(-1.5, 1.5, -3.0), Vec3(0, 1.2, 0));
    uint64_t cHash = 0, cppHash = 0;
    {
        cc_cloth_asset_desc ad;
        cc_cloth_asset_desc_init(&ad);
        test::CWorldScene scene;
        ASSERT_EQ(test::makeCWorldScene(ad, camera, scene), CC_OK);
        cc_world* world = scene.world;
        const cc_garment_id garment = scene.garment;
        for (int f = 0; f < 30; ++f) ASSERT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK) << cc_world_last_error(world);
        cc_render_mesh mesh;
        ASSERT_EQ(cc_world_get_render_mesh(world, garment, &mesh), CC_OK);
        EXPECT_GT(mesh.vertex_count, 0u);
        cc_garment_stats gs;
        ASSERT_EQ(cc_world_get_garment_stats(world, garment, &gs), CC_OK);
        EXPECT_EQ(gs.failed, 0);
        cc_frame_stats fs;
        ASSERT_EQ(cc_world_get_frame_stats(world, &fs), CC_OK);
        EXPECT_EQ(fs.frame, 30u);
        const char* json = nullptr;
        ASSERT_EQ(cc_world_get_stats_json(world, &json), CC_OK);
        EXPECT_NE(std::string(json).find("\"garmentStats\""), std::string::npos);
        ASSERT_EQ(cc_world_state_hash(world, &cHash), CC_OK);
        // Saved, stepped, restored and stepped again: where the first steps left it.
        const void* data = nullptr;
        size_t size = 0;
        EXPECT_EQ(cc_world_save_state(world, nullptr, &size), CC_INVALID_ARGUMENT);
        ASSERT_EQ(cc_world_save_state(world, &data, &size), CC_OK) << cc_world_last_error(world);
        const std::vector<uint8_t> saved(static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + size);
        uint64_t ahead = 0, again = 0;
        for (int f = 0; f < 10; ++f) ASSERT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK);
        ASSERT_EQ(cc_world_state_hash(world, &ahead), CC_OK);
        ASSERT_EQ(cc_world_restore_state(world, saved.data(), saved.size()), CC_OK) << cc_world_last_error(world);
        for (int f = 0; f < 10; ++f) ASSERT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK);
        ASSERT_EQ(cc_world_state_hash(world, &again), CC_OK);
        EXPECT_EQ(again, ahead);
        EXPECT_EQ(cc_world_restore_state(world, saved.data(), size / 2), CC_INVALID_ARGUMENT);
        EXPECT_NE(std::string(cc_world_last_error(world)).find("truncated"), std::string::npos) << cc_world_last_error(world);
        EXPECT_EQ(cc_world_restore_state_mode(world, saved.data(), saved.size(), 7), CC_INVALID_ARGUMENT);
        ASSERT_EQ(cc_world_restore_state_mode(world, saved.data(), saved.size(), CC_RESTORE_OTHER_SOLVER), CC_OK);
        EXPECT_EQ(cc_world_set_garment_level(world, garment, 99), CC_INVALID_ARGUMENT);
        ASSERT_EQ(cc_world_set_garment_level(world, garment, 1), CC_OK) << cc_world_last_error(world);
        ASSERT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK);
        ASSERT_EQ(cc_world_get_garment_stats(world, garment, &gs), CC_OK);
        EXPECT_EQ(gs.level, 1);
        cc_world_destroy(world);
    }
    {
        WorldDesc wd;
        wd.fixedCostModel = true;
        World* world = World::create(wd).value();
        const AssetId asset = world->addClothAsset({}).value();
        CharacterDesc cd;
        cd.body = world->addMannequinBody({}).value();
        const CharacterId character = world->addCharacter(cd).value();
        ASSERT_TRUE(world->addGarment(asset, character, {}).isOk());
        ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
        for (int f = 0; f < 30; ++f) ASSERT_TRUE(world->step(1.0 / 60.0).isOk());
        cppHash = world->stateHash();
        World::destroy(world);
    }
    EXPECT_EQ(cHash, cppHash);
}

TEST(CApi, BadCallsReturnStatusesNotCrashes) {
    EXPECT_EQ(cc_world_step(nullptr, 1.0 / 60.0), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_create(nullptr, nullptr), CC_INVALID_ARGUMENT);
    cc_world_desc unstamped{};
    cc_world* world = nullptr;
    EXPECT_EQ(cc_world_create(&unstamped, &world), CC_INVALID_ARGUMENT);
    EXPECT_EQ(world, nullptr);
    cc_world_desc_init(&unstamped);
    unstamped.frame_budget_ms = -3.0;
    EXPECT_EQ(cc_world_create(&unstamped, &world), CC_INVALID_ARGUMENT);

    cc_world_desc wd;
    cc_world_desc_init(&wd);
    ASSERT_EQ(cc_world_create(&wd, &world), CC_OK);
    cc_cloth_asset_desc ad{}; // not initialised
    cc_asset_id asset{};
    EXPECT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find("_desc_init"), std::string::npos);
    cc_cloth_asset_desc_init(&ad);
    ad.cell_size = 0.0;
    EXPECT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find("cellSize"), std::string::npos);
    // A C host may store any int in an enum field (C allows it): refused by name, not undefined.
    for (const int32_t kind : {4, -1, 1 << 30}) {
        cc_cloth_asset_desc_init(&ad);
        std::memcpy(&ad.kind, &kind, sizeof kind);
        EXPECT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_INVALID_ARGUMENT) << kind;
        EXPECT_NE(std::string(cc_world_last_error(world)).find("kind"), std::string::npos) << kind;
    }
    cc_cloth_asset_desc_init(&ad);
    ASSERT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_OK);

    cc_mannequin_desc md;
    cc_mannequin_desc_init(&md);
    md.height = 7.0;
    cc_body_id body{};
    EXPECT_EQ(cc_world_add_mannequin_body(world, &md, &body), CC_INVALID_ARGUMENT);
    cc_mannequin_desc_init(&md);
    ASSERT_EQ(cc_world_add_mannequin_body(world, &md, &body), CC_OK);
    cc_character_desc cd;
    cc_character_desc_init(&cd);
    cd.body = body;
    cc_character_id character;
    ASSERT_EQ(cc_world_add_character(world, &cd, &character), CC_OK);
    const float vertices[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    EXPECT_EQ(cc_world_set_character_skinned_vertices(world, character, vertices, 3, 0), CC_INVALID_OPERATION);
    cc_garment_desc gd;
    cc_garment_desc_init(&gd);
    cc_garment_id garment;
    ASSERT_EQ(cc_world_add_garment(world, asset, character, &gd, &garment), CC_OK);
    EXPECT_EQ(cc_world_step(world, -1.0), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_set_cameras(world, nullptr, 2), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_remove_garment(world, garment), CC_OK);
    cc_render_mesh mesh;
    EXPECT_EQ(cc_world_get_render_mesh(world, garment, &mesh), CC_INVALID_ARGUMENT) << "stale handle";
    EXPECT_EQ(cc_world_remove_garment(world, garment), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_add_garment(world, cc_asset_id{77, 1}, character, &gd, &garment), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_get_frame_stats(world, nullptr), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_step(world, 1.0 / 60.0), CC_OK);
    EXPECT_STREQ(cc_world_last_error(world), "");
    cc_world_destroy(world);
    cc_world_destroy(nullptr);
}

} // namespace
} // namespace cc
