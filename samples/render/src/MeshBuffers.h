#pragma once
// GL buffer objects that each submitted mesh is copied into once, so that its colour pass and its
// shadow pass both draw from GL-owned memory instead of Mesa re-reading the caller's arrays.

#include <cstddef>
#include <cstdint>

namespace cc::render {

class MeshBuffers {
public:
    /// Needs the renderer's context to be current; the buffers live as long as that context.
    MeshBuffers();
    MeshBuffers(const MeshBuffers&) = delete;
    MeshBuffers& operator=(const MeshBuffers&) = delete;

    /// Copies the mesh, binds it and points the vertex (and, if given, normal) array at it.
    /// Draw it with glDrawElements(GL_TRIANGLES, 3 * triangleCount, GL_UNSIGNED_INT, nullptr).
    void bind(const float* positions, const float* normals, uint32_t vertexCount, const uint32_t* indices,
              uint32_t triangleCount);
    /// Unbinds, so that later client-side arrays (the text overlay) are read from memory again.
    void unbind();

private:
    unsigned mVertices = 0, mIndices = 0;
    std::size_t mVertexBytes = 0, mIndexBytes = 0;  // allocated sizes; grown, never shrunk
};

} // namespace cc::render
