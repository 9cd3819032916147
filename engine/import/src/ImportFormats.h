#pragma once

#include <cstddef>
#include <string>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc::detail {

/// What assimp 5.2.5 brings out of a format.
enum class FormatContent {
    Skinned,    ///< bones, skin weights and animation clips (or some of them)
    Static,     ///< meshes and nodes only: an unskinned body (rigid parts follow their nodes)
    Animation,  ///< a skeleton and clips without any mesh: no body
};

/// One file format the import gate knows: how to recognise a real file of it, and the conventions
/// its files are authored in when they say nothing themselves.
struct ImportFormat {
    const char* name = "";            ///< "Blitz3D"
    const char* extensions = "";      ///< space-separated, lower case: "b3d"
    FormatContent content = FormatContent::Static;
    double unitScale = 1.0;           ///< [m per file unit] when the file states no unit
    bool zUp = false;                 ///< authored Z up and assimp leaves it so (we turn it Y up)
    bool unitFromFile = false;        ///< the importer or the file's own metadata sets the unit
    double ticksPerSecond = 0.0;      ///< [ticks/s] the format's key rate when assimp's is wrong; 0 = assimp's
};

/// The frame rate a Doom 3 .md5anim states ("frameRate 24"), or 0.
double md5FrameRate(const std::string& animText);

/// The format of `path` by its extension ("mesh.xml" counts as one), or null.
const ImportFormat* formatOf(const std::string& path);

/// Every extension the gate accepts, for error messages (".glb, .gltf, ...").
std::string supportedExtensions();

/// Checks the first bytes (and, for binary formats, the structure) of a file of that format before
/// assimp parses it: a file that is not what its extension says, or is cut short, is refused here
/// with the reason; assimp's parsers do not all survive such input.
Status checkSignature(const ImportFormat& format, const std::string& head, const std::string& path, std::size_t size);

/// OpenGEX states its units and up axis in Metric structures that assimp 5.2.5 ignores: reads
/// them (distance in metres per unit, "z" or "y" up). False when the file has none.
bool openGexMetrics(const std::string& text, double& outMetresPerUnit, bool& outZUp);

} // namespace cc::detail
