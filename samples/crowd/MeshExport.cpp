#include "MeshExport.h"

#include <cstdio>
#include <memory>

namespace crowd {
namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

/// Appends one mesh; OBJ indices are 1-based and global, so `firstVertex` counts what came before.
void writeObject(std::FILE* f, const char* name, std::size_t index, const cc::RenderMeshView& m, uint64_t& firstVertex) {
    std::fprintf(f, "o %s_%zu\n", name, index);
    for (uint32_t v = 0; v < m.vertexCount; ++v)
        std::fprintf(f, "v %.5f %.5f %.5f\n", m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    for (uint32_t v = 0; v < m.vertexCount; ++v)
        std::fprintf(f, "vn %.4f %.4f %.4f\n", m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    for (uint32_t t = 0; t < m.triangleCount; ++t) {
        const uint64_t a = firstVertex + m.indices[3 * t], b = firstVertex + m.indices[3 * t + 1],
                       c = firstVertex + m.indices[3 * t + 2];
        std::fprintf(f, "f %llu//%llu %llu//%llu %llu//%llu\n", (unsigned long long)a, (unsigned long long)a,
                     (unsigned long long)b, (unsigned long long)b, (unsigned long long)c, (unsigned long long)c);
    }
    firstVertex += m.vertexCount;
}

} // namespace

cc::Status exportObj(cc::World& world, const Plaza& plaza, const std::string& path) {
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "w"));
    if (!f) return cc::Status::invalidArgument(path + ": cannot be written");
    std::fprintf(f.get(), "# crowdcloth cc_crowd frame: %zu bodies and garments, metres, Y up\n",
                 plaza.characters().size());
    uint64_t firstVertex = 1;
    for (std::size_t i = 0; i < plaza.characters().size(); ++i) {
        auto body = world.characterMesh(plaza.characters()[i]);
        if (!body.isOk()) return body.status();
        writeObject(f.get(), "body", i, body.value(), firstVertex);
        auto garment = world.renderMesh(plaza.garments()[i]);
        if (!garment.isOk()) return garment.status();
        writeObject(f.get(), "garment", i, garment.value(), firstVertex);
    }
    if (std::ferror(f.get())) return cc::Status::invalidArgument(path + ": write failed (disk full?)");
    return cc::Status::ok();
}

} // namespace crowd
