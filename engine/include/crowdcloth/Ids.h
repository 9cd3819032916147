/* Handles shared by the C and C++ APIs (C-compatible). */
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

#ifdef __cplusplus
}
#endif
