#pragma once
// --export obj: one frame's body and garment meshes as a Wavefront OBJ, one object per mesh, for
// other tools (DCC packages, diffing, offline renderers).

#include <string>

#include "Plaza.h"
#include "crowdcloth/World.h"

namespace crowd {

/// Writes every character's body ("body_<i>") and garment ("garment_<i>") in world space [m].
cc::Status exportObj(cc::World& world, const Plaza& plaza, const std::string& path);

} // namespace crowd
