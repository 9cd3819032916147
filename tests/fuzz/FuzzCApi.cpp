// Fuzz target: the C API (crowdcloth/crowdcloth.h) called as a C host might get it wrong: null
// pointers for descs and out-parameters, unstamped and foreign desc versions, enum values out of
// range, handles made up or stale, the phased step's calls out of order and with any task index,
// snapshots of any bytes. The header's promise is checked: every call returns a cc_status and
// never crashes, a failure leaves a message naming it, and what a call hands out (meshes, stats,
// names, JSON, snapshots) is readable and finite; a sloppy host's step (a task skipped, another
// run twice) stays whole. FuzzWorld.cpp fuzzes the World behind it.
// Built for libFuzzer with -DCC_BUILD_FUZZERS=ON (clang), and always as cc_fuzz_capi_replay,
// which runs the committed corpus (tests/fuzz/capi_corpus) in CTest.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "FuzzInput.h"
#include "crowdcloth/crowdcloth.h"

namespace {

using cc::fuzz::Input;

[[noreturn]] void fail(const char* what, const char* detail) {
    std::fprintf(stderr, "FuzzCApi: %s: %s\n", what, detail);
    std::abort();
}

/// A status is one of the enum's values; a failure leaves a message on the world.
cc_status checked(cc_world* world, cc_status s, const char* call) {
    if (int(s) < int(CC_OK) || int(s) > int(CC_OUT_OF_MEMORY))
        fail(call, "returned a value outside cc_status");
    if (s != CC_OK && world) {
        const char* message = cc_world_last_error(world);
        if (!message || !message[0]) fail(call, "failed without a message");
    }
    return s;
}

/// A desc's version as a host might leave it: stamped (mostly), zero, or another layout.
uint32_t version(Input& in) {
    switch (in.byte() % 8) {
    case 0: return 0;
    case 1: return CC_DESC_MAGIC | (CC_DESC_VERSION + 1);
    case 2: return in.u32();
    default: return CC_DESC_VERSION;
    }
}

/// One of the handles made so far, a stale or made-up one, or zero.
template <typename Id>
Id pick(Input& in, const std::vector<Id>& ids) {
    const uint8_t how = in.byte();
    if (how % 8 == 0) return Id{in.u32() % 8, in.u32() % 4};
    if (ids.empty() || how % 8 == 1) return Id{0, 0};
    Id id = ids[in.byte() % ids.size()];
    if (how % 8 == 2) ++id.generation;
    return id;
}

void checkMesh(const cc_render_mesh& m) {
    if (m.vertex_count && (!m.positions || !m.normals))
        fail("cc_world_get_render_mesh", "null arrays");
    if (m.triangle_count && !m.indices) fail("cc_world_get_render_mesh", "null indices");
    for (uint32_t i = 0; i < 3 * m.vertex_count; ++i)
        if (!std::isfinite(m.positions[i]) || !std::isfinite(m.normals[i]))
            fail("cc_world_get_render_mesh", "a non-finite vertex");
    for (uint32_t i = 0; i < 3 * m.triangle_count; ++i)
        if (m.indices[i] >= m.vertex_count)
            fail("cc_world_get_render_mesh", "an index past the vertices");
}

void addAsset(Input& in, cc_world* w, std::vector<cc_asset_id>& assets) {
    cc_cloth_asset_desc d;
    cc_cloth_asset_desc_init(&d);
    d.version = version(in);
    d.kind = cc_garment_kind(int32_t(in.byte() % 7) - 1);
    d.cut = cc_garment_cut(int32_t(in.byte() % 5) - 1);
    d.level_count = 1 + in.byte() % 4;
    d.render_level = d.level_count - 1 + in.byte() % 2;
    if (in.byte() % 2) d.width = in.real(0.0, 3.0);
    if (in.byte() % 2) d.length = in.real(0.0, 3.0);
    if (in.byte() % 3 == 0) d.cell_size = in.real(0.08, 1.0);
    if (in.byte() % 3 == 0) d.relative_length = in.real(0.0, 1.0);
    if (in.byte() % 3 == 0) d.ease = in.real(-0.5, 0.5);
    if (in.byte() % 3 == 0) d.compression_stiffness = in.real(0.0, 1.0);
    // Sizes that keep one input fast: a fuzzer that cooks a 10^6-vertex garment learns nothing.
    if (!(d.cell_size >= 0.08 && d.width <= 3.0 && d.length <= 3.0)) return;
    cc_asset_id id{};
    const bool nullDesc = in.byte() % 16 == 0, nullOut = in.byte() % 16 == 0;
    if (checked(w, cc_world_add_cloth_asset(w, nullDesc ? nullptr : &d, nullOut ? nullptr : &id),
                "cc_world_add_cloth_asset") == CC_OK) {
        if (nullDesc || nullOut) fail("cc_world_add_cloth_asset", "took a null pointer");
        assets.push_back(id);
    }
}

void addBody(Input& in, cc_world* w, std::vector<cc_body_id>& bodies) {
    cc_body_id id{};
    cc_status s;
    if (in.byte() % 2) {
        cc_mannequin_desc m;
        cc_mannequin_desc_init(&m);
        m.version = version(in);
        m.height = in.real(1.0, 2.5);
        m.limb_girth = in.real(0.6, 1.6);
        s = checked(w, cc_world_add_mannequin_body(w, in.byte() % 16 ? &m : nullptr, &id),
                    "cc_world_add_mannequin_body");
    } else { // a host-skinned body with any mesh, stride and counts
        const uint32_t n = in.byte() % 12, t = in.byte() % 12;
        std::vector<float> v(4 * n + 4);
        for (float& x : v) x = float(in.real(-1.0, 1.0));
        std::vector<uint32_t> tri(3 * t + 3);
        for (uint32_t& i : tri) i = in.byte() % (n + 2);
        const uint32_t stride = in.byte() % 4 == 0 ? in.byte() % 20 : 12;
        s = checked(w,
                    cc_world_add_skinned_body(w, in.byte() % 16 ? v.data() : nullptr, n, stride,
                                              in.byte() % 16 ? tri.data() : nullptr, t, &id),
                    "cc_world_add_skinned_body");
    }
    if (s == CC_OK) bodies.push_back(id);
}

void readBody(Input& in, cc_world* w, const std::vector<cc_body_id>& bodies) {
    const cc_body_id body = pick(in, bodies);
    uint32_t clips = 0;
    if (checked(w, cc_world_get_body_clip_count(w, body, in.byte() % 16 ? &clips : nullptr),
                "cc_world_get_body_clip_count") != CC_OK)
        return;
    const char* name = nullptr;
    if (checked(w, cc_world_get_body_clip_name(w, body, in.byte() % (clips + 2), &name),
                "cc_world_get_body_clip_name") == CC_OK &&
        (!name || std::strlen(name) > 4096))
        fail("cc_world_get_body_clip_name", "no name or an unterminated one");
    cc_body_landmarks l;
    cc_body_landmarks_init(&l);
    if (checked(w, cc_world_get_body_landmarks(w, body, &l), "cc_world_get_body_landmarks") !=
        CC_OK)
        return;
    if (in.byte() % 2) { // handed back, changed
        l.version = version(in);
        double* measures[] = {&l.neck_y,    &l.shoulder_y,     &l.waist_y,
                              &l.hip_girth, &l.shoulder_width, &l.forward[0]};
        *measures[in.byte() % 6] = in.real(-1.0, 3.0);
        (void)checked(w, cc_world_set_body_landmarks(w, body, in.byte() % 16 ? &l : nullptr),
                      "cc_world_set_body_landmarks");
    }
}

void addCharacter(Input& in, cc_world* w, const std::vector<cc_body_id>& bodies,
                  std::vector<cc_character_id>& characters) {
    cc_character_desc c;
    cc_character_desc_init(&c);
    c.version = version(in);
    c.body = pick(in, bodies);
    const char* clips[] = {"walk", "run", "idle", "", "no such clip", nullptr};
    c.clip = clips[in.byte() % 6];
    c.clip_index = int32_t(in.byte() % 6) - 2;
    c.clip_time = in.real(0.0, 10.0);
    c.clip_phase = in.real(0.0, 1.0);
    c.playback_rate = in.real(0.0, 10.0);
    c.position[0] = in.real(-50.0, 50.0);
    c.yaw = in.real(-7.0, 7.0);
    cc_character_id id{};
    if (checked(w, cc_world_add_character(w, in.byte() % 16 ? &c : nullptr, &id),
                "cc_world_add_character") == CC_OK)
        characters.push_back(id);
}

void addGarment(Input& in, cc_world* w, const std::vector<cc_asset_id>& assets,
                const std::vector<cc_character_id>& characters,
                std::vector<cc_garment_id>& garments) {
    cc_garment_desc g;
    cc_garment_desc_init(&g);
    g.version = version(in);
    g.importance = in.real(0.1, 10.0);
    g.force_level = int32_t(in.byte() % 6) - 2;
    g.inertia_scale = in.real(0.0, 2.0);
    cc_garment_id id{};
    if (checked(w,
                cc_world_add_garment(w, pick(in, assets), pick(in, characters),
                                     in.byte() % 16 ? &g : nullptr, &id),
                "cc_world_add_garment") == CC_OK)
        garments.push_back(id);
}

void changeCharacter(Input& in, cc_world* w, const std::vector<cc_character_id>& characters) {
    const cc_character_id c = pick(in, characters);
    switch (in.byte() % 4) {
    case 0: {
        const double p[3] = {in.real(-50.0, 50.0), in.real(-1.0, 1.0), in.real(-50.0, 50.0)};
        (void)checked(
            w, cc_world_set_character_root(w, c, in.byte() % 16 ? p : nullptr, in.real(-7.0, 7.0)),
            "cc_world_set_character_root");
        break;
    }
    case 1:
        (void)checked(w, cc_world_set_character_playback_rate(w, c, in.real(0.0, 10.0)),
                      "cc_world_set_character_playback_rate");
        break;
    case 2: {
        const uint32_t n = in.byte() % 12;
        std::vector<float> v(4 * n + 4);
        for (float& x : v) x = float(in.real(-1.0, 1.0));
        const uint32_t stride = in.byte() % 4 == 0 ? in.byte() % 20 : 12;
        (void)checked(w,
                      cc_world_set_character_skinned_vertices(
                          w, c, in.byte() % 16 ? v.data() : nullptr, n, stride),
                      "cc_world_set_character_skinned_vertices");
        break;
    }
    default: (void)checked(w, cc_world_remove_character(w, c), "cc_world_remove_character"); break;
    }
}

void setView(Input& in, cc_world* w) {
    switch (in.byte() % 3) {
    case 0: {
        cc_camera_desc cameras[2];
        for (cc_camera_desc& camera : cameras) {
            cc_camera_desc_init(&camera);
            camera.version = version(in);
            for (double& x : camera.view_projection) x = in.byte() % 2 ? in.real(-2.0, 2.0) : x;
            camera.viewport_width = in.real(1.0, 4000.0);
        }
        const uint32_t count = in.byte() % 4; // 3: more than the array holds, with a null pointer
        (void)checked(w, cc_world_set_cameras(w, count == 3 ? nullptr : cameras, count),
                      "cc_world_set_cameras");
        break;
    }
    case 1:
        (void)checked(w, cc_world_set_frame_budget(w, in.real(0.0, 50.0)),
                      "cc_world_set_frame_budget");
        break;
    default:
        (void)checked(w,
                      cc_world_set_shadow_check(w, in.byte() % 3, in.real(0.05, 1.0), in.byte() % 8,
                                                in.byte() % 8),
                      "cc_world_set_shadow_check");
        break;
    }
}

/// A step whole, or in phases with each phase's tasks in any order plus one past the count, and
/// calls that must wait for the step's end made in the middle of it; a sloppy host's phase skips a
/// task and runs another twice (refused; the skipped one is run for it, and end_step says so).
void step(Input& in, cc_world* w, const std::vector<cc_garment_id>& garments) {
    const double dt = in.byte() % 8 ? 1.0 / 60.0 : in.real(0.0, 0.2);
    if (in.byte() % 2) {
        (void)checked(w, cc_world_step(w, dt), "cc_world_step");
        return;
    }
    if (checked(w, cc_world_begin_step(w, dt), "cc_world_begin_step") != CC_OK) return;
    bool skipped = false;
    for (int phase = 0; phase < 16; ++phase) {
        const uint32_t tasks = cc_world_step_task_count(w);
        const uint32_t start = tasks ? in.byte() % tasks : 0;
        const bool sloppy = tasks > 1 && in.byte() % 8 == 0;
        for (uint32_t k = sloppy ? 1 : 0; k < tasks; ++k) // a rotation: each task once
            if (cc_world_run_step_task(w, (start + k) % tasks) != CC_OK)
                fail("cc_world_run_step_task", "refused a task");
        if (sloppy && cc_world_run_step_task(w, (start + 1) % tasks) == CC_OK)
            fail("cc_world_run_step_task", "ran a task twice in one phase");
        skipped = skipped || sloppy;
        if (cc_world_run_step_task(w, tasks + in.byte() % 4) == CC_OK)
            fail("cc_world_run_step_task", "ran a task past the count");
        if (in.byte() % 8 == 0 &&
            (checked(w, cc_world_remove_garment(w, pick(in, garments)),
                     "cc_world_remove_garment mid-step") == CC_OK ||
             checked(w, cc_world_step(w, dt), "cc_world_step mid-step") == CC_OK))
            fail("a call mid-step", "was carried out between begin_step and end_step");
        if (!cc_world_next_step_phase(w)) break;
    }
    const cc_status end = checked(w, cc_world_end_step(w), "cc_world_end_step");
    if (skipped && end != CC_INVALID_OPERATION)
        fail("cc_world_end_step", "did not report the skipped task");
}

void read(Input& in, cc_world* w, const std::vector<cc_garment_id>& garments) {
    const cc_garment_id g = pick(in, garments);
    cc_render_mesh mesh{};
    if (checked(w, cc_world_get_render_mesh(w, g, in.byte() % 16 ? &mesh : nullptr),
                "cc_world_get_render_mesh") == CC_OK)
        checkMesh(mesh);
    cc_garment_stats stats{};
    if (checked(w, cc_world_get_garment_stats(w, g, &stats), "cc_world_get_garment_stats") ==
            CC_OK &&
        !(stats.max_strain >= 0.0))
        fail("cc_world_get_garment_stats", "a negative or non-finite strain");
    cc_cloth_asset_desc fit;
    (void)checked(w, cc_world_get_garment_fit(w, g, &fit), "cc_world_get_garment_fit");
    (void)checked(w, cc_world_set_garment_level(w, g, int32_t(in.byte() % 8) - 2),
                  "cc_world_set_garment_level");
    cc_frame_stats frame{};
    (void)checked(w, cc_world_get_frame_stats(w, in.byte() % 16 ? &frame : nullptr),
                  "cc_world_get_frame_stats");
    const char* json = nullptr;
    if (checked(w, cc_world_get_stats_json(w, &json), "cc_world_get_stats_json") == CC_OK &&
        (!json || json[0] != '{'))
        fail("cc_world_get_stats_json", "not a JSON object");
    cc_shadow_check_result results[4];
    uint32_t count = 0;
    const uint32_t capacity = in.byte() % 5;
    (void)checked(
        w, cc_world_get_shadow_check_results(w, capacity ? results : nullptr, capacity, &count),
        "cc_world_get_shadow_check_results");
    if (count > capacity && capacity)
        fail("cc_world_get_shadow_check_results", "more results than the capacity");
    if (in.byte() % 8 == 0)
        (void)checked(w, cc_world_remove_garment(w, g), "cc_world_remove_garment");
}

/// Saved and restored whole (the hash comes back), damaged (refused or taken, never a crash), and
/// restored in any mode.
void snapshot(Input& in, cc_world* w) {
    const void* data = nullptr;
    size_t size = 0;
    if (checked(w, cc_world_save_state(w, &data, &size), "cc_world_save_state") != CC_OK) return;
    if (!data || size == 0) fail("cc_world_save_state", "no bytes");
    const std::vector<uint8_t> bytes(static_cast<const uint8_t*>(data),
                                     static_cast<const uint8_t*>(data) + size);
    uint64_t before = 0, after = 0;
    (void)checked(w, cc_world_state_hash(w, &before), "cc_world_state_hash");
    std::vector<uint8_t> bad = bytes;
    bad.resize(in.byte() % 2 ? bad.size() : in.u32() % (bad.size() + 1));
    if (!bad.empty()) bad[in.u32() % bad.size()] ^= uint8_t(1 + in.byte() % 255);
    (void)checked(
        w, cc_world_restore_state_mode(w, bad.data(), bad.size(), int32_t(in.byte() % 4) - 1),
        "cc_world_restore_state_mode");
    if (checked(w, cc_world_restore_state(w, bytes.data(), bytes.size()),
                "cc_world_restore_state") != CC_OK ||
        checked(w, cc_world_state_hash(w, &after), "cc_world_state_hash") != CC_OK ||
        after != before)
        fail("cc_world_restore_state", "the world's own snapshot did not restore it");
}

void run(Input& in) {
    cc_world_desc wd;
    cc_world_desc_init(&wd);
    wd.version = version(in);
    wd.fixed_cost_model = 1;
    wd.max_threads = 1 + in.byte() % 2;
    if (in.byte() % 4 == 0) wd.frame_budget_ms = in.real(0.1, 50.0);
    if (in.byte() % 4 == 0) wd.substeps = in.u32() % 80;
    if (in.byte() % 4 == 0) wd.batch_size = in.byte() % 10;
    if (in.byte() % 4 == 0) wd.max_update_interval = in.byte() % 80;
    if (in.byte() % 4 == 0) wd.strain_limit = in.real(0.0, 11.0);
    if (in.byte() % 4 == 0) wd.self_collision = int32_t(in.byte() % 3) - 1;
    cc_world* w = nullptr;
    if (cc_world_create(in.byte() % 32 ? &wd : nullptr, in.byte() % 32 ? &w : nullptr) != CC_OK) {
        const char* message = cc_world_create_error();
        if (!message || !message[0]) fail("cc_world_create", "failed without a message");
        return;
    }
    if (!w) fail("cc_world_create", "succeeded without a world");
    std::vector<cc_asset_id> assets;
    std::vector<cc_body_id> bodies;
    std::vector<cc_character_id> characters;
    std::vector<cc_garment_id> garments;
    for (int op = 0; op < 40 && !in.empty(); ++op) {
        switch (in.byte() % 11) {
        case 0: addAsset(in, w, assets); break;
        case 1: addBody(in, w, bodies); break;
        case 2: readBody(in, w, bodies); break;
        case 3: addCharacter(in, w, bodies, characters); break;
        case 4: addGarment(in, w, assets, characters, garments); break;
        case 5: changeCharacter(in, w, characters); break;
        case 6: setView(in, w); break;
        case 7: read(in, w, garments); break;
        case 8: snapshot(in, w); break;
        default: step(in, w, garments); break;
        }
    }
    // Null worlds everywhere are refused, not dereferenced.
    if (cc_world_step(nullptr, 1.0 / 60.0) == CC_OK || cc_world_step_task_count(nullptr) != 0 ||
        cc_world_last_error(nullptr) == nullptr)
        fail("a null world", "was taken");
    cc_world_destroy(w);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    Input in(data, size);
    run(in);
    return 0;
}
