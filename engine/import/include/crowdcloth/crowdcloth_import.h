/* crowdcloth import (C): bodies from character files, through the optional import library
 * (cc_import, which links assimp). Wraps crowdcloth/import/CharacterIO.h and
 * World::addCharacterBody one to one.
 *
 *   cc_import_settings is; cc_import_settings_init(&is);
 *   cc_body_desc bd; cc_body_desc_init(&bd);
 *   cc_body_id body;
 *   if (cc_world_add_body_from_file(world, "hero.fbx", &is, &bd, &body) != CC_OK)
 *       puts(cc_world_last_error(world));   // names the file and the problem
 */
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "crowdcloth/ImportExport.h"
#include "crowdcloth/crowdcloth.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum cc_up_axis { CC_UP_FROM_FILE = 0, CC_UP_Y = 1, CC_UP_Z = 2 } cc_up_axis;

typedef struct cc_import_settings {
    uint32_t version;
    int32_t join_identical_vertices;  /* 1 = merge identical vertices (assimp) */
    double weight_sum_tolerance;      /* [-] (0, 0.5] */
    double unit_scale;                /* [m per file unit] 0 = the file's or its format's */
    cc_up_axis up_axis;
    double ticks_per_second;          /* [ticks/s] 0 = the file's or its format's */
    int32_t isolate;                  /* 1 = parse in a child process */
    double timeout_seconds;           /* [s] (0, 3600] */
    uint64_t max_file_bytes;          /* [bytes] > 0 */
    uint64_t max_memory_bytes;        /* [bytes] 0 = no cap */
} cc_import_settings;

CC_IMPORT_API void cc_import_settings_init(cc_import_settings* settings);

/* Reads a skinned character (any format assimp 5.2.5 reads with bones, or an unskinned one) and
 * adds it as a body the world skins itself. settings and desc may be NULL (defaults). */
CC_IMPORT_API cc_status cc_world_add_body_from_file(cc_world* world, const char* path, const cc_import_settings* settings,
                                      const cc_body_desc* desc, cc_body_id* out_body);

#ifdef __cplusplus
}
#endif
