#pragma once

#include <cstddef>
#include <string>

#include "crowdcloth/character/Character.h"

namespace cc {

/// How characters are read. Plain settings; validate() names the first bad field.
struct ImportSettings {
    /// Merge identical vertices (assimp's JoinIdenticalVertices). Changes vertex counts (CesiumMan:
    /// 3273 -> 2612), so garments bound to a body must be bound with the same setting.
    bool joinIdenticalVertices = true;
    /// [-] largest |sum of a vertex's skin weights in the file - 1| accepted; (0, 0.5]. The four
    /// largest weights are then renormalised to sum exactly 1.
    double weightSumTolerance = 0.02;
    /// [m per file unit] forces the unit scale; 0 = take it from the file (glTF: metres; Collada:
    /// its <unit>, applied by assimp; FBX: UnitScaleFactor, centimetres per unit).
    double unitScale = 0.0;
    /// [bytes] larger files are refused before parsing; > 0.
    std::size_t maxFileBytes = std::size_t(1) << 29;

    Status validate() const;
};

/// Reads a skinned, animated character from glTF 2 (.gltf/.glb), FBX (.fbx) or Collada (.dae)
/// through assimp: every scene node becomes a joint (so animated non-bone nodes work), the
/// skinned and unskinned triangle meshes merge into one body with at most four normalised weights
/// per vertex, every animation becomes a clip whose times are seconds from its first key
/// (ticks / mTicksPerSecond, 25 ticks/s when the file gives 0). The result is in metres with Y up.
///
/// When a mesh's bind matrices agree with the file's node rest pose (the usual case), the body's
/// bind positions are the rest pose in model space; otherwise they stay in mesh space with the
/// file's inverse bind matrices. Either way skinning reproduces assimp's skinned result.
///
/// Every count is capped before allocation and every number checked; a missing, empty,
/// oversized, truncated, malformed or unsupported file, or one whose skin weights do not sum to 1,
/// gives an error whose message starts with the file path and names the problem.
Result<Character> importCharacter(const std::string& path, const ImportSettings& settings = {});

/// Writes a character with its skeleton, skin and clips through assimp's glTF 2 exporter: .glb
/// (binary) or .gltf (JSON with its .bin beside it). Other extensions are refused: assimp 5.2.5's
/// FBX and Collada writers lose or corrupt skinned animation (see CharacterExport.cpp). Clip key
/// times are written in seconds. The character is validated first; errors name the file.
Status exportCharacter(const Character& character, const std::string& path);

} // namespace cc
