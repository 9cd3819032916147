#pragma once
// Draws one frame of the plaza: ground, bodies, garments (in their colours or a --color-by overlay)
// and a title strip with the frame's numbers.

#include <string>
#include <vector>

#include "CommandLine.h"
#include "Plaza.h"
#include "crowdcloth/World.h"
#include "crowdcloth/render/OffscreenRenderer.h"

namespace crowd {

/// "frame 120  t 2.00 s  cloth 3.4 ms  200 garments: 50 updated 180 visible 10 asleep  L0:12 L1:30 ..."
std::string titleText(int frame, double time, const cc::FrameStats& stats);

/// Renders the frame and writes it to `pngPath`. `garments` are this frame's stats of
/// plaza.garments(), in order; `pixelTolerance` scales the error overlay.
cc::Status renderFrame(cc::World& world, const Plaza& plaza, const std::vector<cc::GarmentStats>& garments,
                       ColorBy colorBy, double pixelTolerance, const std::string& title,
                       cc::render::OffscreenRenderer& renderer, const std::string& pngPath);

} // namespace crowd
