#pragma once

// A small skinned, animated rig and writers for the formats assimp 5.2.5 reads but cannot write,
// each in its format's own conventions (units, up axis, handedness, rotation encoding, key
// times), so the import tests read files they made themselves (never downloaded).

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "crowdcloth/character/Character.h"

namespace cc::test {

/// A three-joint column (root, mid, tip along +Y, 1.25 m tall) with a square tube of skin blended
/// between the joints, and one clip "bend" (1 s): the root slides forward, the mid joint bends
/// about Z, the tip about X, all back to rest at the end. Metres, Y up.
inline Character formatRig() {
    Character c;
    c.name = "rig";
    const char* names[3] = {"root", "mid", "tip"};
    for (int j = 0; j < 3; ++j) {
        Joint joint;
        joint.name = names[j];
        joint.parent = j - 1;
        joint.restLocal.translation = Vec3(0.0, j == 0 ? 0.0 : 0.5, 0.0);
        c.skeleton.joints.push_back(joint);
    }
    SkinnedMesh& b = c.body;
    const int rings = 6;
    const double half = 0.05;
    const double corners[4][2] = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
    for (int r = 0; r < rings; ++r) {
        const double y = 0.25 * r;
        for (const auto& xz : corners) {
            b.bindPositions.push_back(Vec3(xz[0], y, xz[1]));
            b.bindNormals.push_back(Vec3(xz[0], 0.0, xz[1]).normalized());
            // Weights blend across the joints at 0.5 m and 1.0 m.
            std::array<uint16_t, 4> joints{0, 0, 0, 0};
            std::array<double, 4> weights{1.0, 0.0, 0.0, 0.0};
            if (r == 2) joints = {0, 1, 0, 0}, weights = {0.5, 0.5, 0, 0};
            if (r == 3) joints = {1, 0, 0, 0};
            if (r == 4) joints = {1, 2, 0, 0}, weights = {0.5, 0.5, 0, 0};
            if (r == 5) joints = {2, 0, 0, 0};
            b.jointIndices.push_back(joints);
            b.jointWeights.push_back(weights);
        }
    }
    for (int r = 0; r + 1 < rings; ++r) {
        for (int k = 0; k < 4; ++k) {
            const uint32_t a = uint32_t(4 * r + k), bb = uint32_t(4 * r + (k + 1) % 4), cc = a + 4, d = bb + 4;
            b.triangles.push_back({a, bb, d});
            b.triangles.push_back({a, d, cc});
        }
    }
    for (int j = 0; j < 3; ++j) {
        Mat4 inverse = Mat4::Identity();
        inverse(1, 3) = -0.5 * j;
        b.inverseBindMatrices.push_back(inverse);
    }
    AnimationClip clip;
    clip.name = "bend";
    clip.duration = 1.0;
    const double times[3] = {0.0, 0.5, 1.0};
    for (int j = 0; j < 3; ++j) {
        JointChannel ch;
        ch.joint = j;
        for (int k = 0; k < 3; ++k) {
            const double peak = k == 1 ? 1.0 : 0.0;
            ch.rotationTimes.push_back(times[k]);
            ch.translationTimes.push_back(times[k]);
            ch.translations.push_back(c.skeleton.joints[std::size_t(j)].restLocal.translation + Vec3(0, 0, j == 0 ? 0.1 * peak : 0.0));
            const Quat q = j == 1 ? Quat(Eigen::AngleAxisd(0.6 * peak, Vec3(0.3, 0.2, 1.0).normalized()))
                                  : j == 2 ? Quat(Eigen::AngleAxisd(-0.4 * peak, Vec3(1.0, 0.4, 0.0).normalized())) : Quat::Identity();
            ch.rotations.push_back(q);
        }
        clip.channels.push_back(ch);
    }
    c.clips.push_back(clip);
    return c;
}

/// Local (parent-relative) transforms of every joint at clip time t, as matrices.
inline std::vector<Mat4> localsAt(const Character& c, double t) {
    std::vector<Transform> local(c.skeleton.jointCount());
    c.clips[0].evaluate(c.skeleton, t, ClipWrap::Clamp, local);
    std::vector<Mat4> out;
    out.reserve(local.size());
    for (const Transform& l : local) out.push_back(l.matrix());
    return out;
}

inline std::vector<Mat4> globalsAt(const Character& c, double t) {
    std::vector<Transform> local(c.skeleton.jointCount());
    if (t < 0.0) c.skeleton.restPose(local);
    else c.clips[0].evaluate(c.skeleton, t, ClipWrap::Clamp, local);
    std::vector<Mat4> global(c.skeleton.jointCount());
    c.skeleton.computeGlobalTransforms(local, global);
    return global;
}

/// A file's conventions as a map from crowdcloth's space (metres, Y up, right-handed) into the
/// file's: p_file = linear * p. Rotations map by conjugation with the rotation part.
struct FileSpace {
    double metresPerUnit = 1.0;
    Mat3 axes = Mat3::Identity();  ///< orthonormal; determinant -1 for a left-handed format
    Vec3 point(const Vec3& p) const { return axes * p / metresPerUnit; }
    Mat3 rotation(const Mat3& r) const { return axes * r * axes.transpose(); }
};

/// Z up, Y forward... the Doom 3 / Source convention: file (x, y, z) = (x, -z, y).
inline Mat3 zUpAxes() {
    Mat3 m;
    m << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    return m;
}

inline std::string num(double v) {
    char text[64];
    std::snprintf(text, sizeof(text), "%.9g", v);
    return text;
}

/// Doom 3 .md5mesh and .md5anim (30 frames per second), Z up, inches. Orientations are stored as
/// x, y, z of a unit quaternion with w <= 0 (the reader rebuilds w as -sqrt(1 - x^2 - y^2 - z^2)).
inline void writeMd5(const Character& c, const std::string& stem, const FileSpace& space) {
    const auto quatText = [](const Mat3& r) {
        Quat q(r);
        q.normalize();
        if (q.w() > 0.0) q.coeffs() *= -1.0;
        return "( " + num(q.x()) + " " + num(q.y()) + " " + num(q.z()) + " )";
    };
    const auto vecText = [](const Vec3& v) { return "( " + num(v.x()) + " " + num(v.y()) + " " + num(v.z()) + " )"; };
    const std::size_t nj = c.skeleton.jointCount();
    const std::vector<Mat4> bind = globalsAt(c, -1.0);
    std::ostringstream m;
    m << "MD5Version 10\ncommandline \"\"\n\nnumJoints " << nj << "\nnumMeshes 1\n\njoints {\n";
    for (std::size_t j = 0; j < nj; ++j) {
        m << "\t\"" << c.skeleton.joints[j].name << "\"\t" << c.skeleton.joints[j].parent << " "
          << vecText(space.point(bind[j].topRightCorner<3, 1>())) << " " << quatText(space.rotation(bind[j].topLeftCorner<3, 3>()))
          << "\n";
    }
    m << "}\n\nmesh {\n\tshader \"skin\"\n\n\tnumverts " << c.body.vertexCount() << "\n";
    std::vector<std::string> weights;
    for (std::size_t v = 0; v < c.body.vertexCount(); ++v) {
        int count = 0;
        const std::size_t first = weights.size();
        for (int k = 0; k < 4; ++k) {
            const double w = c.body.jointWeights[v][std::size_t(k)];
            if (w <= 0.0) continue;
            const std::size_t j = c.body.jointIndices[v][std::size_t(k)];
            const Vec3 p = space.point(c.body.bindPositions[v]);
            const Mat3 r = space.rotation(bind[j].topLeftCorner<3, 3>());
            const Vec3 local = r.transpose() * (p - space.point(bind[j].topRightCorner<3, 1>()));
            weights.push_back("\tweight " + std::to_string(weights.size()) + " " + std::to_string(j) + " " + num(w) + " " + vecText(local));
            ++count;
        }
        m << "\tvert " << v << " ( 0 0 ) " << first << " " << count << "\n";
    }
    m << "\n\tnumtris " << c.body.triangles.size() << "\n";
    for (std::size_t t = 0; t < c.body.triangles.size(); ++t) {
        const auto& tri = c.body.triangles[t];
        m << "\ttri " << t << " " << tri[0] << " " << tri[2] << " " << tri[1] << "\n";
    }
    m << "\n\tnumweights " << weights.size() << "\n";
    for (const std::string& w : weights) m << w << "\n";
    m << "}\n";
    std::ofstream(stem + ".md5mesh") << m.str();

    const int fps = 30, frames = int(std::lround(c.clips[0].duration * fps)) + 1;
    std::ostringstream a;
    a << "MD5Version 10\ncommandline \"\"\n\nnumFrames " << frames << "\nnumJoints " << nj << "\nframeRate " << fps
      << "\nnumAnimatedComponents " << 6 * nj << "\n\nhierarchy {\n";
    for (std::size_t j = 0; j < nj; ++j)
        a << "\t\"" << c.skeleton.joints[j].name << "\"\t" << c.skeleton.joints[j].parent << " 63 " << 6 * j << "\n";
    a << "}\n\nbounds {\n";
    for (int f = 0; f < frames; ++f) a << "\t( -100 -100 -100 ) ( 100 100 100 )\n";
    a << "}\n\nbaseframe {\n";
    const std::vector<Mat4> rest = localsAt(c, 0.0);
    for (std::size_t j = 0; j < nj; ++j)
        a << "\t" << vecText(space.point(rest[j].topRightCorner<3, 1>())) << " " << quatText(space.rotation(rest[j].topLeftCorner<3, 3>())) << "\n";
    a << "}\n";
    for (int f = 0; f < frames; ++f) {
        const std::vector<Mat4> local = localsAt(c, double(f) / fps);
        a << "\nframe " << f << " {\n";
        for (std::size_t j = 0; j < nj; ++j) {
            const Vec3 p = space.point(local[j].topRightCorner<3, 1>());
            Quat q(space.rotation(local[j].topLeftCorner<3, 3>()));
            q.normalize();
            if (q.w() > 0.0) q.coeffs() *= -1.0;
            a << "\t" << num(p.x()) << " " << num(p.y()) << " " << num(p.z()) << " " << num(q.x()) << " " << num(q.y()) << " "
              << num(q.z()) << "\n";
        }
        a << "}\n";
    }
    std::ofstream(stem + ".md5anim") << a.str();
}

/// Valve .smd: a node list, one skeleton frame per time (30 per second, the first the bind pose),
/// triangles in model space with their bone links. Euler angles in radians.
inline void writeSmd(const Character& c, const std::string& path, const FileSpace& space, bool zyxEuler) {
    const auto euler = [&](const Mat3& r) {
        // Angles (x, y, z) with r = Rz(z) Ry(y) Rx(x) (zyxEuler) or Rx(x) Ry(y) Rz(z).
        const Vec3 e = zyxEuler ? r.eulerAngles(2, 1, 0) : r.eulerAngles(0, 1, 2);
        return zyxEuler ? Vec3(e[2], e[1], e[0]) : e;
    };
    std::ostringstream s;
    s << "version 1\nnodes\n";
    for (std::size_t j = 0; j < c.skeleton.jointCount(); ++j)
        s << j << " \"" << c.skeleton.joints[j].name << "\" " << c.skeleton.joints[j].parent << "\n";
    s << "end\nskeleton\n";
    const int fps = 30, frames = int(std::lround(c.clips[0].duration * fps)) + 1;
    for (int f = 0; f < frames; ++f) {
        s << "time " << f << "\n";
        const std::vector<Mat4> local = localsAt(c, double(f) / fps);
        for (std::size_t j = 0; j < c.skeleton.jointCount(); ++j) {
            const Vec3 p = space.point(local[j].topRightCorner<3, 1>());
            const Vec3 e = euler(space.rotation(local[j].topLeftCorner<3, 3>()));
            s << j << " " << num(p.x()) << " " << num(p.y()) << " " << num(p.z()) << " " << num(e.x()) << " " << num(e.y()) << " "
              << num(e.z()) << "\n";
        }
    }
    s << "end\ntriangles\n";
    for (const auto& tri : c.body.triangles) {
        s << "skin\n";
        for (uint32_t v : tri) {
            const Vec3 p = space.point(c.body.bindPositions[v]);
            const Vec3 n = space.axes * c.body.bindNormals[v];
            int links = 0;
            std::string linkText;
            for (int k = 0; k < 4; ++k) {
                if (c.body.jointWeights[v][std::size_t(k)] <= 0.0) continue;
                ++links;
                linkText += " " + std::to_string(c.body.jointIndices[v][std::size_t(k)]) + " " + num(c.body.jointWeights[v][std::size_t(k)]);
            }
            s << c.body.jointIndices[v][0] << " " << num(p.x()) << " " << num(p.y()) << " " << num(p.z()) << " " << num(n.x()) << " "
              << num(n.y()) << " " << num(n.z()) << " 0 0 " << links << linkText << "\n";
        }
    }
    s << "end\n";
    std::ofstream(path) << s.str();
}

/// Little-endian binary chunks, as Blitz3D writes them.
class ChunkWriter {
public:
    void begin(const char* tag) {
        mOut.append(tag, 4);
        mOpen.push_back(mOut.size());
        u32(0);
    }
    void end() {
        const std::size_t at = mOpen.back();
        mOpen.pop_back();
        const uint32_t length = uint32_t(mOut.size() - at - 4);
        std::memcpy(&mOut[at], &length, 4);
    }
    void u32(uint32_t v) { mOut.append(reinterpret_cast<const char*>(&v), 4); }
    void i32(int32_t v) { mOut.append(reinterpret_cast<const char*>(&v), 4); }
    void f32(double v) {
        const float f = float(v);
        mOut.append(reinterpret_cast<const char*>(&f), 4);
    }
    void text(const std::string& s) { mOut.append(s.c_str(), s.size() + 1); }
    const std::string& bytes() const { return mOut; }

private:
    std::string mOut;
    std::vector<std::size_t> mOpen;
};

/// Blitz3D .b3d: a node tree (each joint a NODE with its BONE weights and KEYS), the mesh in the
/// root node, one ANIM at 30 frames per second. Left-handed (Z mirrored); rotations stored
/// (w, x, y, z) with w negated, as Blitz3D's tools write them.
inline void writeB3d(const Character& c, const std::string& path, const FileSpace& space) {
    ChunkWriter w;
    const auto quat = [&](const Mat3& r) {
        Quat q(space.rotation(r));
        q.normalize();
        w.f32(-q.w()), w.f32(q.x()), w.f32(q.y()), w.f32(q.z());
    };
    const auto vec = [&](const Vec3& v) {
        const Vec3 p = space.point(v);
        w.f32(p.x()), w.f32(p.y()), w.f32(p.z());
    };
    const int fps = 30, frames = int(std::lround(c.clips[0].duration * fps)) + 1;
    std::vector<std::vector<Mat4>> keys;
    keys.reserve(std::size_t(frames));
    for (int f = 0; f < frames; ++f) keys.push_back(localsAt(c, double(f) / fps));
    const std::vector<Mat4> rest = localsAt(c, 0.0);
    const std::function<void(std::size_t)> node = [&](std::size_t j) {
        w.begin("NODE");
        w.text(c.skeleton.joints[j].name);
        vec(rest[j].topRightCorner<3, 1>());
        w.f32(1.0), w.f32(1.0), w.f32(1.0);
        quat(rest[j].topLeftCorner<3, 3>());
        if (j == 0) {
            w.begin("MESH");
            w.i32(-1);
            w.begin("VRTS");
            w.i32(1), w.i32(0), w.i32(0);
            for (std::size_t v = 0; v < c.body.vertexCount(); ++v) {
                vec(c.body.bindPositions[v]);
                const Vec3 n = space.axes * c.body.bindNormals[v];
                w.f32(n.x()), w.f32(n.y()), w.f32(n.z());
            }
            w.end();
            w.begin("TRIS");
            w.i32(-1);
            for (const auto& t : c.body.triangles) w.i32(int32_t(t[0])), w.i32(int32_t(t[2])), w.i32(int32_t(t[1]));
            w.end();
            w.end();
            w.begin("ANIM");
            w.i32(0), w.i32(frames - 1), w.f32(fps);
            w.end();
        }
        w.begin("BONE");
        for (std::size_t v = 0; v < c.body.vertexCount(); ++v)
            for (int k = 0; k < 4; ++k)
                if (c.body.jointWeights[v][std::size_t(k)] > 0.0 && c.body.jointIndices[v][std::size_t(k)] == j)
                    w.i32(int32_t(v)), w.f32(c.body.jointWeights[v][std::size_t(k)]);
        w.end();
        w.begin("KEYS");
        w.i32(1 | 4);
        for (int f = 0; f < frames; ++f) {
            w.i32(f);
            vec(keys[std::size_t(f)][j].topRightCorner<3, 1>());
            quat(keys[std::size_t(f)][j].topLeftCorner<3, 3>());
        }
        w.end();
        for (std::size_t child = 0; child < c.skeleton.jointCount(); ++child)
            if (c.skeleton.joints[child].parent == int32_t(j)) node(child);
        w.end();
    };
    w.begin("BB3D");
    w.i32(1);
    node(0);
    w.end();
    std::ofstream(path, std::ios::binary) << w.bytes();
}

/// Ogre XML: `stem.mesh.xml` (shared geometry, bone assignments) and `stem.skeleton.xml` (bones
/// with their binding pose, keyframes relative to it: translate added, rotate applied after).
/// Keyframe times in seconds. Y up, metres.
inline void writeOgreXml(const Character& c, const std::string& stem, const std::string& linkName) {
    const auto vec = [](const char* tag, const Vec3& v) {
        return std::string("<") + tag + " x=\"" + num(v.x()) + "\" y=\"" + num(v.y()) + "\" z=\"" + num(v.z()) + "\"/>";
    };
    const auto rotation = [&](const char* tag, const Mat3& r) {
        const Eigen::AngleAxisd aa(r);
        const Vec3 axis = aa.angle() == 0.0 ? Vec3::UnitX() : Vec3(aa.axis());
        return std::string("<") + tag + " angle=\"" + num(aa.angle()) + "\">" + vec("axis", axis) + "</" + tag + ">";
    };
    std::ostringstream m;
    m << "<mesh>\n <sharedgeometry vertexcount=\"" << c.body.vertexCount() << "\">\n  <vertexbuffer positions=\"true\" normals=\"true\">\n";
    for (std::size_t v = 0; v < c.body.vertexCount(); ++v)
        m << "   <vertex>" << vec("position", c.body.bindPositions[v]) << vec("normal", c.body.bindNormals[v]) << "</vertex>\n";
    m << "  </vertexbuffer>\n </sharedgeometry>\n <submeshes>\n  <submesh material=\"skin\" usesharedvertices=\"true\" "
         "use32bitindexes=\"false\" operationtype=\"triangle_list\">\n   <faces count=\""
      << c.body.triangles.size() << "\">\n";
    for (const auto& t : c.body.triangles) m << "    <face v1=\"" << t[0] << "\" v2=\"" << t[1] << "\" v3=\"" << t[2] << "\"/>\n";
    m << "   </faces>\n  </submesh>\n </submeshes>\n <skeletonlink name=\"" << linkName << "\"/>\n <boneassignments>\n";
    for (std::size_t v = 0; v < c.body.vertexCount(); ++v)
        for (int k = 0; k < 4; ++k)
            if (c.body.jointWeights[v][std::size_t(k)] > 0.0)
                m << "  <vertexboneassignment vertexindex=\"" << v << "\" boneindex=\"" << c.body.jointIndices[v][std::size_t(k)]
                  << "\" weight=\"" << num(c.body.jointWeights[v][std::size_t(k)]) << "\"/>\n";
    m << " </boneassignments>\n</mesh>\n";
    std::ofstream(stem + ".mesh.xml") << m.str();

    const std::vector<Mat4> rest = localsAt(c, 0.0);
    std::ostringstream k;
    k << "<skeleton>\n <bones>\n";
    for (std::size_t j = 0; j < c.skeleton.jointCount(); ++j)
        k << "  <bone id=\"" << j << "\" name=\"" << c.skeleton.joints[j].name << "\">" << vec("position", rest[j].topRightCorner<3, 1>())
          << rotation("rotation", rest[j].topLeftCorner<3, 3>()) << "</bone>\n";
    k << " </bones>\n <bonehierarchy>\n";
    for (std::size_t j = 1; j < c.skeleton.jointCount(); ++j)
        k << "  <boneparent bone=\"" << c.skeleton.joints[j].name << "\" parent=\""
          << c.skeleton.joints[std::size_t(c.skeleton.joints[j].parent)].name << "\"/>\n";
    k << " </bonehierarchy>\n <animations>\n  <animation name=\"" << c.clips[0].name << "\" length=\"" << num(c.clips[0].duration)
      << "\">\n   <tracks>\n";
    const int frames = 31;
    for (std::size_t j = 0; j < c.skeleton.jointCount(); ++j) {
        k << "    <track bone=\"" << c.skeleton.joints[j].name << "\">\n     <keyframes>\n";
        for (int f = 0; f < frames; ++f) {
            const double t = c.clips[0].duration * f / (frames - 1);
            const Mat4 local = localsAt(c, t)[j];
            const Vec3 translate = local.topRightCorner<3, 1>() - rest[j].topRightCorner<3, 1>();
            const Mat3 rotate = rest[j].topLeftCorner<3, 3>().transpose() * local.topLeftCorner<3, 3>();
            k << "      <keyframe time=\"" << num(t) << "\">" << vec("translate", translate) << rotation("rotate", rotate)
              << vec("scale", Vec3::Ones()) << "</keyframe>\n";
        }
        k << "     </keyframes>\n    </track>\n";
    }
    k << "   </tracks>\n  </animation>\n </animations>\n</skeleton>\n";
    std::ofstream(stem + ".skeleton.xml") << k.str();
}

/// OpenGEX (.ogex): the rig's skin as one static mesh, in the units and up axis its Metric
/// structures state (assimp 5.2.5 reads no skin or animation from OpenGEX).
inline void writeOpenGex(const Character& c, const std::string& path, const FileSpace& space, const char* up) {
    std::ostringstream g;
    g << "Metric (key = \"distance\") {float {" << num(space.metresPerUnit) << "}}\n";
    g << "Metric (key = \"angle\") {float {1}}\nMetric (key = \"time\") {float {1}}\n";
    g << "Metric (key = \"up\") {string {\"" << up << "\"}}\n\n";
    g << "GeometryNode $node1\n{\n\tName {string {\"body\"}}\n\tObjectRef {ref {$geometry1}}\n}\n\n";
    g << "GeometryObject $geometry1\n{\n\tMesh (primitive = \"triangles\")\n\t{\n\t\tVertexArray (attrib = \"position\")\n\t\t{\n\t\t\tfloat[3]\n\t\t\t{\n";
    for (std::size_t v = 0; v < c.body.vertexCount(); ++v) {
        const Vec3 p = space.point(c.body.bindPositions[v]);
        g << "\t\t\t\t{" << num(p.x()) << ", " << num(p.y()) << ", " << num(p.z()) << "}" << (v + 1 < c.body.vertexCount() ? "," : "") << "\n";
    }
    g << "\t\t\t}\n\t\t}\n\n\t\tIndexArray\n\t\t{\n\t\t\tunsigned_int32[3]\n\t\t\t{\n";
    for (std::size_t t = 0; t < c.body.triangles.size(); ++t) {
        const auto& tri = c.body.triangles[t];
        g << "\t\t\t\t{" << tri[0] << ", " << tri[1] << ", " << tri[2] << "}" << (t + 1 < c.body.triangles.size() ? "," : "") << "\n";
    }
    g << "\t\t\t}\n\t\t}\n\t}\n}\n";
    std::ofstream(path) << g.str();
}

/// Biovision .bvh: the rig's skeleton and clip without any mesh (animation only).
inline void writeBvh(const Character& c, const std::string& path) {
    std::ostringstream b;
    b << "HIERARCHY\nROOT root\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
         "\tJOINT mid\n\t{\n\t\tOFFSET 0 0.5 0\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"
         "\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 0.5 0\n\t\t}\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n"
         "0 0 0 0 0 0 0 0 0\n0 0 0.1 0 0 0 30 0 0\n";
    (void)c;
    std::ofstream(path) << b.str();
}

} // namespace cc::test
