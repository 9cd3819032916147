#pragma once

#include <algorithm>
#include <cctype>
#include <string>

#include <assimp/matrix4x4.h>
#include <assimp/quaternion.h>
#include <assimp/vector3.h>

#include "crowdcloth/character/Transform.h"

namespace cc::detail {

// assimp stores matrices row-major (a1..a4 is the first row); Eigen's Mat4 is column-major.
inline Mat4 toMat4(const aiMatrix4x4& m) {
    Mat4 r;
    r << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
    return r;
}

inline aiMatrix4x4 toAi(const Mat4& m) {
    return aiMatrix4x4(static_cast<ai_real>(m(0, 0)), static_cast<ai_real>(m(0, 1)), static_cast<ai_real>(m(0, 2)),
                       static_cast<ai_real>(m(0, 3)), static_cast<ai_real>(m(1, 0)), static_cast<ai_real>(m(1, 1)),
                       static_cast<ai_real>(m(1, 2)), static_cast<ai_real>(m(1, 3)), static_cast<ai_real>(m(2, 0)),
                       static_cast<ai_real>(m(2, 1)), static_cast<ai_real>(m(2, 2)), static_cast<ai_real>(m(2, 3)),
                       static_cast<ai_real>(m(3, 0)), static_cast<ai_real>(m(3, 1)), static_cast<ai_real>(m(3, 2)),
                       static_cast<ai_real>(m(3, 3)));
}

inline Vec3 toVec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }
inline aiVector3D toAi(const Vec3& v) {
    return aiVector3D(static_cast<ai_real>(v.x()), static_cast<ai_real>(v.y()), static_cast<ai_real>(v.z()));
}
inline Quat toQuat(const aiQuaternion& q) { return Quat(q.w, q.x, q.y, q.z); }
inline aiQuaternion toAi(const Quat& q) {
    return aiQuaternion(static_cast<ai_real>(q.w()), static_cast<ai_real>(q.x()), static_cast<ai_real>(q.y()),
                        static_cast<ai_real>(q.z()));
}

// Lower-case extension of the file name in `path` (without the dot), or "" if it has none.
inline std::string lowerExtension(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

} // namespace cc::detail
