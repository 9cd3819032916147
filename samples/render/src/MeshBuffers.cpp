#define GL_GLEXT_PROTOTYPES  // buffer objects are core GL 1.5; libOSMesa exports them
#include "MeshBuffers.h"

#include <GL/gl.h>
#include <GL/glext.h>

namespace cc::render {
namespace {

// Reuses the allocation while it is large enough: reallocating per draw costs more than the copy.
void reserve(GLenum target, std::size_t& allocated, std::size_t bytes) {
    if (bytes <= allocated) return;
    allocated = bytes + bytes / 2;
    glBufferData(target, GLsizeiptr(allocated), nullptr, GL_STREAM_DRAW);
}

} // namespace

MeshBuffers::MeshBuffers() {
    GLuint names[2];
    glGenBuffers(2, names);
    mVertices = names[0];
    mIndices = names[1];
}

void MeshBuffers::bind(const float* positions, const float* normals, uint32_t vertexCount, const uint32_t* indices,
                       uint32_t triangleCount) {
    const std::size_t arrayBytes = std::size_t(vertexCount) * 3 * sizeof(float);
    const std::size_t indexBytes = std::size_t(triangleCount) * 3 * sizeof(uint32_t);
    glBindBuffer(GL_ARRAY_BUFFER, mVertices);
    reserve(GL_ARRAY_BUFFER, mVertexBytes, normals ? 2 * arrayBytes : arrayBytes);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(arrayBytes), positions);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, nullptr);
    if (normals) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(arrayBytes), GLsizeiptr(arrayBytes), normals);
        glEnableClientState(GL_NORMAL_ARRAY);
        glNormalPointer(GL_FLOAT, 0, reinterpret_cast<const void*>(arrayBytes));
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mIndices);
    reserve(GL_ELEMENT_ARRAY_BUFFER, mIndexBytes, indexBytes);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(indexBytes), indices);
}

void MeshBuffers::unbind() {
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
}

} // namespace cc::render
