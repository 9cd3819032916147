/* Handles and callbacks shared by the C and C++ APIs (C-compatible). */
#pragma once

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A handle is a slot index plus one (0 = null) and the slot's generation, so a handle to a removed
 * object is recognised as stale even after its slot is reused (Box2D's ids). */
typedef struct cc_asset_id { uint32_t index1; uint32_t generation; } cc_asset_id;
typedef struct cc_body_id { uint32_t index1; uint32_t generation; } cc_body_id;
typedef struct cc_character_id { uint32_t index1; uint32_t generation; } cc_character_id;
typedef struct cc_garment_id { uint32_t index1; uint32_t generation; } cc_garment_id;

/* A host's job system: runs task(context, i) for every i in [0, count), in any order and on any
 * threads, and returns when all have finished. Tasks are independent (each writes only its own
 * garments), so the result does not depend on how they are run. */
typedef void (*cc_task_fn)(void* context, uint32_t index);
typedef void (*cc_task_runner)(void* user_data, uint32_t count, cc_task_fn task, void* context);

#ifdef __cplusplus
}
#endif
