#include "MeshExport.h"

#include <cstdio>
#include <memory>
#include <vector>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

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

const aiColor3D kSkin(0.80f, 0.72f, 0.62f);

aiMesh* toAssimp(const std::string& name, const cc::RenderMeshView& m, unsigned int material) {
    auto* mesh = new aiMesh();
    mesh->mName = aiString(name);
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mMaterialIndex = material;
    mesh->mNumVertices = m.vertexCount;
    mesh->mVertices = new aiVector3D[m.vertexCount];
    mesh->mNormals = new aiVector3D[m.vertexCount];
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        mesh->mVertices[v] = aiVector3D(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
        mesh->mNormals[v] = aiVector3D(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    }
    mesh->mNumFaces = m.triangleCount;
    mesh->mFaces = new aiFace[m.triangleCount];
    for (uint32_t t = 0; t < m.triangleCount; ++t) {
        mesh->mFaces[t].mNumIndices = 3;
        mesh->mFaces[t].mIndices = new unsigned int[3]{m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]};
    }
    return mesh;
}

aiMaterial* material(const std::string& name, const aiColor3D& colour, bool twoSided) {
    auto* m = new aiMaterial();
    const aiString n(name);
    m->AddProperty(&n, AI_MATKEY_NAME);
    m->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
    const int sides = twoSided ? 1 : 0;
    m->AddProperty(&sides, 1, AI_MATKEY_TWOSIDED);
    return m;
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

cc::Status exportGlb(cc::World& world, const Plaza& plaza, const std::string& path) {
    // The scene owns (and deletes) everything hung on it, also when a mesh fails half way.
    auto scene = std::make_unique<aiScene>();
    const std::size_t n = plaza.characters().size();
    scene->mRootNode = new aiNode("crowd");
    scene->mMeshes = new aiMesh*[2 * n]();
    scene->mMaterials = new aiMaterial*[n + 1]();
    scene->mMaterials[scene->mNumMaterials++] = material("skin", kSkin, false);
    scene->mRootNode->mChildren = new aiNode*[2 * n]();
    for (std::size_t i = 0; i < n; ++i) {
        auto body = world.characterMesh(plaza.characters()[i]);
        if (!body.isOk()) return body.status();
        scene->mMeshes[scene->mNumMeshes++] = toAssimp("body_" + std::to_string(i), body.value(), 0);
        auto garment = world.renderMesh(plaza.garments()[i]);
        if (!garment.isOk()) return garment.status();
        const auto& c = plaza.garmentColours()[i];
        scene->mMaterials[scene->mNumMaterials++] =
            material("garment_" + std::to_string(i), aiColor3D(c[0], c[1], c[2]), true);
        scene->mMeshes[scene->mNumMeshes++] =
            toAssimp("garment_" + std::to_string(i), garment.value(), scene->mNumMaterials - 1);
    }
    for (unsigned int k = 0; k < scene->mNumMeshes; ++k) {
        auto* node = new aiNode(scene->mMeshes[k]->mName.C_Str());
        node->mNumMeshes = 1;
        node->mMeshes = new unsigned int[1]{k};
        node->mParent = scene->mRootNode;
        scene->mRootNode->mChildren[scene->mRootNode->mNumChildren++] = node;
    }
    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), "glb2", path) != aiReturn_SUCCESS)
        return cc::Status::invalidArgument(path + ": assimp glTF export failed: " + exporter.GetErrorString());
    return cc::Status::ok();
}

} // namespace crowd
