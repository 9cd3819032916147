#include "Plaza.h"

#include "Studies.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>

namespace crowd {
cc::Result<Plaza> Plaza::create(cc::World& world, const PlazaSettings& settings) {
    Plaza plaza;
    std::mt19937 rng(settings.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    plaza.mExtent = 0.5 * settings.spacing * std::sqrt(double(std::max(settings.characters, 1)));

    // A few body variants, shared by the whole crowd (bodies are cooked once, like garments).
    std::vector<cc::BodyId> bodies = settings.bodies;
    const bool imported = !bodies.empty();
    for (int b = 0; b < 6 && !imported; ++b) {
        cc::MannequinDesc m;
        m.height = 1.62 + 0.05 * b;
        m.shoulderWidth = 0.37 + 0.01 * (b % 3);
        m.hipWidth = 0.33 + 0.01 * ((b + 1) % 3);
        m.limbGirth = 0.9 + 0.05 * (b % 4);
        auto body = world.addMannequinBody(m);
        if (!body.isOk()) return body.status();
        bodies.push_back(body.value());
    }
    cc::ClothAssetDesc capeDesc;
    capeDesc.width = 0.7;
    capeDesc.length = 1.0;
    cc::ClothAssetDesc skirtDesc;
    skirtDesc.kind = cc::GarmentKind::Skirt;
    skirtDesc.width = 1.3;
    skirtDesc.length = 0.6;
    skirtDesc.cellSize = 0.16;
    if (imported) {
        // Any body: the sizes come from each one (fitted garments).
        capeDesc = cc::ClothAssetDesc{};
        skirtDesc = cc::ClothAssetDesc{};
        skirtDesc.kind = cc::GarmentKind::Skirt;
    }
    auto cape = world.addClothAsset(capeDesc);
    if (!cape.isOk()) return cape.status();
    auto skirt = world.addClothAsset(skirtDesc);
    if (!skirt.isOk()) return skirt.status();

    for (int i = 0; i < settings.characters; ++i) {
        const double roll = unit(rng);
        const bool runs = roll < settings.runnerFraction;
        const bool idle = !runs && roll < settings.runnerFraction + settings.idleFraction;
        Walker w;
        w.cx = (2.0 * unit(rng) - 1.0) * plaza.mExtent;
        w.cz = (2.0 * unit(rng) - 1.0) * plaza.mExtent;
        w.radius = 2.0 + 6.0 * unit(rng);
        w.phase = 2.0 * M_PI * unit(rng);
        const double speed = imported ? settings.walkSpeed : idle ? 0.0 : runs ? 4.6 : 1.35;
        w.angularSpeed = (unit(rng) < 0.5 ? 1.0 : -1.0) * speed / w.radius;
        cc::CharacterDesc c;
        c.body = bodies[i % bodies.size()];
        c.clip = idle ? "idle" : runs ? "run" : "walk";
        c.clipTime = 3.0 * unit(rng);
        if (imported) {
            c.clip = settings.clip.empty() ? nullptr : settings.clip.c_str();
            c.clipIndex = settings.clip.empty() ? 0 : -1;
            c.clipTime = 0.0;
            c.clipPhase = unit(rng);
        }
        auto character = world.addCharacter(c);
        if (!character.isOk()) return character.status();
        const bool wearsSkirt = unit(rng) < 0.35;
        auto garment = world.addGarment(wearsSkirt ? skirt.value() : cape.value(), character.value(), {});
        if (!garment.isOk()) return garment.status();
        plaza.mWalkers.push_back(w);
        plaza.mCharacters.push_back(character.value());
        plaza.mGarments.push_back(garment.value());
        plaza.mKinds.push_back(int(wearsSkirt ? cc::GarmentKind::Skirt : cc::GarmentKind::Cape));
    }
    return plaza;
}

cc::Status Plaza::update(cc::World& world, double t, int viewportWidth, int viewportHeight) {
    for (std::size_t i = 0; i < mWalkers.size(); ++i) {
        const Walker& w = mWalkers[i];
        const double angle = w.phase + w.angularSpeed * t;
        const double position[3] = {w.cx + w.radius * std::cos(angle), 0.0, w.cz + w.radius * std::sin(angle)};
        // Facing along the circle: the derivative of the position, direction of travel.
        const double dx = -std::sin(angle) * w.angularSpeed, dz = std::cos(angle) * w.angularSpeed;
        const double yaw = w.angularSpeed == 0.0 ? w.phase : std::atan2(dx, dz);
        if (cc::Status s = world.setCharacterRoot(mCharacters[i], position, yaw); !s) return s;
    }
    // The camera circles the plaza at walking height and dollies in and out every 20 s.
    const double orbit = 0.05 * t, dolly = 0.5 + 0.45 * std::cos(2.0 * M_PI * t / 20.0);
    const double radius = 3.0 + dolly * 1.2 * mExtent;
    const Eigen::Vector3d eye(radius * std::cos(orbit), 1.7 + 0.15 * radius, radius * std::sin(orbit));
    const Eigen::Vector3d target(0.2 * radius * std::cos(orbit), 1.0, 0.2 * radius * std::sin(orbit));
    lookAt(eye, target, double(viewportWidth) / viewportHeight, mViewProjection);
    cc::CameraDesc camera;
    for (int k = 0; k < 16; ++k) camera.viewProjection[k] = mViewProjection[k];
    camera.viewportWidth = viewportWidth;
    camera.viewportHeight = viewportHeight;
    return world.setCameras(&camera, 1);
}

} // namespace crowd
