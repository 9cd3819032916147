/* crowdcloth C API: a one-to-one wrapper of crowdcloth/World.h for engines written in C or other
 * languages. Opaque handles, status codes, defaults from *_desc_init(), out-parameters last.
 *
 *   cc_world_desc wd; cc_world_desc_init(&wd);
 *   cc_world* world; if (cc_world_create(&wd, &world) != CC_OK) return 1;
 *   ... add an asset, a body, a character, a garment; cc_world_step(world, 1.0 / 60.0); ...
 *   cc_world_destroy(world);
 *
 * Every function is safe to call with bad arguments: it returns a status and never crashes. The
 * message of the last failure is cc_world_last_error(world). Not thread-safe: one thread per world.
 * Pointers returned by the world stay valid until the next cc_world_step() or removal. */
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "crowdcloth/Export.h"
#include "crowdcloth/Ids.h"
#include "crowdcloth/Version.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum cc_status {
    CC_OK = 0,
    CC_INVALID_ARGUMENT = 1,   /* a parameter is out of its documented range, or a handle is stale */
    CC_INVALID_OPERATION = 2,  /* not allowed in the current state (e.g. call order) */
    CC_NOT_CONVERGED = 3,
    CC_NUMERICAL_FAILURE = 4,
    CC_OUT_OF_MEMORY = 5,
} cc_status;

/* Stamped into every *_desc by its init function: 'CC' in the high half, the layout in the low
 * half. create/add calls reject unstamped structs and structs of another layout (older or newer
 * headers than the library), naming the desc and both layouts. */
#define CC_DESC_MAGIC 0x43430000u
#define CC_DESC_VERSION (CC_DESC_MAGIC | 6u)

typedef struct cc_world cc_world;

typedef struct cc_world_desc {
    uint32_t version;
    uint32_t max_threads;          /* threads that step garments; 0 = all OpenMP offers */
    double frame_budget_ms;        /* [ms] wall time per frame for cloth; > 0 */
    uint32_t budget_threads;       /* threads the budget is spread over; 0 = those stepping garments.
                                      Set it (with fixed_cost_model) for results that do not depend
                                      on the thread count */
    double pixel_tolerance;        /* [px] > 0 */
    int32_t fixed_cost_model;      /* 1 = deterministic cost predictions (tests, replays) */
    double gravity[3];             /* [m/s^2] */
    cc_task_runner task_runner;    /* the host's job system for the garment tasks; NULL = OpenMP */
    void* task_runner_user_data;
    uint32_t max_update_interval;  /* [frames] power of two in [1, 64] */
    uint32_t substeps;             /* solver substeps per update of a 1/60 s frame at the finest
                                      level (a longer frame gets more); [1, 64] */
    uint32_t solver_iterations;    /* CG iterations per substep at the finest level; [1, 100] */
    uint32_t batch_size;           /* garments stepped together per solver call; [1, 8] */
    double strain_limit;           /* [-] Provot edge strain limit; 0 = off; [0, 10] */
    int32_t self_collision;        /* 1 = the scheduler may turn self-collision on */
    int32_t spend_slack;           /* 1 = budget left after the tolerance refines further */
} cc_world_desc;

typedef enum cc_garment_kind { CC_GARMENT_CAPE = 0, CC_GARMENT_SKIRT = 1, CC_GARMENT_DRESS = 2, CC_GARMENT_PONCHO = 3 } cc_garment_kind;
typedef enum cc_garment_cut { CC_CUT_STRAIGHT = 0, CC_CUT_A_LINE = 1, CC_CUT_CIRCLE = 2 } cc_garment_cut;
/* What a restore may change of the saved run (World.h's RestoreMode). */
typedef enum cc_restore_mode { CC_RESTORE_CONTINUE = 0, CC_RESTORE_OTHER_SOLVER = 1 } cc_restore_mode;

/* Sizes left at 0 are fitted to the body that wears the garment (see ClothAssetDesc in World.h). */
typedef struct cc_cloth_asset_desc {
    uint32_t version;
    cc_garment_kind kind;
    double width, length, cell_size;   /* [m]; width and length 0 = fitted */
    uint32_t level_count, render_level;
    double areal_density;              /* [kg/m^2] */
    double stretch_stiffness;          /* [N/m] */
    double shear_stiffness;            /* [N/m] */
    double bend_stiffness;             /* [N m] */
    double damping;                    /* [s] */
    double thickness;                  /* [m] */
    double friction;                   /* [-] */
    double fold_radius;                /* [m] */
    cc_garment_cut cut;
    double relative_length;            /* [body heights] used when length is 0; 0 = the kind's */
    double hem_width;                  /* [m] 0 = the cut's */
    double ease;                       /* [m] girth added to the body's */
    double velocity_damping;           /* [1/s] decay of the cloth's velocity relative to its character */
    double compression_stiffness;      /* [-] of stretch and shear shorter than rest, fraction of theirs */
} cc_cloth_asset_desc;

/* How an imported character becomes a body. */
typedef struct cc_body_desc {
    uint32_t version;
    double height;           /* [m] scale the character to this height; 0 = as authored */
} cc_body_desc;

/* Where garments sit on a body (bind space, metres, Y up); girths and widths 0 = measured. */
typedef struct cc_body_landmarks {
    uint32_t version;
    double forward[3];
    double neck_y, shoulder_y, chest_y, waist_y, hip_y;          /* [m] */
    double neck_girth, chest_girth, waist_girth, hip_girth;      /* [m] */
    double shoulder_width;                                       /* [m] */
    double stride; /* [rad] thigh swing from the vertical in the widest stride; 0 = measured */
} cc_body_landmarks;

typedef struct cc_mannequin_desc {
    uint32_t version;
    double height, shoulder_width, hip_width, waist_width; /* [m] */
    double limb_girth;                                      /* [-] */
} cc_mannequin_desc;

typedef struct cc_character_desc {
    uint32_t version;
    cc_body_id body;
    const char* clip;        /* by name (the mannequin: "idle", "walk", "run"); NULL or "" = rest pose */
    int32_t clip_index;      /* >= 0: by index into the body's clips, `clip` ignored; -1 = by name */
    double clip_time;        /* [s] */
    double clip_phase;       /* [-] fraction of the clip's length added to clip_time; [0, 1] */
    double playback_rate;    /* [-] */
    double position[3];      /* [m] */
    double yaw;              /* [rad] */
} cc_character_desc;

typedef struct cc_garment_desc {
    uint32_t version;
    double importance;       /* [-] > 0 */
    int32_t force_level;     /* uniform level to simulate every frame; -1 = scheduled */
    double inertia_scale;    /* [-] how much of the character's motion the cloth feels; [0, 2] */
} cc_garment_desc;

typedef struct cc_camera_desc {
    uint32_t version;
    double view_projection[16];  /* column-major, OpenGL clip convention */
    double viewport_width, viewport_height; /* [px] */
} cc_camera_desc;

typedef struct cc_render_mesh {
    const float* positions;  /* xyz per vertex [m] */
    const float* normals;    /* unit xyz per vertex */
    uint32_t vertex_count;
    const uint32_t* indices; /* 3 per triangle */
    uint32_t triangle_count;
} cc_render_mesh;

typedef struct cc_garment_stats {
    int32_t level;
    uint32_t vertex_count;
    uint32_t solver;          /* 0 substep Newton, 1 substep local/global */
    uint32_t substeps;
    uint32_t iterations;      /* solver iterations over the update */
    uint32_t update_interval; /* 0 = asleep */
    int32_t updated, level_switched;
    uint32_t collision;       /* 0 none, 1 proxies, 2 mesh, 3 mesh + continuous */
    int32_t self_collision;
    uint32_t contacts, fail_safes;
    int32_t failed;
    double screen_radius_px, predicted_error_px, predicted_ms, measured_ms, collision_ms, max_strain;
    double max_attachment_error;  /* [m] */
    double self_collision_ms;     /* [ms] of collision_ms spent on self-collision */
    int32_t restarted;            /* tangled with the body mesh: started again from its placement */
} cc_garment_stats;

typedef struct cc_frame_stats {
    uint64_t frame;
    double schedule_ms, simulate_ms, total_ms;  /* [ms] wall */
    double predicted_cpu_ms, measured_cpu_ms, budget_cpu_ms;
    uint32_t garments, updated, asleep, visible, failed, level_switches;
    uint32_t batches;         /* solver calls that stepped the updated garments together */
    uint32_t garments_per_level[16];
    uint32_t threads;
} cc_frame_stats;

CC_API uint32_t cc_get_version(void);

CC_API void cc_world_desc_init(cc_world_desc* desc);
/* Speed against accuracy in one choice (cc::QualityPreset): sets pixel_tolerance, substeps and
 * solver_iterations of an initialised desc; anything else stays. CC_INVALID_ARGUMENT for a null
 * desc or an unknown preset (message: cc_world_create_error()). */
typedef enum cc_quality_preset { CC_PRESET_FAST = 0, CC_PRESET_BALANCED = 1, CC_PRESET_QUALITY = 2 } cc_quality_preset;
CC_API cc_status cc_world_desc_apply_preset(cc_world_desc* desc, int32_t preset);
CC_API void cc_cloth_asset_desc_init(cc_cloth_asset_desc* desc);
CC_API void cc_mannequin_desc_init(cc_mannequin_desc* desc);
CC_API void cc_character_desc_init(cc_character_desc* desc);
CC_API void cc_garment_desc_init(cc_garment_desc* desc);
CC_API void cc_camera_desc_init(cc_camera_desc* desc);
CC_API void cc_body_desc_init(cc_body_desc* desc);
CC_API void cc_body_landmarks_init(cc_body_landmarks* landmarks);

CC_API cc_status cc_world_create(const cc_world_desc* desc, cc_world** out_world);
/* Message of the last cc_world_create() on this thread that failed ("" if none). */
CC_API const char* cc_world_create_error(void);
CC_API void cc_world_destroy(cc_world* world);
/* Message of the last call on `world` that failed ("" if none); valid until the next call. */
CC_API const char* cc_world_last_error(const cc_world* world);

CC_API cc_status cc_world_add_cloth_asset(cc_world* world, const cc_cloth_asset_desc* desc, cc_asset_id* out_asset);
/* Measured errors for the scheduler in place of its formula (World::loadErrorTable): the design's
   table for this world's effort from `directory`, cooked and cached there first when absent. */
CC_API cc_status cc_world_load_error_table(cc_world* world, cc_asset_id asset, const char* directory);
CC_API cc_status cc_world_add_mannequin_body(cc_world* world, const cc_mannequin_desc* desc, cc_body_id* out_body);
CC_API cc_status cc_world_add_skinned_body(cc_world* world, const float* bind_positions, uint32_t vertex_count,
                                    uint32_t stride_bytes, const uint32_t* triangles, uint32_t triangle_count,
                                    cc_body_id* out_body);
/* Imported characters: crowdcloth/crowdcloth_import.h (the optional import library) adds bodies
 * from files. Host-skinned bodies without a humanoid shape need the host's landmarks for garments;
 * landmarks apply to characters added afterwards. */
CC_API cc_status cc_world_set_body_landmarks(cc_world* world, cc_body_id body, const cc_body_landmarks* landmarks);
CC_API cc_status cc_world_get_body_landmarks(const cc_world* world, cc_body_id body, cc_body_landmarks* out_landmarks);
CC_API cc_status cc_world_get_body_clip_count(const cc_world* world, cc_body_id body, uint32_t* out_count);
/* Name of clip `index` of a body; valid as long as the world. */
CC_API cc_status cc_world_get_body_clip_name(const cc_world* world, cc_body_id body, uint32_t index, const char** out_name);
CC_API cc_status cc_world_add_character(cc_world* world, const cc_character_desc* desc, cc_character_id* out_character);
CC_API cc_status cc_world_remove_character(cc_world* world, cc_character_id character);
CC_API cc_status cc_world_set_character_root(cc_world* world, cc_character_id character, const double position[3], double yaw);
/* Clip seconds per world second from the next step on, [0, 10]; the clip goes on from where it is. */
CC_API cc_status cc_world_set_character_playback_rate(cc_world* world, cc_character_id character, double playback_rate);
CC_API cc_status cc_world_set_character_skinned_vertices(cc_world* world, cc_character_id character, const float* positions,
                                                  uint32_t vertex_count, uint32_t stride_bytes);
CC_API cc_status cc_world_add_garment(cc_world* world, cc_asset_id asset, cc_character_id character,
                               const cc_garment_desc* desc, cc_garment_id* out_garment);
CC_API cc_status cc_world_remove_garment(cc_world* world, cc_garment_id garment);
/* Forces a garment's uniform level from the next step on (-1 = scheduled again). */
CC_API cc_status cc_world_set_garment_level(cc_world* world, cc_garment_id garment, int32_t force_level);
CC_API cc_status cc_world_set_cameras(cc_world* world, const cc_camera_desc* cameras, uint32_t count);
CC_API cc_status cc_world_set_frame_budget(cc_world* world, double milliseconds);
/* dt in [1e-6, 0.1] s. Between begin_step and end_step the calls that change or read characters and
 * garments return CC_INVALID_OPERATION. */
CC_API cc_status cc_world_step(cc_world* world, double dt);
/* The same step in phases of tasks for the host's job system (World::beginStep in World.h), bit for
 * bit cc_world_step():
 *   cc_world_begin_step(world, dt);
 *   do { run cc_world_run_step_task(world, i) for i < cc_world_step_task_count(), any threads, and
 *        wait for all } while (cc_world_next_step_phase(world));
 *   cc_world_end_step(world);
 * cc_world_run_step_task may run concurrently: it records no last error (its status says all). A
 * task run twice in a phase is refused (CC_INVALID_OPERATION); one never run is run by
 * cc_world_next_step_phase, and cc_world_end_step then returns CC_INVALID_OPERATION with the step
 * complete. */
CC_API cc_status cc_world_begin_step(cc_world* world, double dt);
CC_API uint32_t cc_world_step_task_count(const cc_world* world);
CC_API cc_status cc_world_run_step_task(cc_world* world, uint32_t index);
/* 1 when another phase of tasks is open, 0 when the tasks are done (then cc_world_end_step). */
CC_API int32_t cc_world_next_step_phase(cc_world* world);
CC_API cc_status cc_world_end_step(cc_world* world);
CC_API cc_status cc_world_get_render_mesh(const cc_world* world, cc_garment_id garment, cc_render_mesh* out_mesh);
CC_API cc_status cc_world_get_garment_stats(const cc_world* world, cc_garment_id garment, cc_garment_stats* out_stats);
/* The design as cut for the garment's body (width, length, hem_width filled in). */
CC_API cc_status cc_world_get_garment_fit(const cc_world* world, cc_garment_id garment, cc_cloth_asset_desc* out_desc);
CC_API cc_status cc_world_get_frame_stats(const cc_world* world, cc_frame_stats* out_stats);
/* JSON text of the last frame's stats; valid until the next call on the world. */
CC_API cc_status cc_world_get_stats_json(cc_world* world, const char** out_json);
CC_API cc_status cc_world_state_hash(const cc_world* world, uint64_t* out_hash);
/* The shadow check (World::setShadowCheck): `garments` followed at once (0 = off), a reference of
   each at its asset's finest level under `substeps` x `iterations`, windows of `window_seconds`
   restarted from it; the results of the windows the last step completed, up to `capacity` into
   out_results (null when capacity is 0), their number in *out_count. */
typedef struct cc_shadow_check_result {
    cc_garment_id garment;
    int32_t level, reference_level;
    uint32_t update_interval;
    double screen_radius_px, predicted_error_px, measured_error_px;
    double measured_rms_metres, measured_max_metres;
    double reference_check_px;
    double measured_rms_px, reference_check_rms_px;
} cc_shadow_check_result;
CC_API cc_status cc_world_set_shadow_check(cc_world* world, uint32_t garments, double window_seconds,
                                           uint32_t substeps, uint32_t iterations);
CC_API cc_status cc_world_get_shadow_check_results(const cc_world* world, cc_shadow_check_result* out_results,
                                                   uint32_t capacity, uint32_t* out_count);
/* Snapshots (World::saveState / restoreState): the world's state as bytes, valid until the next
   call on the world; and a snapshot's state restored into a world made with the same desc,
   assets and bodies (its characters and garments replaced; on error nothing changes). */
CC_API cc_status cc_world_save_state(cc_world* world, const void** out_data, size_t* out_size);
CC_API cc_status cc_world_restore_state(cc_world* world, const void* data, size_t size);
/* The same with mode CC_RESTORE_OTHER_SOLVER: the world's substeps, iterations and strain limit may
   differ from the saved one's (a saved state restarted under other solver settings). `mode` is a
   cc_restore_mode value, passed as an integer so that any other value is an error, not undefined. */
CC_API cc_status cc_world_restore_state_mode(cc_world* world, const void* data, size_t size, int32_t mode);

#ifdef __cplusplus
}
#endif
