/* A C99 host: one walking mannequin wearing a cape through the C API, and the import library's
 * error for a missing file. */
#include <stdio.h>
#include <string.h>

#include "crowdcloth/crowdcloth.h"
#include "crowdcloth/crowdcloth_import.h"

#define CHECK(call)                                                                                \
    do {                                                                                           \
        if ((call) != CC_OK) {                                                                     \
            fprintf(stderr, "%s failed: %s\n", #call, cc_world_last_error(world));                 \
            return 1;                                                                              \
        }                                                                                          \
    } while (0)

int main(void) {
    if (cc_get_version() != CC_VERSION) {
        fprintf(stderr, "library %x, headers %x\n", (unsigned)cc_get_version(),
                (unsigned)CC_VERSION);
        return 1;
    }
    cc_world_desc wd;
    cc_world_desc_init(&wd);
    wd.fixed_cost_model = 1;
    cc_world* world = NULL;
    if (cc_world_create(&wd, &world) != CC_OK) return 1;

    cc_cloth_asset_desc ad;
    cc_cloth_asset_desc_init(&ad);
    cc_asset_id cape;
    CHECK(cc_world_add_cloth_asset(world, &ad, &cape));
    cc_mannequin_desc md;
    cc_mannequin_desc_init(&md);
    cc_character_desc cd;
    cc_character_desc_init(&cd);
    CHECK(cc_world_add_mannequin_body(world, &md, &cd.body));
    cc_character_id walker;
    CHECK(cc_world_add_character(world, &cd, &walker));
    cc_garment_desc gd;
    cc_garment_desc_init(&gd);
    cc_garment_id garment;
    CHECK(cc_world_add_garment(world, cape, walker, &gd, &garment));
    for (int frame = 0; frame < 10; ++frame) CHECK(cc_world_step(world, 1.0 / 60.0));
    uint64_t hash = 0;
    CHECK(cc_world_state_hash(world, &hash));

    cc_body_id body;
    if (cc_world_add_body_from_file(world, "no-such-file.glb", NULL, NULL, &body) == CC_OK ||
        strstr(cc_world_last_error(world), "no-such-file.glb") == NULL) {
        fprintf(stderr, "importing a missing file: expected an error naming it, got '%s'\n",
                cc_world_last_error(world));
        return 1;
    }
    printf("c99 consumer: crowdcloth %s, hash %016llx\n", CC_VERSION_STRING,
           (unsigned long long)hash);
    cc_world_destroy(world);
    return 0;
}
