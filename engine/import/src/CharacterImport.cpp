#include "crowdcloth/import/CharacterIO.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <sys/stat.h>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "AssimpConvert.h"
#include "ImportFormats.h"
#include "IsolatedImport.h"

namespace cc {
namespace {

using detail::lowerExtension;
using detail::toMat4;
using detail::toQuat;
using detail::toVec3;

constexpr std::size_t kMaxNodeDepth = 1024;
constexpr std::size_t kMaxMeshes = 4096;
constexpr std::size_t kMaxAnimations = 4096;
constexpr std::size_t kMaxBonesPerMesh = kMaxJoints;
constexpr std::size_t kMaxWeightsPerBone = kMaxBodyVertices * 2;
constexpr double kTicksPerSecondFallback = 25.0; // assimp's convention when a file gives 0

// An import in progress: the file name goes in front of every error.
class Reader {
public:
    Reader(std::string path, const ImportSettings& settings) : mPath(std::move(path)), mSettings(settings) {}

    /// Checks the file (exists, size, format signature): done in this process, before any parser.
    Status checkFile();
    /// Parses it with assimp and converts (in the child process when isolated).
    Result<Character> read();

private:
    Status fail(const std::string& what) const { return Status::invalidArgument(mPath + ": " + what); }
    Status collectNodes(const aiNode* node, int32_t parent, std::size_t depth);
    Status readMeshes(const aiScene& scene);
    Status readClips(const aiScene& scene);
    Status applyAxisAndUnits(const aiScene& scene);

    std::string mPath;
    ImportSettings mSettings;
    const detail::ImportFormat* mFormat = nullptr;
    double mFormatTicksPerSecond = 0.0;  // the format's key rate where assimp's is wrong
    std::string mHead;  // the file's first bytes (all of it for binary formats checked by structure)
    Character mCharacter;
    std::vector<const aiNode*> mNodes;   // per joint
    std::vector<Mat4> mRestGlobal;       // per joint, file rest pose
};

Status Reader::checkFile() {
    struct stat st {};
    if (::stat(mPath.c_str(), &st) != 0) return fail("file not found");
    if (!S_ISREG(st.st_mode)) return fail("not a regular file");
    const std::size_t size = static_cast<std::size_t>(st.st_size);
    if (size == 0) return fail("file is empty");
    if (size > mSettings.maxFileBytes) {
        return fail("file has " + std::to_string(size) + " bytes, more than the cap " + std::to_string(mSettings.maxFileBytes));
    }
    mFormat = detail::formatOf(mPath);
    if (!mFormat) {
        return fail("unsupported format '." + lowerExtension(mPath) + "' (supported: " + detail::supportedExtensions() + ")");
    }
    std::ifstream in(mPath, std::ios::binary);
    if (!in) return fail("cannot open the file for reading");
    // Binary formats checked by their structure are read whole; the rest by their first bytes.
    const std::string ext = lowerExtension(mPath);
    const bool whole = ext == "b3d" || ext == "ms3d" || ext == "md5mesh" || ext == "smd" || ext == "vta";
    mHead.assign(whole ? size : std::min<std::size_t>(size, 65536), '\0');
    in.read(mHead.data(), static_cast<std::streamsize>(mHead.size()));
    if (std::size_t(in.gcount()) != mHead.size()) return fail("cannot read the file");
    return detail::checkSignature(*mFormat, mHead, mPath, size);
}

Status Reader::collectNodes(const aiNode* node, int32_t parent, std::size_t depth) {
    if (depth > kMaxNodeDepth) return fail("node hierarchy deeper than " + std::to_string(kMaxNodeDepth));
    if (mNodes.size() >= kMaxJoints) return fail("more than " + std::to_string(kMaxJoints) + " nodes");
    Joint joint;
    joint.name = node->mName.C_Str();
    joint.parent = parent;
    const Mat4 local = toMat4(node->mTransformation);
    if (!local.allFinite()) return fail("node '" + joint.name + "' has a non-finite transform");
    aiVector3D scale, position;
    aiQuaternion rotation;
    node->mTransformation.Decompose(scale, rotation, position);
    joint.restLocal.translation = toVec3(position);
    joint.restLocal.rotation = toQuat(rotation).normalized();
    joint.restLocal.scale = toVec3(scale);
    if (!joint.restLocal.isFinite() || !(joint.restLocal.scale.minCoeff() > 0.0)) {
        return fail("node '" + joint.name + "' has a degenerate or mirrored transform (scale " +
                    std::to_string(scale.x) + ", " + std::to_string(scale.y) + ", " + std::to_string(scale.z) + ")");
    }
    const double err = (joint.restLocal.matrix() - local).cwiseAbs().maxCoeff();
    if (err > 1e-4 * std::max(1.0, local.cwiseAbs().maxCoeff())) {
        return fail("node '" + joint.name + "' has a sheared transform, which translation/rotation/scale cannot hold");
    }
    const int32_t index = static_cast<int32_t>(mNodes.size());
    mNodes.push_back(node);
    mCharacter.skeleton.joints.push_back(joint);
    mRestGlobal.push_back(parent < 0 ? joint.restLocal.matrix()
                                     : Mat4(mRestGlobal[static_cast<std::size_t>(parent)] * joint.restLocal.matrix()));
    if (node->mNumChildren > 0 && !node->mChildren) return fail("node '" + joint.name + "' has a null child list");
    for (unsigned int c = 0; c < node->mNumChildren; ++c) {
        if (!node->mChildren[c]) return fail("node '" + joint.name + "' has a null child");
        Status s = collectNodes(node->mChildren[c], index, depth + 1);
        if (!s) return s;
    }
    return Status::ok();
}

bool nearlyEqual(const Mat4& a, const Mat4& b) {
    return (a - b).cwiseAbs().maxCoeff() <= 1e-4 * std::max(1.0, std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()));
}

Status Reader::readMeshes(const aiScene& scene) {
    if (scene.mNumMeshes == 0 || !scene.mMeshes) return fail("the scene has no meshes");
    if (scene.mNumMeshes > kMaxMeshes) return fail("more than " + std::to_string(kMaxMeshes) + " meshes");
    const std::size_t jointCount = mNodes.size();
    const auto jointOf = [&](const std::string& name) { return mCharacter.skeleton.findJoint(name); };

    // The mesh instances in node order (a mesh used by several nodes is instanced each time).
    struct Instance {
        const aiMesh* mesh;
        int32_t node;
    };
    std::vector<Instance> instances;
    std::size_t totalVertices = 0, totalTriangles = 0;
    for (std::size_t j = 0; j < jointCount; ++j) {
        const aiNode* node = mNodes[j];
        if (node->mNumMeshes > 0 && !node->mMeshes) return fail("node '" + std::string(node->mName.C_Str()) + "' has a null mesh list");
        for (unsigned int k = 0; k < node->mNumMeshes; ++k) {
            const unsigned int mi = node->mMeshes[k];
            if (mi >= scene.mNumMeshes || !scene.mMeshes[mi]) return fail("node references missing mesh " + std::to_string(mi));
            const aiMesh* mesh = scene.mMeshes[mi];
            if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue; // points and lines are no body
            totalVertices += mesh->mNumVertices;
            totalTriangles += mesh->mNumFaces;
            if (totalVertices > kMaxBodyVertices || totalTriangles > kMaxBodyTriangles) {
                return fail("more than " + std::to_string(kMaxBodyVertices) + " vertices or " +
                            std::to_string(kMaxBodyTriangles) + " triangles");
            }
            instances.push_back({mesh, static_cast<int32_t>(j)});
        }
    }
    if (instances.empty()) return fail("the scene has no triangle mesh");

    // Pass 1: inverse bind matrices. A mesh whose bones satisfy restGlobal(bone) * offset(bone) =
    // M for one M (bind pose = rest pose) is rebased into model space: vertices M v, inverse bind
    // inv(restGlobal). Otherwise the file's offsets are kept and the vertices stay in mesh space.
    std::vector<Mat4> inverseBind(jointCount, Mat4::Zero());
    std::vector<char> hasInverseBind(jointCount, 0);
    std::vector<Mat4> meshToBind(instances.size(), Mat4::Identity());
    std::vector<char> skinned(instances.size(), 0);
    const auto setInverseBind = [&](std::size_t j, const Mat4& m, const std::string& meshName) -> Status {
        if (hasInverseBind[j] && !nearlyEqual(inverseBind[j], m)) {
            return fail("mesh '" + meshName + "': bone '" + mCharacter.skeleton.joints[j].name +
                        "' has a different bind matrix than in an earlier mesh (unsupported)");
        }
        inverseBind[j] = m;
        hasInverseBind[j] = 1;
        return Status::ok();
    };
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const aiMesh* mesh = instances[i].mesh;
        const std::string meshName = mesh->mName.C_Str();
        if (mesh->mNumBones == 0) continue;
        if (mesh->mNumBones > kMaxBonesPerMesh || !mesh->mBones) return fail("mesh '" + meshName + "': bad bone count");
        skinned[i] = 1;
        bool consistent = true;
        Mat4 common = Mat4::Identity();
        for (unsigned int b = 0; b < mesh->mNumBones; ++b) {
            const aiBone* bone = mesh->mBones[b];
            if (!bone) return fail("mesh '" + meshName + "': null bone " + std::to_string(b));
            const int32_t j = jointOf(bone->mName.C_Str());
            if (j < 0) return fail("mesh '" + meshName + "': bone '" + bone->mName.C_Str() + "' names no node");
            Mat4 offset = toMat4(bone->mOffsetMatrix);
            if (!offset.allFinite() || !(std::abs(offset.topLeftCorner<3, 3>().determinant()) > 1e-12) ||
                (offset.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6) {
                return fail("mesh '" + meshName + "': bone '" + bone->mName.C_Str() + "' has a non-finite or singular offset matrix");
            }
            offset.row(3) << 0, 0, 0, 1;
            const Mat4 x = mRestGlobal[static_cast<std::size_t>(j)] * offset;
            if (b == 0) {
                common = x;
            } else if (!nearlyEqual(x, common)) {
                consistent = false;
            }
        }
        for (unsigned int b = 0; b < mesh->mNumBones; ++b) {
            const aiBone* bone = mesh->mBones[b];
            const auto j = static_cast<std::size_t>(jointOf(bone->mName.C_Str()));
            Mat4 offset = toMat4(bone->mOffsetMatrix);
            offset.row(3) << 0, 0, 0, 1;
            Status s = setInverseBind(j, consistent ? affineInverse(mRestGlobal[j]) : offset, meshName);
            if (!s) return s;
        }
        if (consistent) meshToBind[i] = common;
    }
    for (std::size_t j = 0; j < jointCount; ++j) {
        if (!hasInverseBind[j]) inverseBind[j] = affineInverse(mRestGlobal[j]);
    }

    // Pass 2: vertices, triangles and weights.
    SkinnedMesh& body = mCharacter.body;
    body.bindPositions.reserve(totalVertices);
    body.bindNormals.reserve(totalVertices);
    body.jointIndices.reserve(totalVertices);
    body.jointWeights.reserve(totalVertices);
    body.triangles.reserve(totalTriangles);
    std::vector<std::vector<std::pair<int32_t, double>>> influences;
    bool anyMissingNormals = false;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const aiMesh* mesh = instances[i].mesh;
        const std::string meshName = "mesh '" + std::string(mesh->mName.C_Str()) + "'";
        const std::size_t nv = mesh->mNumVertices;
        if (nv == 0 || !mesh->mVertices) return fail(meshName + " has no vertices");
        if (mesh->mNumFaces > 0 && !mesh->mFaces) return fail(meshName + " has a null face list");
        const auto base = static_cast<uint32_t>(body.bindPositions.size());

        influences.assign(nv, {});
        if (skinned[i]) {
            for (unsigned int b = 0; b < mesh->mNumBones; ++b) {
                const aiBone* bone = mesh->mBones[b];
                if (bone->mNumWeights > kMaxWeightsPerBone || (bone->mNumWeights > 0 && !bone->mWeights)) {
                    return fail(meshName + ": bone '" + bone->mName.C_Str() + "' has a bad weight list");
                }
                const int32_t j = jointOf(bone->mName.C_Str());
                for (unsigned int w = 0; w < bone->mNumWeights; ++w) {
                    const aiVertexWeight& vw = bone->mWeights[w];
                    if (vw.mVertexId >= nv) {
                        return fail(meshName + ": bone '" + bone->mName.C_Str() + "' weights vertex " +
                                    std::to_string(vw.mVertexId) + ", the mesh has " + std::to_string(nv));
                    }
                    if (!std::isfinite(vw.mWeight) || vw.mWeight < 0.0f) {
                        return fail(meshName + ": vertex " + std::to_string(vw.mVertexId) + " has a negative or non-finite weight");
                    }
                    if (vw.mWeight > 0.0f) influences[vw.mVertexId].push_back({j, vw.mWeight});
                }
            }
        }
        const Mat4& toBind = meshToBind[i];
        const Mat3 normalMap = toBind.topLeftCorner<3, 3>().inverse().transpose();
        const auto node = static_cast<std::size_t>(instances[i].node);
        // Vertices without weights follow their mesh node: skinned = global(node) * v.
        const Mat4 unweightedToBind = affineInverse(inverseBind[node]);
        const Mat3 unweightedNormalMap = unweightedToBind.topLeftCorner<3, 3>().inverse().transpose();
        for (std::size_t v = 0; v < nv; ++v) {
            const Vec3 p = toVec3(mesh->mVertices[v]);
            if (!isFinite(p)) return fail(meshName + ": vertex " + std::to_string(v) + " has a non-finite position");
            Vec3 n = mesh->mNormals ? toVec3(mesh->mNormals[v]) : Vec3::Zero();
            if (!isFinite(n) || n.norm() < 1e-12) {
                anyMissingNormals = true;
                n = Vec3::UnitY();
            }
            auto& inf = influences[v];
            double sum = 0.0;
            for (const auto& jw : inf) sum += jw.second;
            std::array<uint16_t, kMaxInfluences> joints{};
            std::array<double, kMaxInfluences> weights{};
            Vec3 bindP, bindN;
            if (inf.empty()) {
                joints[0] = static_cast<uint16_t>(node);
                weights[0] = 1.0;
                bindP = unweightedToBind.topLeftCorner<3, 3>() * p + unweightedToBind.topRightCorner<3, 1>();
                bindN = unweightedNormalMap * n;
            } else {
                if (std::abs(sum - 1.0) > mSettings.weightSumTolerance) {
                    return fail(meshName + ": vertex " + std::to_string(v) + ": skin weights sum to " +
                                std::to_string(sum) + ", not 1 (tolerance " + std::to_string(mSettings.weightSumTolerance) + ")");
                }
                // Keep the four largest (ties by joint index: deterministic) and renormalise.
                std::sort(inf.begin(), inf.end(), [](const auto& a, const auto& b) {
                    return a.second != b.second ? a.second > b.second : a.first < b.first;
                });
                const std::size_t kept = std::min<std::size_t>(inf.size(), kMaxInfluences);
                double keptSum = 0.0;
                for (std::size_t k = 0; k < kept; ++k) keptSum += inf[k].second;
                for (std::size_t k = 0; k < kept; ++k) {
                    joints[k] = static_cast<uint16_t>(inf[k].first);
                    weights[k] = inf[k].second / keptSum;
                }
                bindP = toBind.topLeftCorner<3, 3>() * p + toBind.topRightCorner<3, 1>();
                bindN = normalMap * n;
            }
            body.bindPositions.push_back(bindP);
            body.bindNormals.push_back(bindN.normalized());
            body.jointIndices.push_back(joints);
            body.jointWeights.push_back(weights);
        }
        for (unsigned int f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue; // points/lines sorted into the same mesh
            if (!face.mIndices) return fail(meshName + ": face " + std::to_string(f) + " has no indices");
            std::array<uint32_t, 3> tri{};
            for (int k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= nv) {
                    return fail(meshName + ": face " + std::to_string(f) + " uses vertex " + std::to_string(face.mIndices[k]) +
                                ", the mesh has " + std::to_string(nv));
                }
                tri[static_cast<std::size_t>(k)] = base + face.mIndices[k];
            }
            if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue; // degenerate: no surface
            body.triangles.push_back(tri);
        }
    }
    if (body.triangles.empty()) return fail("the meshes have no triangles");
    body.inverseBindMatrices = std::move(inverseBind);
    if (anyMissingNormals) body.computeBindNormals();
    return Status::ok();
}

Status Reader::readClips(const aiScene& scene) {
    if (scene.mNumAnimations > kMaxAnimations) return fail("more than " + std::to_string(kMaxAnimations) + " animations");
    if (scene.mNumAnimations > 0 && !scene.mAnimations) return fail("null animation list");
    for (unsigned int a = 0; a < scene.mNumAnimations; ++a) {
        const aiAnimation* anim = scene.mAnimations[a];
        if (!anim) return fail("null animation " + std::to_string(a));
        AnimationClip clip;
        clip.name = anim->mName.length > 0 ? anim->mName.C_Str() : "clip" + std::to_string(a);
        const std::string where = "animation '" + clip.name + "'";
        double tps = anim->mTicksPerSecond != 0.0 ? anim->mTicksPerSecond : kTicksPerSecondFallback;
        if (mFormatTicksPerSecond > 0.0) tps = mFormatTicksPerSecond;
        if (mSettings.ticksPerSecond > 0.0) tps = mSettings.ticksPerSecond;
        if (!std::isfinite(tps) || tps < 0.0 || !std::isfinite(anim->mDuration)) return fail(where + ": bad ticks per second or duration");
        if (anim->mNumChannels > kMaxJoints || (anim->mNumChannels > 0 && !anim->mChannels)) return fail(where + ": bad channel list");
        double first = std::numeric_limits<double>::infinity(), last = 0.0;
        for (unsigned int c = 0; c < anim->mNumChannels; ++c) {
            const aiNodeAnim* na = anim->mChannels[c];
            if (!na) return fail(where + ": null channel " + std::to_string(c));
            const int32_t j = mCharacter.skeleton.findJoint(na->mNodeName.C_Str());
            if (j < 0) continue; // a channel for a node outside the hierarchy moves nothing
            JointChannel ch;
            ch.joint = j;
            const std::string cw = where + " channel '" + std::string(na->mNodeName.C_Str()) + "'";
            if (na->mNumPositionKeys > kMaxKeysPerCurve || na->mNumRotationKeys > kMaxKeysPerCurve ||
                na->mNumScalingKeys > kMaxKeysPerCurve) {
                return fail(cw + ": more than " + std::to_string(kMaxKeysPerCurve) + " keys");
            }
            if ((na->mNumPositionKeys && !na->mPositionKeys) || (na->mNumRotationKeys && !na->mRotationKeys) ||
                (na->mNumScalingKeys && !na->mScalingKeys)) {
                return fail(cw + ": null key list");
            }
            // Keys in seconds; a key at the same time as the previous one replaces it.
            const auto push = [&](std::vector<double>& times, auto& values, double t, const auto& value,
                                  const char* what, unsigned int k) -> Status {
                t /= tps;
                if (!std::isfinite(t)) return fail(cw + ": " + what + " key " + std::to_string(k) + " has a non-finite time");
                if (!times.empty() && t < times.back()) {
                    return fail(cw + ": " + what + " key " + std::to_string(k) + " goes back in time");
                }
                if (!times.empty() && t == times.back()) {
                    values.back() = value;
                } else {
                    times.push_back(t);
                    values.push_back(value);
                }
                first = std::min(first, t);
                last = std::max(last, t);
                return Status::ok();
            };
            for (unsigned int k = 0; k < na->mNumPositionKeys; ++k) {
                const Vec3 v = toVec3(na->mPositionKeys[k].mValue);
                if (!isFinite(v)) return fail(cw + ": translation key " + std::to_string(k) + " is not finite");
                Status s = push(ch.translationTimes, ch.translations, na->mPositionKeys[k].mTime, v, "translation", k);
                if (!s) return s;
            }
            for (unsigned int k = 0; k < na->mNumRotationKeys; ++k) {
                Quat q = toQuat(na->mRotationKeys[k].mValue);
                const double norm = q.norm();
                if (!std::isfinite(norm) || norm < 1e-6) return fail(cw + ": rotation key " + std::to_string(k) + " is not a rotation");
                q.coeffs() /= norm;
                Status s = push(ch.rotationTimes, ch.rotations, na->mRotationKeys[k].mTime, q, "rotation", k);
                if (!s) return s;
            }
            for (unsigned int k = 0; k < na->mNumScalingKeys; ++k) {
                const Vec3 v = toVec3(na->mScalingKeys[k].mValue);
                if (!isFinite(v) || !(v.minCoeff() > 0.0)) {
                    return fail(cw + ": scale key " + std::to_string(k) + " is not finite and positive");
                }
                Status s = push(ch.scaleTimes, ch.scales, na->mScalingKeys[k].mTime, v, "scale", k);
                if (!s) return s;
            }
            clip.channels.push_back(std::move(ch));
        }
        if (clip.channels.empty()) continue; // e.g. morph-target-only animations
        if (!std::isfinite(first)) first = 0.0; // channels without keys
        // Clips may be ranges of one timeline (ECOSYSTEM pitfall 17): times count from the first key.
        for (JointChannel& ch : clip.channels) {
            for (double& t : ch.translationTimes) t -= first;
            for (double& t : ch.rotationTimes) t -= first;
            for (double& t : ch.scaleTimes) t -= first;
        }
        clip.duration = std::max(last - first, anim->mDuration / tps - first);
        if (!std::isfinite(clip.duration) || clip.duration < 0.0) clip.duration = last - first;
        mCharacter.clips.push_back(std::move(clip));
    }
    return Status::ok();
}

// Units and axes: the file's own metadata (FBX, OpenGEX) where it has some, else the format's
// convention, unless the settings force them. glTF and Collada arrive in metres, Y up (assimp
// applies Collada's <unit> and <up_axis>).
Status Reader::applyAxisAndUnits(const aiScene& scene) {
    double scale = mSettings.unitScale;
    Mat3 axes = Mat3::Identity();
    bool zUp = mFormat->zUp;
    const std::string ext = lowerExtension(mPath);
    if (ext == "fbx" && scene.mMetaData) {
        const aiMetadata& md = *scene.mMetaData;
        if (scale == 0.0) {
            double unit = 0.0;
            float unitF = 0.0f;
            if (md.Get("UnitScaleFactor", unit) || (md.Get("UnitScaleFactor", unitF) && (unit = unitF, true))) {
                if (!std::isfinite(unit) || !(unit > 0.0)) return fail("FBX UnitScaleFactor is not a positive number");
                scale = unit * 0.01; // centimetres per file unit -> metres
            }
        }
        int32_t up = 1, upSign = 1, front = 2, frontSign = 1, coord = 0, coordSign = 1;
        md.Get("UpAxis", up);
        md.Get("UpAxisSign", upSign);
        md.Get("FrontAxis", front);
        md.Get("FrontAxisSign", frontSign);
        md.Get("CoordAxis", coord);
        md.Get("CoordAxisSign", coordSign);
        const auto ok = [](int32_t a) { return a >= 0 && a <= 2; };
        if (!ok(up) || !ok(front) || !ok(coord) || up == front || up == coord || front == coord) {
            return fail("FBX axis metadata is inconsistent (UpAxis " + std::to_string(up) + ", FrontAxis " +
                        std::to_string(front) + ", CoordAxis " + std::to_string(coord) + ")");
        }
        // Rows: where the file's coord/up/front axes go (+X, +Y, +Z).
        Mat3 fileAxes = Mat3::Zero(); // columns: file's coord, up, front directions
        fileAxes(coord, 0) = coordSign < 0 ? -1.0 : 1.0;
        fileAxes(up, 1) = upSign < 0 ? -1.0 : 1.0;
        fileAxes(front, 2) = frontSign < 0 ? -1.0 : 1.0;
        axes = fileAxes.transpose();
        if (axes.determinant() < 0.0) axes.row(0) *= -1.0; // keep a rotation: flip the side axis
    } else if (ext == "ogex") {
        std::ifstream in(mPath, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        double metres = 0.0;
        bool metricZUp = false;
        if (detail::openGexMetrics(text, metres, metricZUp)) {
            if (scale == 0.0 && metres > 0.0) scale = metres;
            zUp = metricZUp;
        }
    }
    if (scale == 0.0) scale = mFormat->unitFromFile ? 1.0 : mFormat->unitScale;
    if (mSettings.upAxis != ImportUpAxis::FromFile) zUp = mSettings.upAxis == ImportUpAxis::Z;
    if (zUp) {
        // File +Z up, +Y forward... turned so that file +Z is +Y and file +Y is -Z.
        Mat3 turn;
        turn << 1, 0, 0, 0, 0, 1, 0, -1, 0;
        axes = turn * axes;
    }
    if (!std::isfinite(scale) || !(scale > 0.0)) return fail("unit scale must be positive");
    if (scale == 1.0 && axes == Mat3::Identity()) return Status::ok();

    Status s = changeBasis(mCharacter, scale, axes);
    return s ? s : fail(s.message());
}

Result<Character> Reader::read() {
    Assimp::Importer importer;
    // Points and lines are dropped; bone weights are limited here, not by assimp (which would
    // renormalise before the sum check).
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    unsigned int flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    if (mSettings.joinIdenticalVertices) flags |= aiProcess_JoinIdenticalVertices;
    const aiScene* scene = importer.ReadFile(mPath, flags);
    if (!scene) return fail(std::string("assimp could not read it: ") + importer.GetErrorString());
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) return fail("the scene is incomplete (assimp flagged it)");
    if (!scene->mRootNode) return fail("the scene has no root node");
    if (mFormat->content == detail::FormatContent::Animation || scene->mNumMeshes == 0)
        return fail(std::string(mFormat->name) + " file without a mesh: it holds " +
                    (scene->mNumAnimations > 0 ? "animation only" : "nothing") + ", not a body");

    mFormatTicksPerSecond = mFormat->ticksPerSecond;
    if (lowerExtension(mPath) == "md5mesh") {
        // The clips come from the .md5anim beside the mesh; its frame rate is what the keys count.
        std::ifstream anim(mPath.substr(0, mPath.size() - 4) + "anim", std::ios::binary);
        std::string text(std::min<std::size_t>(mSettings.maxFileBytes, 65536), '\0');
        anim.read(text.data(), std::streamsize(text.size()));
        text.resize(std::size_t(std::max<std::streamsize>(anim.gcount(), 0)));
        mFormatTicksPerSecond = detail::md5FrameRate(text);
    }
    Status s = collectNodes(scene->mRootNode, -1, 0);
    if (s) s = readMeshes(*scene);
    if (s) s = readClips(*scene);
    if (s) s = applyAxisAndUnits(*scene);
    if (!s) return s;
    const auto slash = mPath.find_last_of("/\\");
    mCharacter.name = mPath.substr(slash == std::string::npos ? 0 : slash + 1);
    s = mCharacter.validate();
    if (!s) return fail(s.message());
    return std::move(mCharacter);
}

} // namespace

Status ImportSettings::validate() const {
    if (!std::isfinite(weightSumTolerance) || !(weightSumTolerance > 0.0) || weightSumTolerance > 0.5) {
        return Status::invalidArgument("ImportSettings.weightSumTolerance must be in (0, 0.5]");
    }
    if (!std::isfinite(unitScale) || unitScale < 0.0) {
        return Status::invalidArgument("ImportSettings.unitScale must be finite and >= 0");
    }
    if (uint32_t(upAxis) > uint32_t(ImportUpAxis::Z)) return Status::invalidArgument("ImportSettings.upAxis is unknown");
    if (maxFileBytes == 0) return Status::invalidArgument("ImportSettings.maxFileBytes must be > 0");
    if (!(std::isfinite(ticksPerSecond) && ticksPerSecond >= 0.0 && ticksPerSecond <= 1e6))
        return Status::invalidArgument("ImportSettings.ticksPerSecond must be in [0, 1e6]");
    if (!(std::isfinite(timeoutSeconds) && timeoutSeconds > 0.0 && timeoutSeconds <= 3600.0))
        return Status::invalidArgument("ImportSettings.timeoutSeconds must be in (0, 3600]");
    return Status::ok();
}

Result<Character> importCharacter(const std::string& path, const ImportSettings& settings) {
    if (Status s = settings.validate(); !s) return Status::invalidArgument(path + ": " + s.message());
    Reader reader(path, settings);
    if (Status s = reader.checkFile(); !s) return s;
    if (!settings.isolate) return reader.read();
    return detail::readIsolated([&] { return reader.read(); }, path, settings.timeoutSeconds, settings.maxMemoryBytes);
}

} // namespace cc
