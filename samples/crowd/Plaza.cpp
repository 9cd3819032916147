#include "Plaza.h"

#include "Studies.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

namespace crowd {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Cloth colours of the crowd (outside); the inside is drawn darker.
const std::array<float, 3> kCapeColours[] = {{0.70f, 0.13f, 0.13f}, {0.55f, 0.10f, 0.45f}, {0.15f, 0.45f, 0.25f}};
const std::array<float, 3> kSkirtColours[] = {{0.15f, 0.33f, 0.70f}, {0.80f, 0.55f, 0.15f}, {0.20f, 0.55f, 0.60f}};
const std::array<float, 3> kDressColours[] = {{0.85f, 0.75f, 0.30f}, {0.30f, 0.25f, 0.60f}, {0.75f, 0.35f, 0.45f}};
const std::array<float, 3> kPonchoColours[] = {{0.45f, 0.30f, 0.15f}, {0.85f, 0.40f, 0.10f}, {0.35f, 0.50f, 0.20f}};

double smoothstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

/// The integral of smoothstep from 0 to x, x in [0, 1] (1/2 at 1).
double smoothstepIntegral(double x) { return x * x * x - 0.5 * x * x * x * x; }

/// A stop-and-start walker's cycle [s]: it walks, brakes, stands and sets off again, its speed
/// ramping smoothly (a 1.35 m/s walker brakes at up to 2 m/s^2, a 4.6 m/s runner at 6.9: the
/// garments swing forward as they stop and trail as they start).
constexpr double kCruise = 4.0, kRamp = 1.0, kStand = 1.5;
constexpr double kGaitCycle = kCruise + kRamp + kStand + kRamp;

struct Gait {
    double speed;      ///< [-] share of the walker's full speed
    double travelled;  ///< [s] time at full speed that covers the distance walked since the cycle began
};

Gait stopAndStart(double t) {
    const double cycles = std::floor(t / kGaitCycle);
    double u = t - cycles * kGaitCycle;
    double travelled = cycles * (kCruise + kRamp);  // each ramp covers half its time at full speed
    if (u < kCruise) return {1.0, travelled + u};
    travelled += kCruise;
    u -= kCruise;
    if (u < kRamp) {
        const double x = u / kRamp;
        return {1.0 - smoothstep(x), travelled + kRamp * (x - smoothstepIntegral(x))};
    }
    travelled += 0.5 * kRamp;
    u -= kRamp;
    if (u < kStand) return {0.0, travelled};
    const double x = (u - kStand) / kRamp;
    return {smoothstep(x), travelled + kRamp * smoothstepIntegral(x)};
}

} // namespace

std::vector<CameraKey> Plaza::defaultCameraPath(const PlazaSettings& settings) {
    const double extent = 0.5 * settings.spacing * std::sqrt(double(std::max(settings.characters, 1)));
    const double wide = 3.0 + 1.1 * extent;
    // Wide shot (0-6 s), into a close-up of character 0 from behind and to its side (8-13 s),
    // round to its front (13-15 s), back out (17-20 s); then again.
    std::vector<CameraKey> path;
    path.push_back({0.0, {wide, 1.7 + 0.15 * wide, 0.0}, {0.0, 1.0, 0.0}, -1});
    path.push_back({6.0, {0.0, 1.7 + 0.15 * wide, wide}, {0.0, 1.0, 0.0}, -1});
    path.push_back({8.0, {-1.6, 1.6, -2.4}, {0.0, 1.1, 0.0}, 0});
    path.push_back({13.0, {-2.2, 1.4, 0.4}, {0.0, 1.1, 0.0}, 0});
    path.push_back({15.0, {-1.0, 1.5, 2.4}, {0.0, 1.1, 0.0}, 0});
    path.push_back({17.0, {-wide, 1.7 + 0.15 * wide, 0.0}, {0.0, 1.0, 0.0}, -1});
    path.push_back({20.0, {wide, 1.7 + 0.15 * wide, 0.0}, {0.0, 1.0, 0.0}, -1});
    return path;
}

/// Adds a garment design, with its measured error table when the settings name a cache.
cc::Result<cc::AssetId> addDesign(cc::World& world, const cc::ClothAssetDesc& desc, const PlazaSettings& settings) {
    auto id = world.addClothAsset(desc);
    if (!id.isOk() || settings.errorTables.empty()) return id;
    if (cc::Status s = world.loadErrorTable(id.value(), settings.errorTables.c_str()); !s) return s;
    return id;
}

cc::Result<Plaza> Plaza::create(cc::World& world, const PlazaSettings& settings) {
    Plaza plaza;
    std::mt19937 rng(settings.seed);
    std::mt19937 gaitRng(settings.seed ^ 0x9e3779b9u);  // its own stream: the layout stays the seed's
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    plaza.mExtent = 0.5 * settings.spacing * std::sqrt(double(std::max(settings.characters, 1)));
    plaza.mCamera = settings.camera.empty() ? defaultCameraPath(settings) : settings.camera;
    for (std::size_t i = 0; i < plaza.mCamera.size(); ++i) {
        const CameraKey& k = plaza.mCamera[i];
        if (!std::isfinite(k.time) || k.time < 0.0 || (i > 0 && !(k.time > plaza.mCamera[i - 1].time)))
            return cc::Status::invalidArgument("camera key " + std::to_string(i) +
                                               ": times must be finite, >= 0 and increasing");
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(k.eye[c]) || !std::isfinite(k.target[c]))
                return cc::Status::invalidArgument("camera key " + std::to_string(i) + ": eye and target must be finite");
        if (k.follow >= settings.characters)
            return cc::Status::invalidArgument("camera key at " + std::to_string(k.time) + " s follows character " +
                                               std::to_string(k.follow) + " of " +
                                               std::to_string(settings.characters));
    }

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
    // Designs fitted to each body (sizes 0 = measured), in two lengths and cuts each.
    struct Design {
        cc::GarmentKind kind;
        cc::ClothAssetDesc desc;
        std::vector<cc::AssetId> ids;  // one per variant
    };
    const cc::GarmentKind kinds[4] = {cc::GarmentKind::Cape, cc::GarmentKind::Skirt, cc::GarmentKind::Dress,
                                      cc::GarmentKind::Poncho};
    const double shares[4] = {settings.garments.cape, settings.garments.skirt, settings.garments.dress,
                              settings.garments.poncho};
    double total = 0.0;
    for (double s : shares) {
        if (!(s >= 0.0 && std::isfinite(s))) return cc::Status::invalidArgument("garment shares must be >= 0");
        total += s;
    }
    if (!(total > 0.0)) return cc::Status::invalidArgument("garment shares must not all be 0");
    std::vector<std::vector<cc::AssetId>> variants(4);
    for (int k = 0; k < 4; ++k) {
        if (shares[k] == 0.0) continue;
        for (int v = 0; v < 2; ++v) {
            cc::ClothAssetDesc d;
            d.kind = kinds[k];
            d.cut = v == 0 ? cc::GarmentCut::ALine : kinds[k] == cc::GarmentKind::Skirt ? cc::GarmentCut::Circle
                                                                                        : cc::GarmentCut::Straight;
            const double baseLength[4] = {0.5, 0.3, 0.45, 0.3};
            d.relativeLength = baseLength[k] * (v == 0 ? 1.0 : 0.8);
            d.velocityDamping = settings.velocityDamping;
            d.damping = settings.stiffnessDamping;
            auto id = addDesign(world, d, settings);
            if (!id.isOk()) return id.status();
            variants[k].push_back(id.value());
        }
    }

    // The close-up's character wears a full half-circle cape, wide over the shoulders and long:
    // the garment whose folds and swing the camera comes to see.
    cc::AssetId heroCape{};
    if (!imported && shares[0] > 0.0) {
        cc::ClothAssetDesc d;
        d.cut = cc::GarmentCut::Circle;
        d.width = 0.7;
        d.length = 1.0;
        d.velocityDamping = settings.velocityDamping;
        d.damping = settings.stiffnessDamping;
        auto id = addDesign(world, d, settings);
        if (!id.isOk()) return id.status();
        heroCape = id.value();
    }

    for (int i = 0; i < settings.characters; ++i) {
        const double roll = unit(rng);
        const bool runs = roll < settings.runnerFraction;
        const bool idle = !runs && roll < settings.runnerFraction + settings.idleFraction;
        Walker w;
        w.cx = (2.0 * unit(rng) - 1.0) * plaza.mExtent;
        w.cz = (2.0 * unit(rng) - 1.0) * plaza.mExtent;
        w.radius = 2.0 + 6.0 * unit(rng);
        w.phase = 2.0 * kPi * unit(rng);
        const double speed = imported ? settings.walkSpeed : idle ? 0.0 : runs ? 4.6 : 1.35;
        w.angularSpeed = (unit(rng) < 0.5 ? 1.0 : -1.0) * speed / w.radius;
        if (speed > 0.0 && unit(gaitRng) < settings.stopStartFraction) w.gaitOffset = kGaitCycle * unit(gaitRng);
        if (i == 0) {  // the close-up's character walks near the centre and stops in the close-up
            w.cx = w.cz = 0.0;
            w.radius = 4.0;
            w.angularSpeed = 1.35 / w.radius;
            const double brakes = 8.4;  // [s] the built-in camera path is close behind it from 8 s (the run ends at 10)
            w.gaitOffset = settings.stopStartFraction > 0.0 ? std::fmod(kCruise - brakes + 2.0 * kGaitCycle, kGaitCycle) : -1.0;
        }
        cc::CharacterDesc c;
        c.body = bodies[i % bodies.size()];
        c.clip = i == 0 ? "walk" : idle ? "idle" : runs ? "run" : "walk";
        c.clipTime = 3.0 * unit(rng);
        if (imported) {
            c.clip = settings.clip.empty() ? nullptr : settings.clip.c_str();
            c.clipIndex = settings.clip.empty() ? 0 : -1;
            c.clipTime = 0.0;
            c.clipPhase = unit(rng);
        }
        auto character = world.addCharacter(c);
        if (!character.isOk()) return character.status();
        double pick = unit(rng) * total;
        int kind = 0;
        while (kind < 3 && (shares[kind] == 0.0 || pick >= shares[kind])) pick -= shares[kind++];
        if (i == 0 && shares[0] > 0.0) kind = 0;  // the close-up shows a cape's swing
        const int variant = int(unit(rng) * 2.0) % 2;
        cc::GarmentDesc gd;
        gd.inertiaScale = settings.inertiaScale;
        const bool hero = i == 0 && kind == 0 && !imported && shares[0] > 0.0;
        auto garment = world.addGarment(hero ? heroCape : variants[kind][variant], character.value(), gd);
        if (!garment.isOk()) return garment.status();
        const auto* palette = kind == 0 ? kCapeColours : kind == 1 ? kSkirtColours : kind == 2 ? kDressColours
                                                                                             : kPonchoColours;
        plaza.mWalkers.push_back(w);
        plaza.mJoiners.push_back({c, hero ? heroCape : variants[kind][variant], gd});
        plaza.mCharacters.push_back(character.value());
        plaza.mGarments.push_back(garment.value());
        plaza.mKinds.push_back(int(kinds[kind]));
        plaza.mColours.push_back(palette[int(unit(rng) * 3.0) % 3]);
    }
    plaza.mRoots.resize(plaza.mWalkers.size());
    plaza.mClip = settings.clip;
    return plaza;
}

cc::Status Plaza::respawn(cc::World& world, std::size_t i) {
    if (i >= mCharacters.size()) return cc::Status::invalidArgument("respawn: no character " + std::to_string(i));
    if (cc::Status s = world.removeCharacter(mCharacters[i]); !s) return s;
    Joiner& j = mJoiners[i];
    if (j.character.clipIndex < 0 && !mClip.empty()) j.character.clip = mClip.c_str();
    auto character = world.addCharacter(j.character);
    if (!character.isOk()) return character.status();
    auto garment = world.addGarment(j.asset, character.value(), j.garment);
    if (!garment.isOk()) return garment.status();
    mCharacters[i] = character.value();
    mGarments[i] = garment.value();
    return cc::Status::ok();
}

cc::Status Plaza::update(cc::World& world, double t, int viewportWidth, int viewportHeight) {
    for (std::size_t i = 0; i < mWalkers.size(); ++i) {
        const Walker& w = mWalkers[i];
        double travelled = t;
        if (w.gaitOffset >= 0.0) {
            const Gait gait = stopAndStart(t + w.gaitOffset);
            travelled = gait.travelled;
            if (cc::Status s = world.setCharacterPlaybackRate(mCharacters[i], gait.speed); !s) return s;
        }
        const double angle = w.phase + w.angularSpeed * travelled;
        const double position[3] = {w.cx + w.radius * std::cos(angle), 0.0, w.cz + w.radius * std::sin(angle)};
        // Facing along the circle: the derivative of the position, direction of travel.
        const double dx = -std::sin(angle) * w.angularSpeed, dz = std::cos(angle) * w.angularSpeed;
        const double yaw = w.angularSpeed == 0.0 ? w.phase : std::atan2(dx, dz);
        if (cc::Status s = world.setCharacterRoot(mCharacters[i], position, yaw); !s) return s;
        mRoots[i] = {position[0], position[1], position[2], yaw};
    }
    return pointCamera(world, t, viewportWidth, viewportHeight);
}

cc::Status Plaza::pointCamera(cc::World& world, double t, int viewportWidth, int viewportHeight) {
    // Where a key puts the eye and target at time t (a followed character moves).
    auto place = [&](const CameraKey& k, Eigen::Vector3d& eye, Eigen::Vector3d& target) {
        eye = Eigen::Vector3d(k.eye[0], k.eye[1], k.eye[2]);
        target = Eigen::Vector3d(k.target[0], k.target[1], k.target[2]);
        if (k.follow < 0) return;
        const auto& r = mRoots[std::size_t(k.follow)];
        const Eigen::Matrix3d turn = Eigen::AngleAxisd(r[3], Eigen::Vector3d::UnitY()).toRotationMatrix();
        const Eigen::Vector3d root(r[0], r[1], r[2]);
        eye = root + turn * eye;
        target = root + turn * target;
    };
    Eigen::Vector3d eye, target;
    if (mCamera.size() == 1) {
        place(mCamera[0], eye, target);
    } else {
        const double period = mCamera.back().time;
        const double local = period > 0.0 ? std::fmod(t, period) : 0.0;
        std::size_t k = 0;
        while (k + 2 < mCamera.size() && local >= mCamera[k + 1].time) ++k;
        const double span = mCamera[k + 1].time - mCamera[k].time;
        const double s = smoothstep(span > 0.0 ? (local - mCamera[k].time) / span : 1.0);
        Eigen::Vector3d e0, t0, e1, t1;
        place(mCamera[k], e0, t0);
        place(mCamera[k + 1], e1, t1);
        eye = e0 + s * (e1 - e0);
        target = t0 + s * (t1 - t0);
    }
    lookAt(eye, target, double(viewportWidth) / viewportHeight, mViewProjection);
    cc::CameraDesc camera;
    for (int k = 0; k < 16; ++k) camera.viewProjection[k] = mViewProjection[k];
    camera.viewportWidth = viewportWidth;
    camera.viewportHeight = viewportHeight;
    return world.setCameras(&camera, 1);
}

} // namespace crowd
