#include "crowdcloth/crowdcloth.h"

#include <new>
#include <string>
#include <vector>

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

} // namespace cc::detail

namespace {

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

#define CC_CHECK_WORLD(w)                                                                                    \
    if (!(w) || !(w)->world) return CC_INVALID_ARGUMENT
#define CC_CHECK_DESC(w, d, name)                                                                            \
    if (!(d)) return fail(w, CC_INVALID_ARGUMENT, name " is null");                                        \
    if ((d)->version != CC_DESC_VERSION)                                                                   \
    return fail(w, CC_INVALID_ARGUMENT, name " was not initialised with its _desc_init()")
#define CC_CHECK_OUT(w, p, name)                                                                             \
    if (!(p)) return fail(w, CC_INVALID_ARGUMENT, name " is null")

} // namespace

/// Each C desc field next to its C++ field: one list serves both directions, so the two APIs
/// cannot drift apart field by field.
#define CC_WORLD_FIELDS(X)                                                                           \
    X(max_threads, maxThreads) X(frame_budget_ms, frameBudgetMs) X(pixel_tolerance, pixelTolerance)  \
    X(max_update_interval, maxUpdateInterval)
#define CC_ASSET_FIELDS(X)                                                                           \
    X(width, width) X(length, length) X(cell_size, cellSize) X(level_count, levelCount)              \
    X(render_level, renderLevel) X(areal_density, arealDensity) X(stretch_stiffness, stretchStiffness) \
    X(shear_stiffness, shearStiffness) X(bend_stiffness, bendStiffness) X(damping, damping)          \
    X(thickness, thickness) X(friction, friction) X(fold_radius, foldRadius)                        \
    X(relative_length, relativeLength) X(hem_width, hemWidth) X(ease, ease)
#define CC_MANNEQUIN_FIELDS(X)                                                                       \
    X(height, height) X(shoulder_width, shoulderWidth) X(hip_width, hipWidth)                        \
    X(waist_width, waistWidth) X(limb_girth, limbGirth)
#define CC_CHARACTER_FIELDS(X)                                                                       \
    X(body, body) X(clip, clip) X(clip_index, clipIndex) X(clip_time, clipTime) X(clip_phase, clipPhase) \
    X(playback_rate, playbackRate) X(yaw, yaw)
#define CC_LANDMARK_FIELDS(X)                                                                        \
    X(neck_y, neckY) X(shoulder_y, shoulderY) X(chest_y, chestY) X(waist_y, waistY) X(hip_y, hipY)   \
    X(neck_girth, neckGirth) X(chest_girth, chestGirth) X(waist_girth, waistGirth)                    \
    X(hip_girth, hipGirth) X(shoulder_width, shoulderWidth)
#define CC_TO_C(c, cpp) d->c = x.cpp;
#define CC_TO_CPP(c, cpp) x.cpp = d->c;

extern "C" {

uint32_t cc_get_version(void) { return cc::getVersion(); }

void cc_world_desc_init(cc_world_desc* d) {
    if (!d) return;
    const cc::WorldDesc x;
    d->version = CC_DESC_VERSION;
    CC_WORLD_FIELDS(CC_TO_C)
    d->fixed_cost_model = x.fixedCostModel;
    for (int k = 0; k < 3; ++k) d->gravity[k] = x.gravity[k];
}

void cc_cloth_asset_desc_init(cc_cloth_asset_desc* d) {
    if (!d) return;
    const cc::ClothAssetDesc x;
    d->version = CC_DESC_VERSION;
    d->kind = cc_garment_kind(x.kind);
    d->cut = cc_garment_cut(x.cut);
    CC_ASSET_FIELDS(CC_TO_C)
}

void cc_mannequin_desc_init(cc_mannequin_desc* d) {
    if (!d) return;
    const cc::MannequinDesc x;
    d->version = CC_DESC_VERSION;
    CC_MANNEQUIN_FIELDS(CC_TO_C)
}

void cc_character_desc_init(cc_character_desc* d) {
    if (!d) return;
    const cc::CharacterDesc x;
    d->version = CC_DESC_VERSION;
    CC_CHARACTER_FIELDS(CC_TO_C)
    for (int k = 0; k < 3; ++k) d->position[k] = x.position[k];
}

void cc_garment_desc_init(cc_garment_desc* d) {
    if (!d) return;
    d->version = CC_DESC_VERSION;
    d->importance = cc::GarmentDesc{}.importance;
    d->force_level = cc::GarmentDesc{}.forceLevel;
}

void cc_body_desc_init(cc_body_desc* d) {
    if (!d) return;
    d->version = CC_DESC_VERSION;
    d->height = cc::BodyDesc{}.height;
}

void cc_body_landmarks_init(cc_body_landmarks* d) {
    if (!d) return;
    const cc::BodyLandmarkDesc x;
    d->version = CC_DESC_VERSION;
    for (int k = 0; k < 3; ++k) d->forward[k] = x.forward[k];
    CC_LANDMARK_FIELDS(CC_TO_C)
}

void cc_camera_desc_init(cc_camera_desc* d) {
    if (!d) return;
    const cc::CameraDesc x;
    d->version = CC_DESC_VERSION;
    for (int k = 0; k < 16; ++k) d->view_projection[k] = x.viewProjection[k];
    d->viewport_width = x.viewportWidth;
    d->viewport_height = x.viewportHeight;
}

cc_status cc_world_create(const cc_world_desc* d, cc_world** out_world) {
    if (!out_world) return CC_INVALID_ARGUMENT;
    *out_world = nullptr;
    if (!d || d->version != CC_DESC_VERSION) return CC_INVALID_ARGUMENT;
    return guarded(nullptr, [&] {
        cc::WorldDesc x;
        CC_WORLD_FIELDS(CC_TO_CPP)
        x.fixedCostModel = d->fixed_cost_model != 0;
        for (int k = 0; k < 3; ++k) x.gravity[k] = d->gravity[k];
        auto world = cc::World::create(x);
        if (!world.isOk()) return cc::detail::toCStatus(world.status().code());
        *out_world = new cc_world{world.value(), {}, {}};
        return CC_OK;
    });
}

void cc_world_destroy(cc_world* w) {
    if (!w) return;
    cc::World::destroy(w->world);
    delete w;
}

const char* cc_world_last_error(const cc_world* w) { return w ? w->lastError.c_str() : "world is null"; }

cc_status cc_world_add_cloth_asset(cc_world* w, const cc_cloth_asset_desc* d, cc_asset_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "cloth asset desc");
    CC_CHECK_OUT(w, out, "out_asset");
    return guarded(w, [&] {
        cc::ClothAssetDesc x;
        x.kind = cc::GarmentKind(d->kind);
        x.cut = cc::GarmentCut(d->cut);
        CC_ASSET_FIELDS(CC_TO_CPP)
        auto id = w->world->addClothAsset(x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_add_mannequin_body(cc_world* w, const cc_mannequin_desc* d, cc_body_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "mannequin desc");
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
    CC_CHECK_DESC(w, d, "body landmarks");
    return guarded(w, [&] {
        cc::BodyLandmarkDesc x;
        for (int k = 0; k < 3; ++k) x.forward[k] = d->forward[k];
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
            for (int k = 0; k < 3; ++k) d->forward[k] = x.forward[k];
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
            d->kind = cc_garment_kind(x.kind);
            d->cut = cc_garment_cut(x.cut);
            CC_ASSET_FIELDS(CC_TO_C)
        }
        return report(w, fit.status());
    });
}

cc_status cc_world_add_character(cc_world* w, const cc_character_desc* d, cc_character_id* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_DESC(w, d, "character desc");
    CC_CHECK_OUT(w, out, "out_character");
    return guarded(w, [&] {
        cc::CharacterDesc x;
        CC_CHARACTER_FIELDS(CC_TO_CPP)
        for (int k = 0; k < 3; ++k) x.position[k] = d->position[k];
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
    CC_CHECK_DESC(w, d, "garment desc");
    CC_CHECK_OUT(w, out, "out_garment");
    return guarded(w, [&] {
        cc::GarmentDesc x;
        x.importance = d->importance;
        x.forceLevel = d->force_level;
        auto id = w->world->addGarment(asset, c, x);
        if (id.isOk()) *out = id.value();
        return report(w, id.status());
    });
}

cc_status cc_world_remove_garment(cc_world* w, cc_garment_id g) {
    CC_CHECK_WORLD(w);
    return guarded(w, [&] { return report(w, w->world->removeGarment(g)); });
}

cc_status cc_world_set_cameras(cc_world* w, const cc_camera_desc* cameras, uint32_t count) {
    CC_CHECK_WORLD(w);
    if (count > 0 && !cameras) return fail(w, CC_INVALID_ARGUMENT, "cameras is null");
    return guarded(w, [&] {
        std::vector<cc::CameraDesc> x(count);
        for (uint32_t c = 0; c < count; ++c) {
            if (cameras[c].version != CC_DESC_VERSION)
                return fail(w, CC_INVALID_ARGUMENT, "camera desc was not initialised with cc_camera_desc_init()");
            for (int k = 0; k < 16; ++k) x[c].viewProjection[k] = cameras[c].view_projection[k];
            x[c].viewportWidth = cameras[c].viewport_width;
            x[c].viewportHeight = cameras[c].viewport_height;
        }
        return report(w, w->world->setCameras(x.data(), count));
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

cc_status cc_world_get_render_mesh(const cc_world* w, cc_garment_id g, cc_render_mesh* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_mesh");
    return guarded(w, [&] {
        auto view = w->world->renderMesh(g);
        if (view.isOk()) {
            const cc::RenderMeshView& v = view.value();
            *out = cc_render_mesh{v.positions, v.normals, v.vertexCount, v.indices, v.triangleCount};
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
            const cc::GarmentStats& s = stats.value();
            *out = cc_garment_stats{s.level, s.vertexCount, uint32_t(s.solver), s.substeps, s.updateInterval,
                                    s.updated, s.levelSwitched, uint32_t(s.collision), s.selfCollision,
                                    s.contacts, s.failSafes, s.failed, s.screenRadiusPx, s.predictedErrorPx,
                                    s.predictedMs, s.measuredMs, s.collisionMs, s.maxStrain, s.maxAttachmentError};
        }
        return report(w, stats.status());
    });
}

cc_status cc_world_get_frame_stats(const cc_world* w, cc_frame_stats* out) {
    CC_CHECK_WORLD(w);
    CC_CHECK_OUT(w, out, "out_stats");
    const cc::FrameStats& f = w->world->frameStats();
    *out = cc_frame_stats{f.frame, f.scheduleMs, f.simulateMs, f.totalMs,
                          f.predictedCpuMs, f.measuredCpuMs, f.budgetCpuMs, f.garments, f.updated, f.asleep,
                          f.visible, f.failed, f.levelSwitches, {}, f.threads};
    for (int l = 0; l < 16; ++l) out->garments_per_level[l] = f.garmentsPerLevel[l];
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

} // extern "C"
