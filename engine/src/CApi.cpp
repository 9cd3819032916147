#include "crowdcloth/crowdcloth.h"

#include <new>
#include <string>
#include <vector>

#include "CApiFields.h"
#include "CApiWorld.h"
#include "crowdcloth/Version.h"
#include "crowdcloth/World.h"

namespace cc::detail {

cc_status toCStatus(StatusCode code) {
    switch (code) {
    case StatusCode::Ok: return CC_OK;
    case StatusCode::InvalidArgument: return CC_INVALID_ARGUMENT;
    case StatusCode::InvalidOperation: return CC_INVALID_OPERATION;
    case StatusCode::NotConverged: return CC_NOT_CONVERGED;
    case StatusCode::NumericalFailure: return CC_NUMERICAL_FAILURE;
    }
    return CC_INVALID_ARGUMENT;
}

cc_status reportToC(const cc_world* w, const Status& s) {
    if (w) const_cast<cc_world*>(w)->lastError = s.isOk() ? std::string() : s.message();
    return toCStatus(s.code());
}

std::string stampError(const char* name, const char* init, uint32_t stamp) {
    if (stamp == CC_DESC_VERSION) return {};
    if ((stamp & 0xffff0000u) != CC_DESC_MAGIC) return std::string(name) + " was not initialised with " + init + "()";
    const uint32_t layout = stamp & 0xffffu, ours = CC_DESC_VERSION & 0xffffu;
    return std::string(name) + " has layout " + std::to_string(layout) + " from " +
           (layout > ours ? "newer" : "older") + " headers than this library (layout " + std::to_string(ours) +
           "): build the host against the headers of the library it runs with";
}

} // namespace cc::detail

namespace {

using cc::detail::stampError;

cc_status report(const cc_world* w, const cc::Status& s) { return cc::detail::reportToC(w, s); }

cc_status fail(const cc_world* w, cc_status code, const char* message) {
    if (w) const_cast<cc_world*>(w)->lastError = message;
    return code;
}

/// Runs `f` and turns a (theoretical) allocation failure into a status: no exception crosses the C API.
template <typename F>
cc_status guarded(const cc_world* w, F&& f) {
    try {
        return f();
    } catch (const std::bad_alloc&) {
        return fail(w, CC_OUT_OF_MEMORY, "out of memory");
    } catch (...) {
        return fail(w, CC_INVALID_OPERATION, "internal error");
    }
}

/// cc_world_create() has no world to keep its message in.
thread_local std::string gCreateError;

#define CC_CHECK_WORLD(w)                                                                                    \
    if (!(w) || !(w)->world) return CC_INVALID_ARGUMENT
#define CC_CHECK_DESC(w, d, name, init)                                                                      \
    if (!(d)) return fail(w, CC_INVALID_ARGUMENT, name " is null");                                        \
    if (const std::string refused = stampError(name, init, (d)->version); !refused.empty())                \
    return fail(w, CC_INVALID_ARGUMENT, refused.c_str())
#define CC_CHECK_OUT(w, p, name)                                                                             \
    if (!(p)) return fail(w, CC_INVALID_ARGUMENT, name " is null")

/// Why a C world desc cannot be read (null, or not stamped by cc_world_desc_init); empty if it can.
std::string worldDescRefusal(const cc_world_desc* d) {
    if (!d) return "world desc is null";
    return stampError("world desc", "cc_world_desc_init", d->version);
}

} // namespace

CC_CHECK_FIELDS(world, CC_WORLD_FIELDS, cc_world_desc, cc::WorldDesc, 1)
CC_CHECK_FIELDS(asset, CC_ASSET_FIELDS, cc_cloth_asset_desc, cc::ClothAssetDesc, 1)
CC_CHECK_FIELDS(mannequin, CC_MANNEQUIN_FIELDS, cc_mannequin_desc, cc::MannequinDesc, 1)
CC_CHECK_FIELDS(body, CC_BODY_FIELDS, cc_body_desc, cc::BodyDesc, 1)
CC_CHECK_FIELDS(landmarks, CC_LANDMARK_FIELDS, cc_body_landmarks, cc::BodyLandmarkDesc, 1)
CC_CHECK_FIELDS(character, CC_CHARACTER_FIELDS, cc_character_desc, cc::CharacterDesc, 1)
CC_CHECK_FIELDS(garment, CC_GARMENT_FIELDS, cc_garment_desc, cc::GarmentDesc, 1)
CC_CHECK_FIELDS(camera, CC_CAMERA_FIELDS, cc_camera_desc, cc::CameraDesc, 1)
CC_CHECK_FIELDS(render_mesh, CC_RENDER_MESH_FIELDS, cc_render_mesh, cc::RenderMeshView, 0)
CC_CHECK_FIELDS(garment_stats, CC_GARMENT_STATS_FIELDS, cc_garment_stats, cc::GarmentStats, 0)
CC_CHECK_FIELDS(shadow_result, CC_SHADOW_RESULT_FIELDS, cc_shadow_check_result, cc::ShadowCheckResult, 0)
CC_CHECK_FIELDS(frame_stats, CC_FRAME_STATS_FIELDS, cc_frame_stats, cc::FrameStats, 0)

#define CC_TO_C(c, cpp) cc::detail::copyField(d->c, x.cpp);
#define CC_TO_CPP(c, cpp) cc::detail::copyField(x.cpp, d->c);

extern "C" {

uint32_t cc_get_version(void) { return cc::getVersion(); }

// Every init function stamps the desc and copies the C++ desc's defaults through its field list.
#define CC_DESC_INIT(function, CStruct, CppStruct, LIST)                                             \
    void function(CStruct* d) {                                                                      \
        if (!d) return;                                                                              \
        const CppStruct x{};                                                                         \
        d->version = CC_DESC_VERSION;                                                                \
        LIST(CC_TO_C)                                                                                \
    }
CC_DESC_INIT(cc_world_desc_init, cc_world_desc, cc::WorldDesc, CC_WORLD_FIELDS)
CC_DESC_INIT(cc_cloth_asset_desc_init, cc_cloth_asset_desc, cc::ClothAssetDesc, CC_ASSET_FIELDS)
CC_DESC_INIT(cc_mannequin_desc_init, cc_mannequin_desc, cc::MannequinDesc, CC_MANNEQUIN_FIELDS)
CC_DESC_INIT(cc_character_desc_init, cc_character_desc, cc::CharacterDesc, CC_CHARACTER_FIELDS)
CC_DESC_INIT(cc_garment_desc_init, cc_garment_desc, cc::GarmentDesc, CC_GARMENT_FIELDS)
CC_DESC_INIT(cc_body_desc_init, cc_body_desc, cc::BodyDesc, CC_BODY_FIELDS)
CC_DESC_INIT(cc_body_landmarks_init, cc_body_landmarks, cc::BodyLandmarkDesc, CC_LANDMARK_FIELDS)
CC_DESC_INIT(cc_camera_desc_init, cc_camera_desc, cc::CameraDesc, CC_CAMERA_FIELDS)

cc_status cc_world_desc_apply_preset(cc_world_desc* d, int32_t preset) {
    gCreateError = worldDescRefusal(d);
    if (!gCreateError.empty()) return CC_INVALID_ARGUMENT;
    if (preset < 0) {
        gCreateError = "cc_quality_preset " + std::to_string(preset) + " is not a preset (0 fast, 1 balanced, 2 quality)";
        return CC_INVALID_ARGUMENT;
    }
    cc::WorldDesc x;
    CC_WORLD_FIELDS(CC_TO_CPP)
    if (const cc::Status s = x.applyPreset(cc::QualityPreset(uint32_t(preset))); !s) {
        gCreateError = s.message();
        return cc::detail::toCStatus(s.code());
    }
    CC_WORLD_FIELDS(CC_TO_C)
    return CC_OK;
}

cc_status cc_world_create(const cc_world_desc* d, cc_world** out_world) {
    gCreateError.clear();
    if (!out_world) {
        gCreateError = "out_world is null";
        return CC_INVALID_ARGUMENT;
    }
    *out_world = nullptr;
    gCreateError = worldDescRefusal(d);
    if (!gCreateError.empty()) return CC_INVALID_ARGUMENT;
    try {
        cc::WorldDesc x;
        CC_WORLD_FIELDS(CC_TO_CPP)
        auto world = cc::World::create(x);
        if (!world.isOk()) {
            gCreateError = world.status().message();
            return cc::detail::toCStatus(world.status().code());
        }
        *out_world = new cc_world{world.value(), {}, {}, {}};
        return CC_OK;
    } catch (const std::bad_alloc&) {
        gCreateError = "out of memory";
        return CC_OUT_OF_MEMORY;
    }
}

const char* cc_world_create_error(void) { return gCreateError.c_str(); }

void cc_world_destroy(cc_world* w) {
    if (!w) return;
    cc::World::destroy(w->world);
    delete w;
}

const char* cc_world_last_error(const cc_world* w) { return w ? w->lastError.c_str() : "world is null"; }

cc_status cc_world_add_cloth_asset(cc_world* w, const cc_cloth_asset_desc* d, cc_asset_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "cloth asset desc", "cc_cloth_asset_desc_init");
    CC_CHECK_OUT(w, out, "out_asset");
    return guarded(w, [&] {
        cc::ClothAssetDesc x;
        CC_ASSET_FIELDS(CC_TO_CPP)
        auto id = w->world->addClothAsset(x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_add_mannequin_body(cc_world* w, const cc_mannequin_desc* d, cc_body_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "mannequin desc", "cc_mannequin_desc_init");
    CC_CHECK_OUT(w, out, "out_body");
    return guarded(w, [&] {
        cc::MannequinDesc x;
        CC_MANNEQUIN_FIELDS(CC_TO_CPP)
        auto id = w->world->addMannequinBody(x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_add_skinned_body(cc_world* w, const float* bind_positions, uint32_t vertex_count,
                                    uint32_t stride_bytes, const uint32_t* triangles, uint32_t triangle_count,
                                    cc_body_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_body");
    return guarded(w, [&] {
        auto id = w->world->addSkinnedBody(bind_positions, vertex_count, stride_bytes, triangles, triangle_count);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_set_body_landmarks(cc_world* w, cc_body_id body, const cc_body_landmarks* d) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "body landmarks", "cc_body_landmarks_init");
    return guarded(w, [&] {
        cc::BodyLandmarkDesc x;
        CC_LANDMARK_FIELDS(CC_TO_CPP)
        return report(w, w->world->setBodyLandmarks(body, x));
    });
}

cc_status cc_world_get_body_landmarks(const cc_world* w, cc_body_id body, cc_body_landmarks* d) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, d, "out_landmarks");
    return guarded(w, [&] {
        auto l = w->world->bodyLandmarks(body);
        if (l.isOk()) {
            const cc::BodyLandmarkDesc& x = l.value();
            d->version = CC_DESC_VERSION;
            CC_LANDMARK_FIELDS(CC_TO_C)
        }
        return report(w, l.status());
    });
}

cc_status cc_world_get_body_clip_count(const cc_world* w, cc_body_id body, uint32_t* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_count");
    return guarded(w, [&] {
        auto n = w->world->bodyClipCount(body);
        if (n.isOk()) *out = n.value();
        return report(w, n.status());
    });
}

cc_status cc_world_get_body_clip_name(const cc_world* w, cc_body_id body, uint32_t index, const char** out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_name");
    return guarded(w, [&] {
        auto name = w->world->bodyClipName(body, index);
        if (name.isOk()) *out = name.value();
        return report(w, name.status());
    });
}

cc_status cc_world_get_garment_fit(const cc_world* w, cc_garment_id g, cc_cloth_asset_desc* d) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, d, "out_desc");
    return guarded(w, [&] {
        auto fit = w->world->garmentFit(g);
        if (fit.isOk()) {
            const cc::ClothAssetDesc& x = fit.value();
            d->version = CC_DESC_VERSION;
            CC_ASSET_FIELDS(CC_TO_C)
        }
        return report(w, fit.status());
    });
}

cc_status cc_world_add_character(cc_world* w, const cc_character_desc* d, cc_character_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "character desc", "cc_character_desc_init");
    CC_CHECK_OUT(w, out, "out_character");
    return guarded(w, [&] {
        cc::CharacterDesc x;
        CC_CHARACTER_FIELDS(CC_TO_CPP)
        auto id = w->world->addCharacter(x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_remove_character(cc_world* w, cc_character_id c) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->removeCharacter(c)); });
}

cc_status cc_world_set_character_root(cc_world* w, cc_character_id c, const double position[3], double yaw) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->setCharacterRoot(c, position, yaw)); });
}

cc_status cc_world_set_character_playback_rate(cc_world* w, cc_character_id c, double playback_rate) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->setCharacterPlaybackRate(c, playback_rate)); });
}

cc_status cc_world_set_character_skinned_vertices(cc_world* w, cc_character_id c, const float* positions,
                                                  uint32_t vertex_count, uint32_t stride_bytes) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] {
        return report(w, w->world->setCharacterSkinnedVertices(c, positions, vertex_count, stride_bytes));
    });
}

cc_status cc_world_add_garment(cc_world* w, cc_asset_id asset, cc_character_id c, const cc_garment_desc* d,
                               cc_garment_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "garment desc", "cc_garment_desc_init");
    CC_CHECK_OUT(w, out, "out_garment");
    return guarded(w, [&] {
        cc::GarmentDesc x;
        CC_GARMENT_FIELDS(CC_TO_CPP)
        auto id = w->world->addGarment(asset, c, x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_remove_garment(cc_world* w, cc_garment_id g) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->removeGarment(g)); });
}

cc_status cc_world_set_garment_level(cc_world* w, cc_garment_id g, int32_t force_level) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->setGarmentLevel(g, force_level)); });
}

cc_status cc_world_set_cameras(cc_world* w, const cc_camera_desc* cameras, uint32_t count) {
    CC_CHECK_WORLD(w);
    if (count > 0 && !cameras) return fail(w, CC_INVALID_ARGUMENT, "cameras is null");
    return guarded(w, [&] {
        std::vector<cc::CameraDesc> cpp(count);
        for (uint32_t c = 0; c < count; ++c) {
            const std::string name = "camera desc " + std::to_string(c);
            if (std::string refused = stampError(name.c_str(), "cc_camera_desc_init", cameras[c].version);
                !refused.empty())
                return fail(w, CC_INVALID_ARGUMENT, refused.c_str());
            const cc_camera_desc* d = &cameras[c];
            cc::CameraDesc& x = cpp[c];
            CC_CAMERA_FIELDS(CC_TO_CPP)
        }
        return report(w, w->world->setCameras(cpp.data(), count));
    });
}

cc_status cc_world_set_frame_budget(cc_world* w, double milliseconds) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->setFrameBudget(milliseconds)); });
}

cc_status cc_world_step(cc_world* w, double dt) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->step(dt)); });
}

cc_status cc_world_begin_step(cc_world* w, double dt) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->beginStep(dt)); });
}

uint32_t cc_world_step_task_count(const cc_world* w) { return w && w->world ? w->world->stepTaskCount() : 0; }

cc_status cc_world_run_step_task(cc_world* w, uint32_t index) {
    CC_CHECK_WORLD(w);
    // Concurrent with the phase's other tasks: the status only, never the shared last error.
    try {
        return cc::detail::toCStatus(w->world->runStepTask(index).code());
    } catch (const std::bad_alloc&) {
        return CC_OUT_OF_MEMORY;
    }
}

int32_t cc_world_next_step_phase(cc_world* w) {
    if (!w || !w->world) return 0;
    try {
        return w->world->nextStepPhase() ? 1 : 0;
    } catch (const std::bad_alloc&) {
        return 0;  // cc_world_end_step() then reports the open phase
    }
}

cc_status cc_world_end_step(cc_world* w) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->endStep()); });
}

cc_status cc_world_get_render_mesh(const cc_world* w, cc_garment_id g, cc_render_mesh* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_mesh");
    return guarded(w, [&] {
        auto view = w->world->renderMesh(g);
        if (view.isOk()) {
            const cc::RenderMeshView& x = view.value();
            cc_render_mesh* d = out;
            CC_RENDER_MESH_FIELDS(CC_TO_C)
        }
        return report(w, view.status());
    });
}

cc_status cc_world_get_garment_stats(const cc_world* w, cc_garment_id g, cc_garment_stats* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_stats");
    return guarded(w, [&] {
        auto stats = w->world->garmentStats(g);
        if (stats.isOk()) {
            const cc::GarmentStats& x = stats.value();
            cc_garment_stats* d = out;
            CC_GARMENT_STATS_FIELDS(CC_TO_C)
        }
        return report(w, stats.status());
    });
}

cc_status cc_world_load_error_table(cc_world* w, cc_asset_id asset, const char* directory) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->loadErrorTable(asset, directory)); });
}

cc_status cc_world_set_shadow_check(cc_world* w, uint32_t garments, double window_seconds, uint32_t substeps,
                                    uint32_t iterations) {
    CC_CHECK_WORLD(w);
    cc::ShadowCheckDesc desc;
    desc.garments = garments;
    desc.windowSeconds = window_seconds;
    desc.substeps = substeps;
    desc.iterations = iterations;
    return guarded(w, [&] { return report(w, w->world->setShadowCheck(desc)); });
}

cc_status cc_world_get_shadow_check_results(const cc_world* w, cc_shadow_check_result* out, uint32_t capacity,
                                            uint32_t* out_count) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out_count, "out_count");
    if (capacity > 0 && !out) return fail(w, CC_INVALID_ARGUMENT, "out_results is null");
    const auto& results = w->world->shadowCheckResults();
    *out_count = uint32_t(results.size());
    for (uint32_t k = 0; k < capacity && k < results.size(); ++k) {
        const cc::ShadowCheckResult& x = results[k];
        cc_shadow_check_result* d = out + k;
        CC_SHADOW_RESULT_FIELDS(CC_TO_C)
    }
    return CC_OK;
}

cc_status cc_world_get_frame_stats(const cc_world* w, cc_frame_stats* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_stats");
    const cc::FrameStats& x = w->world->frameStats();
    cc_frame_stats* d = out;
    CC_FRAME_STATS_FIELDS(CC_TO_C)
    return CC_OK;
}

cc_status cc_world_get_stats_json(cc_world* w, const char** out_json) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out_json, "out_json");
    return guarded(w, [&] {
        w->json = w->world->statsJson();
        *out_json = w->json.c_str();
        return CC_OK;
    });
}

cc_status cc_world_state_hash(const cc_world* w, uint64_t* out_hash) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out_hash, "out_hash");
    *out_hash = w->world->stateHash();
    return CC_OK;
}

cc_status cc_world_save_state(cc_world* w, const void** out_data, size_t* out_size) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out_data, "out_data");
    CC_CHECK_OUT(w, out_size, "out_size");
    return guarded(w, [&] {
        auto saved = w->world->saveState();
        if (!saved.isOk()) return report(w, saved.status());
        w->snapshot = std::move(saved).value();
        *out_data = w->snapshot.data();
        *out_size = w->snapshot.size();
        return report(w, cc::Status::ok());
    });
}

cc_status cc_world_restore_state(cc_world* w, const void* data, size_t size) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->restoreState(data, size)); });
}

cc_status cc_world_restore_state_mode(cc_world* w, const void* data, size_t size, int32_t mode) {
    CC_CHECK_WORLD(w);
    if (mode != CC_RESTORE_CONTINUE && mode != CC_RESTORE_OTHER_SOLVER)
        return fail(w, CC_INVALID_ARGUMENT, "mode is not a cc_restore_mode");
    return guarded(w, [&] { return report(w, w->world->restoreState(data, size, cc::RestoreMode(mode))); });
}

} // extern "C"
