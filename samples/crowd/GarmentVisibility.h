#pragma once
// Which garments the camera sees this frame. GarmentStats does not say (only FrameStats counts
// them), and a garment behind the eye has a meaningless predicted error (millions of pixels), so
// the per-frame error columns are taken over the garments in view.

#include <vector>

#include "Plaza.h"
#include "crowdcloth/World.h"

namespace crowd {

/// Per garment of plaza.garments(): does the bounding sphere of its render mesh meet the view
/// frustum of plaza.viewProjection()?
cc::Result<std::vector<bool>> garmentsInView(const cc::World& world, const Plaza& plaza);

} // namespace crowd
