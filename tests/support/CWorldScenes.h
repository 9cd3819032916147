#pragma once

#include <cstring>

#include "crowdcloth/crowdcloth.h"
#include "support/CrowdScenes.h"

namespace cc::test {

/// A world made through the C API (fixed costs): one standing mannequin wearing one garment of
/// `asset`, seen by `camera`.
struct CWorldScene {
    cc_world* world = nullptr;
    cc_asset_id asset{};
    cc_body_id body{};
    cc_character_id character{};
    cc_garment_id garment{};
};

/// The first failing call's status (the world, if made, is in `out` for the caller to destroy).
inline cc_status makeCWorldScene(const cc_cloth_asset_desc& asset, const CameraDesc& camera, CWorldScene& out) {
    cc_world_desc wd;
    cc_world_desc_init(&wd);
    wd.fixed_cost_model = 1;
    cc_status s = cc_world_create(&wd, &out.world);
    if (s == CC_OK) s = cc_world_add_cloth_asset(out.world, &asset, &out.asset);
    cc_mannequin_desc md;
    cc_mannequin_desc_init(&md);
    if (s == CC_OK) s = cc_world_add_mannequin_body(out.world, &md, &out.body);
    cc_character_desc cd;
    cc_character_desc_init(&cd);
    cd.body = out.body;
    if (s == CC_OK) s = cc_world_add_character(out.world, &cd, &out.character);
    cc_garment_desc gd;
    cc_garment_desc_init(&gd);
    if (s == CC_OK) s = cc_world_add_garment(out.world, out.asset, out.character, &gd, &out.garment);
    cc_camera_desc cam;
    cc_camera_desc_init(&cam);
    std::memcpy(cam.view_projection, camera.viewProjection, sizeof(cam.view_projection));
    cam.viewport_width = camera.viewportWidth;
    cam.viewport_height = camera.viewportHeight;
    if (s == CC_OK) s = cc_world_set_cameras(out.world, &cam, 1);
    return s;
}

} // namespace cc::test
