#pragma once

// The import fuzzer's input: one byte choosing the file's extension (every one the import gate
// knows, plus a few it refuses), then the file's bytes. Shared by the fuzzer and the test that
// checks its committed seeds read whole.

#include <cstddef>
#include <cstdint>
#include <string>

namespace cc::fuzz {

inline constexpr const char* kImportExtensions[] = {
    "glb", "gltf", "fbx", "dae", "x",   "b3d", "smd", "ms3d", "ase",     "pmx",      "assbin", "obj",
    "stl", "ply",  "off", "ogex", "3ds", "md2", "md3", "iqm",  "md5mesh", "mesh.xml", "bvh",    "txt"};
inline constexpr std::size_t kImportExtensionCount = sizeof(kImportExtensions) / sizeof(kImportExtensions[0]);

struct ImportInput {
    const char* extension;
    const uint8_t* bytes;
    std::size_t size;
};

inline ImportInput decodeImportInput(const uint8_t* data, std::size_t size) {
    if (size == 0) return {kImportExtensions[0], data, 0};
    return {kImportExtensions[data[0] % kImportExtensionCount], data + 1, size - 1};
}

/// The input that makes a file of `extension` with these bytes; empty when the extension is not in the table.
inline std::string encodeImportInput(const std::string& extension, const std::string& bytes) {
    for (std::size_t k = 0; k < kImportExtensionCount; ++k)
        if (extension == kImportExtensions[k]) return std::string(1, char(k)) + bytes;
    return {};
}

} // namespace cc::fuzz
