#pragma once

#include <cstddef>
#include <string>

#include "crowdcloth/ImportExport.h"
#include "crowdcloth/character/Character.h"

namespace cc {

/// Which way is up in a file, when the file does not say.
enum class ImportUpAxis {
    FromFile = 0,  ///< the file's metadata, else its format's convention (Doom 3 and Source: Z up)
    Y = 1,         ///< Y up, as crowdcloth is
    Z = 2,         ///< Z up: turned so that file +Z becomes +Y
};

/// How characters are read. Plain settings; validate() names the first bad field.
struct CC_IMPORT_API ImportSettings {
    /// Merge identical vertices (assimp's JoinIdenticalVertices). Changes vertex counts (CesiumMan:
    /// 3273 -> 2612), so garments bound to a body must be bound with the same setting.
    bool joinIdenticalVertices = true;
    /// [-] largest |sum of a vertex's skin weights in the file - 1| accepted; (0, 0.5]. The four
    /// largest weights are then renormalised to sum exactly 1.
    double weightSumTolerance = 0.02;
    /// [m per file unit] forces the unit scale; 0 = the file's (glTF: metres; Collada: its <unit>;
    /// FBX: UnitScaleFactor, centimetres per unit; OpenGEX: its distance metric), else the format's
    /// convention (MD5, SMD, Quake: inches; PMX: 8 cm; the rest: metres).
    double unitScale = 0.0;
    /// Up axis when it is to be forced (see ImportUpAxis).
    ImportUpAxis upAxis = ImportUpAxis::FromFile;
    /// [ticks/s] forces the rate clip keys are counted in; 0 = the file's (glTF, FBX, Collada, X,
    /// B3D, MD5's .md5anim frameRate, ...), else the format's convention (SMD: 30 frames/s).
    double ticksPerSecond = 0.0;
    /// [bytes] larger files are refused before parsing; > 0.
    std::size_t maxFileBytes = std::size_t(1) << 29;
    /// Parse in a child process (POSIX fork): a parser that crashes or hangs on a malformed file
    /// costs an error, never the host. false parses in this process (hosts that must not fork).
    bool isolate = true;
    /// [s] an isolated parse taking longer is stopped; (0, 3600].
    double timeoutSeconds = 120.0;
    /// [bytes] address space an isolated parse may use; 0 = no cap (none under Address- or ThreadSanitizer,
    /// whose shadow memory alone exceeds any cap).
    std::size_t maxMemoryBytes = std::size_t(4) << 30;

    Status validate() const;
};

/// Reads a skinned, animated character from any format assimp 5.2.5 reads with bones and
/// animations: glTF 2 (.gltf/.glb), FBX, Collada (.dae/.zae), DirectX (.x), Blitz3D (.b3d),
/// Doom 3 (.md5mesh with its .md5anim beside it), Valve SMD (.smd/.vta), Ogre XML (.mesh.xml with
/// its .skeleton.xml), Milkshape 3D (.ms3d), 3ds Max ASE, MikuMikuDance PMX, assimp's .assbin.
/// Formats assimp reads without bones (OBJ, STL, PLY, 3DS, OFF, OpenGEX, MD2/MD3, IQM, ...) give
/// an unskinned body whose parts follow their nodes; animation-only formats (BVH, CSM) are refused.
///
/// Every scene node becomes a joint (so animated non-bone nodes work), the skinned and unskinned
/// triangle meshes merge into one body with at most four normalised weights per vertex, every
/// animation becomes a clip whose times are seconds from its first key (ticks / mTicksPerSecond,
/// 25 ticks/s when the file gives 0). The result is in metres with Y up (see ImportSettings for
/// units and axes per format).
///
/// One validation gate for every format: the file must exist, fit the size cap and look like its
/// extension's format (magic, and for binary formats a structure that fits the file); assimp then
/// parses it (isolated in a child process by default); every count is capped before allocation and
/// every number checked. A missing, empty, oversized, truncated, malformed or unsupported file, or
/// one whose skin weights do not sum to 1, gives an error whose message starts with the file path
/// and names the problem.
CC_IMPORT_API Result<Character> importCharacter(const std::string& path, const ImportSettings& settings = {});

/// Writes a character with its skeleton, skin and clips through assimp's glTF 2 exporter: .glb
/// (binary) or .gltf (JSON with its .bin beside it). Other extensions are refused: assimp 5.2.5's
/// FBX and Collada writers lose or corrupt skinned animation (see CharacterExport.cpp). Clip key
/// times are written in seconds. The character is validated first; errors name the file.
CC_IMPORT_API Status exportCharacter(const Character& character, const std::string& path);

} // namespace cc
