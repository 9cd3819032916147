#pragma once
// --export obj|glb: one frame's body and garment meshes for other tools (DCC packages, diffing,
// offline renderers), in world space [m], Y up.

#include <string>

#include "Plaza.h"
#include "crowdcloth/World.h"

namespace crowd {

/// Wavefront OBJ: one object per mesh, "body_<i>" and "garment_<i>" for character i.
cc::Status exportObj(cc::World& world, const Plaza& plaza, const std::string& path);
/// Binary glTF 2 (through assimp): the same meshes as nodes, garments two-sided in their colours.
cc::Status exportGlb(cc::World& world, const Plaza& plaza, const std::string& path);

} // namespace crowd
