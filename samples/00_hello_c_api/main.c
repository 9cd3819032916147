/* 00_hello_c_api: the smallest crowdcloth program, in C.
 *
 * One procedural mannequin walks along +Z wearing a cape; a camera follows it. Every second the
 * program prints the cape's level, solver and cost; at the end the state hash (the same on every
 * run and for any thread count with the fixed cost model). Headless: no window, no files. */
#include <math.h>
#include <stdio.h>

#include "crowdcloth/crowdcloth.h"

#define CHECK(call)                                                                                  \
    do {                                                                                             \
        if ((call) != CC_OK) {                                                                       \
            fprintf(stderr, "%s failed: %s\n", #call, cc_world_last_error(world));                   \
            cc_world_destroy(world);                                                                 \
            return 1;                                                                                \
        }                                                                                            \
    } while (0)

/* A column-major OpenGL view-projection of a camera at `eye` looking at `target` (Y up). */
static void look_at(const double eye[3], const double target[3], double aspect, double out[16]) {
    double f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    double n = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; ++i) f[i] /= n;
    double s[3] = {-f[2], 0.0, f[0]}; /* f x (0, 1, 0) */
    n = sqrt(s[0] * s[0] + s[2] * s[2]);
    s[0] /= n, s[2] /= n;
    const double u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
    const double fy = 1.0 / tan(0.5 * 1.0472), nearZ = 0.1, farZ = 500.0;
    const double view[4][4] = {{s[0], s[1], s[2], -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2])},
                               {u[0], u[1], u[2], -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2])},
                               {-f[0], -f[1], -f[2], f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2]},
                               {0, 0, 0, 1}};
    const double proj[4][4] = {{fy / aspect, 0, 0, 0},
                               {0, fy, 0, 0},
                               {0, 0, (farZ + nearZ) / (nearZ - farZ), 2 * farZ * nearZ / (nearZ - farZ)},
                               {0, 0, -1, 0}};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += proj[r][k] * view[k][c];
            out[c * 4 + r] = sum;
        }
}

int main(void) {
    cc_world* world = NULL;
    cc_world_desc wd;
    cc_world_desc_init(&wd);
    wd.fixed_cost_model = 1; /* reproducible: the hash below is the same on every run */
    if (cc_world_create(&wd, &world) != CC_OK) {
        fprintf(stderr, "cc_world_create failed\n");
        return 1;
    }

    cc_cloth_asset_desc cape;
    cc_cloth_asset_desc_init(&cape); /* a 0.8 m x 1.0 m cape, 5 levels */
    cc_asset_id asset;
    CHECK(cc_world_add_cloth_asset(world, &cape, &asset));

    cc_mannequin_desc md;
    cc_mannequin_desc_init(&md);
    cc_body_id body;
    CHECK(cc_world_add_mannequin_body(world, &md, &body));

    cc_character_desc cd;
    cc_character_desc_init(&cd);
    cd.body = body;
    cd.clip = "walk";
    cc_character_id walker;
    CHECK(cc_world_add_character(world, &cd, &walker));

    cc_garment_desc gd;
    cc_garment_desc_init(&gd);
    cc_garment_id garment;
    CHECK(cc_world_add_garment(world, asset, walker, &gd, &garment));

    const double dt = 1.0 / 60.0, speed = 1.35;
    for (int frame = 1; frame <= 180; ++frame) {
        const double z = speed * frame * dt;
        const double root[3] = {0.0, 0.0, z};
        CHECK(cc_world_set_character_root(world, walker, root, 0.0));
        cc_camera_desc camera;
        cc_camera_desc_init(&camera);
        const double eye[3] = {-2.0, 1.6, z - 3.0}, target[3] = {0.0, 1.2, z};
        look_at(eye, target, camera.viewport_width / camera.viewport_height, camera.view_projection);
        CHECK(cc_world_set_cameras(world, &camera, 1));
        CHECK(cc_world_step(world, dt));
        if (frame % 60 == 0) {
            cc_garment_stats gs;
            cc_render_mesh mesh;
            CHECK(cc_world_get_garment_stats(world, garment, &gs));
            CHECK(cc_world_get_render_mesh(world, garment, &mesh));
            printf("t = %.0f s: level %d (%u vertices simulated, %u rendered), %s, %.2f ms, max strain %.2f%%\n",
                   frame * dt, gs.level, gs.vertex_count, mesh.vertex_count,
                   gs.solver == 0 ? "substep Newton" : "substep local/global",
                   gs.measured_ms, 100.0 * gs.max_strain);
        }
    }
    uint64_t hash = 0;
    CHECK(cc_world_state_hash(world, &hash));
    printf("state hash %016llx\n", (unsigned long long)hash);
    cc_world_destroy(world);
    return 0;
}
