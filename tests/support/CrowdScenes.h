#pragma once

#include <cmath>
#include <vector>

#include "crowdcloth/World.h"
#include "support/Cameras.h"

namespace cc::test {

/// A garment kind's name for test output.
inline const char* kindName(GarmentKind kind) {
    switch (kind) {
    case GarmentKind::Cape: return "cape";
    case GarmentKind::Skirt: return "skirt";
    case GarmentKind::Dress: return "dress";
    case GarmentKind::Poncho: return "poncho";
    }
    return "?";
}

/// Every garment kind.
inline constexpr GarmentKind kGarmentKinds[] = {GarmentKind::Cape, GarmentKind::Skirt, GarmentKind::Dress,
                                                GarmentKind::Poncho};

/// Column-major view-projection of a 60-degree camera at `eye` looking at `target`.
inline CameraDesc cameraLookingAt(const Vec3& eye, const Vec3& target, double width = 1280, double height = 720) {
    const Mat4 vp = perspective(60.0 * M_PI / 180.0, width / height, 0.1, 500.0) * lookAt(eye, target);
    CameraDesc camera;
    for (int k = 0; k < 16; ++k) camera.viewProjection[k] = vp(k % 4, k / 4);
    camera.viewportWidth = width;
    camera.viewportHeight = height;
    return camera;
}

/// Characters walking side by side along +Z in rows, each with one garment of `asset`.
struct WalkingCrowd {
    std::vector<CharacterId> characters;
    std::vector<GarmentId> garments;
    std::vector<Vec3> starts;
    double speed = 1.2;  ///< [m/s]
};

inline WalkingCrowd addWalkingCrowd(World& world, AssetId asset, int count, int bodyVariants = 3) {
    WalkingCrowd crowd;
    std::vector<BodyId> bodies;
    for (int b = 0; b < bodyVariants; ++b) {
        MannequinDesc m;
        m.height = 1.65 + 0.07 * b;
        m.shoulderWidth = 0.38 + 0.02 * b;
        bodies.push_back(world.addMannequinBody(m).value());
    }
    for (int i = 0; i < count; ++i) {
        CharacterDesc c;
        c.body = bodies[i % bodies.size()];
        c.clipTime = 0.13 * i;
        const int row = i / 10; // ten to a row
        c.position[0] = 1.5 * (i % 10);
        c.position[2] = -2.0 * row;
        crowd.starts.push_back(Vec3(c.position[0], c.position[1], c.position[2]));
        crowd.characters.push_back(world.addCharacter(c).value());
        crowd.garments.push_back(world.addGarment(asset, crowd.characters.back(), {}).value());
    }
    return crowd;
}

/// Moves every character of the crowd to where it walks at time t [s].
inline void walkCrowd(World& world, const WalkingCrowd& crowd, double t) {
    for (std::size_t i = 0; i < crowd.characters.size(); ++i) {
        const Vec3 p = crowd.starts[i] + Vec3(0.0, 0.0, crowd.speed * t);
        const double position[3] = {p.x(), p.y(), p.z()};
        (void)world.setCharacterRoot(crowd.characters[i], position, 0.0);
    }
}

} // namespace cc::test
