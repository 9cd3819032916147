#include "crowdcloth/import/CharacterIO.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "AssimpConvert.h"

namespace cc {
namespace {

using detail::lowerExtension;
using detail::toAi;

// Export-time sampling rate of clip times: glTF 2 is read back by assimp at 1000 ticks per
// second, and the exporters divide key times by mTicksPerSecond, so keys are written in ms.
constexpr double kTicksPerSecond = 1000.0;

template <typename T>
T* newArray(std::size_t n) {
    return n == 0 ? nullptr : new T[n];
}

aiNodeAnim* makeChannel(const JointChannel& ch, const Joint& joint) {
    auto* a = new aiNodeAnim();
    a->mNodeName = aiString(joint.name);
    // Every curve gets at least one key (the rest value): some exporters assume non-empty curves.
    const auto fillVec = [](const std::vector<double>& times, const std::vector<Vec3>& values, const Vec3& rest,
                            aiVectorKey*& outKeys, unsigned int& outCount) {
        const std::size_t n = std::max<std::size_t>(1, times.size());
        outKeys = new aiVectorKey[n];
        outCount = static_cast<unsigned int>(n);
        for (std::size_t k = 0; k < n; ++k) {
            outKeys[k].mTime = times.empty() ? 0.0 : times[k] * kTicksPerSecond;
            outKeys[k].mValue = toAi(times.empty() ? rest : values[k]);
        }
    };
    fillVec(ch.translationTimes, ch.translations, joint.restLocal.translation, a->mPositionKeys, a->mNumPositionKeys);
    fillVec(ch.scaleTimes, ch.scales, joint.restLocal.scale, a->mScalingKeys, a->mNumScalingKeys);
    const std::size_t n = std::max<std::size_t>(1, ch.rotationTimes.size());
    a->mRotationKeys = new aiQuatKey[n];
    a->mNumRotationKeys = static_cast<unsigned int>(n);
    for (std::size_t k = 0; k < n; ++k) {
        a->mRotationKeys[k].mTime = ch.rotationTimes.empty() ? 0.0 : ch.rotationTimes[k] * kTicksPerSecond;
        a->mRotationKeys[k].mValue = toAi(ch.rotationTimes.empty() ? joint.restLocal.rotation : ch.rotations[k]);
    }
    return a;
}

std::unique_ptr<aiScene> buildScene(const Character& c) {
    auto scene = std::make_unique<aiScene>();
    const Skeleton& sk = c.skeleton;
    const SkinnedMesh& body = c.body;

    // Nodes: a scene root holding the skeleton's roots and the body's mesh node.
    std::vector<aiNode*> nodes(sk.jointCount());
    std::vector<std::vector<aiNode*>> children(sk.jointCount());
    std::vector<aiNode*> rootChildren;
    for (std::size_t j = 0; j < sk.jointCount(); ++j) {
        nodes[j] = new aiNode(sk.joints[j].name);
        nodes[j]->mTransformation = toAi(sk.joints[j].restLocal.matrix());
        if (sk.joints[j].parent < 0) {
            rootChildren.push_back(nodes[j]);
        } else {
            children[static_cast<std::size_t>(sk.joints[j].parent)].push_back(nodes[j]);
        }
    }
    auto* meshNode = new aiNode(c.name.empty() ? "body" : c.name + "_body");
    meshNode->mNumMeshes = 1;
    meshNode->mMeshes = new unsigned int[1]{0};
    rootChildren.push_back(meshNode);
    scene->mRootNode = new aiNode("scene_root");
    const auto attach = [](aiNode* parent, const std::vector<aiNode*>& kids) {
        parent->mNumChildren = static_cast<unsigned int>(kids.size());
        parent->mChildren = newArray<aiNode*>(kids.size());
        for (std::size_t i = 0; i < kids.size(); ++i) {
            parent->mChildren[i] = kids[i];
            kids[i]->mParent = parent;
        }
    };
    attach(scene->mRootNode, rootChildren);
    for (std::size_t j = 0; j < sk.jointCount(); ++j) attach(nodes[j], children[j]);

    // The body mesh with one bone per joint that carries weight.
    auto* mesh = new aiMesh();
    mesh->mName = aiString("body");
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mMaterialIndex = 0;
    const std::size_t nv = body.vertexCount();
    mesh->mNumVertices = static_cast<unsigned int>(nv);
    mesh->mVertices = new aiVector3D[nv];
    mesh->mNormals = new aiVector3D[nv];
    for (std::size_t v = 0; v < nv; ++v) {
        mesh->mVertices[v] = toAi(body.bindPositions[v]);
        mesh->mNormals[v] = toAi(body.bindNormals[v]);
    }
    mesh->mNumFaces = static_cast<unsigned int>(body.triangles.size());
    mesh->mFaces = newArray<aiFace>(body.triangles.size());
    for (std::size_t t = 0; t < body.triangles.size(); ++t) {
        mesh->mFaces[t].mNumIndices = 3;
        mesh->mFaces[t].mIndices = new unsigned int[3]{body.triangles[t][0], body.triangles[t][1], body.triangles[t][2]};
    }
    std::vector<std::vector<aiVertexWeight>> weights(sk.jointCount());
    for (std::size_t v = 0; v < nv; ++v) {
        for (int k = 0; k < kMaxInfluences; ++k) {
            const double w = body.jointWeights[v][static_cast<std::size_t>(k)];
            if (w > 0.0) {
                weights[body.jointIndices[v][static_cast<std::size_t>(k)]].push_back(
                    aiVertexWeight(static_cast<unsigned int>(v), static_cast<ai_real>(w)));
            }
        }
    }
    std::vector<aiBone*> bones;
    for (std::size_t j = 0; j < sk.jointCount(); ++j) {
        if (weights[j].empty()) continue;
        auto* bone = new aiBone();
        bone->mName = aiString(sk.joints[j].name);
        bone->mOffsetMatrix = toAi(body.inverseBindMatrices[j]);
        bone->mNumWeights = static_cast<unsigned int>(weights[j].size());
        bone->mWeights = new aiVertexWeight[weights[j].size()];
        std::copy(weights[j].begin(), weights[j].end(), bone->mWeights);
        bones.push_back(bone);
    }
    mesh->mNumBones = static_cast<unsigned int>(bones.size());
    mesh->mBones = newArray<aiBone*>(bones.size());
    std::copy(bones.begin(), bones.end(), mesh->mBones);
    scene->mNumMeshes = 1;
    scene->mMeshes = new aiMesh*[1]{mesh};
    scene->mNumMaterials = 1;
    scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};

    scene->mNumAnimations = static_cast<unsigned int>(c.clips.size());
    scene->mAnimations = newArray<aiAnimation*>(c.clips.size());
    for (std::size_t i = 0; i < c.clips.size(); ++i) {
        const AnimationClip& clip = c.clips[i];
        auto* anim = new aiAnimation();
        anim->mName = aiString(clip.name);
        anim->mTicksPerSecond = kTicksPerSecond;
        anim->mDuration = clip.duration * kTicksPerSecond;
        anim->mNumChannels = static_cast<unsigned int>(clip.channels.size());
        anim->mChannels = newArray<aiNodeAnim*>(clip.channels.size());
        for (std::size_t ci = 0; ci < clip.channels.size(); ++ci) {
            anim->mChannels[ci] = makeChannel(clip.channels[ci], sk.joints[static_cast<std::size_t>(clip.channels[ci].joint)]);
        }
        scene->mAnimations[i] = anim;
    }
    return scene;
}

} // namespace

Status exportCharacter(const Character& character, const std::string& path) {
    const std::string ext = lowerExtension(path);
    // Only glTF: assimp 5.2.5's other writers do not round-trip a skinned, animated character
    // through its own reader (binary FBX: "FBX-Tokenize ... block offset is out of range"; ASCII
    // FBX: one key per channel, times off; Collada: "Unable to resolve library reference
    // ...-input" for every animation).
    const char* format = ext == "glb" ? "glb2" : ext == "gltf" ? "gltf2" : nullptr;
    if (!format) {
        return Status::invalidArgument(path + ": unsupported export format '." + ext + "' (use .glb or .gltf)");
    }
    Status s = character.validate();
    if (!s) return Status::invalidArgument(path + ": cannot export: " + s.message());
    for (std::size_t j = 0; j < character.skeleton.jointCount(); ++j) {
        const std::string& name = character.skeleton.joints[j].name;
        if (name.empty()) return Status::invalidArgument(path + ": cannot export: joint " + std::to_string(j) + " has no name");
        for (std::size_t i = 0; i < j; ++i) {
            if (character.skeleton.joints[i].name == name) {
                return Status::invalidArgument(path + ": cannot export: joints " + std::to_string(i) + " and " +
                                               std::to_string(j) + " share the name '" + name +
                                               "' (bones are matched by name)");
            }
        }
    }
    std::unique_ptr<aiScene> scene = buildScene(character);
    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), format, path) != aiReturn_SUCCESS) {
        return Status::invalidArgument(path + ": assimp export (" + format + ") failed: " + exporter.GetErrorString());
    }
    return Status::ok();
}

} // namespace cc
