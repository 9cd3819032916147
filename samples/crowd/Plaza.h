#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/World.h"

namespace crowd {

/// Shares of the crowd wearing each garment kind (normalised; 0 = none).
struct GarmentMix {
    double cape = 0.35, skirt = 0.25, dress = 0.2, poncho = 0.2;
};

/// One key of the camera path. With `follow` >= 0 the eye and target are offsets from that
/// character's root in its own frame (x right, y up, z forward), so the camera keeps up with it.
struct CameraKey {
    double time = 0.0;                    ///< [s] keys in increasing time; the path loops after the last
    std::array<double, 3> eye{0, 0, 0};   ///< [m]
    std::array<double, 3> target{0, 0, 0};
    int follow = -1;                      ///< character index, -1 = plaza coordinates
};

/// How a plaza crowd is laid out; the same settings give the same crowd.
struct PlazaSettings {
    int characters = 200;
    double spacing = 3.2;        ///< [m] mean distance between neighbours
    double runnerFraction = 0.1; ///< [-] characters that run
    double idleFraction = 0.1;   ///< [-] characters that stand
    double stopStartFraction = 0.3; ///< [-] of those that move, the share that stop now and then
                                    ///< (brake, stand, set off again; the clip slows with them)
    uint32_t seed = 1;
    GarmentMix garments;
    double velocityDamping = 0.4; ///< [1/s] the garments' (ClothAssetDesc::velocityDamping)
    /// [s] the garments' Rayleigh damping (ClothAssetDesc::damping): a tenth of the plaza stands,
    /// and without it their skirts and dresses keep moving as in wind (README, garments at rest).
    double stiffnessDamping = 0.01;
    double inertiaScale = 1.0;    ///< [-] the garments' (GarmentDesc::inertiaScale)
    /// The camera path; empty = the built-in one (a wide shot circling the crowd, a flight into a
    /// close-up of the character nearest the centre, and back, every 20 s).
    std::vector<CameraKey> camera;
    /// Imported bodies to dress instead of the mannequins (round robin), each playing `clip` (by
    /// name; empty = its first clip) while walking its circle, in fitted garments.
    std::vector<cc::BodyId> bodies;
    std::string clip;
    double walkSpeed = 1.2;      ///< [m/s] imported characters' speed round their circles
    /// Where each design's measured error table is cached (World::loadErrorTable: cooked on first
    /// use, about half a minute per design); the scheduler then predicts from measurements instead
    /// of its formula. Empty = the formula.
    std::string errorTables;
};

/// A plaza of mannequins (or imported characters) walking and running circles (turning all the
/// while) or standing, each wearing a cape, skirt, dress or poncho, and a camera on a path through it.
class Plaza {
public:
    static cc::Result<Plaza> create(cc::World& world, const PlazaSettings& settings);

    /// Character i leaves the world with its garment and an identical one joins in its place
    /// (new handles; a soak's churn). Its garment starts again from the fitted drape.
    cc::Status respawn(cc::World& world, std::size_t i);

    /// Moves every character to where it is at time t [s] and points the camera.
    cc::Status update(cc::World& world, double t, int viewportWidth, int viewportHeight);

    double extent() const { return mExtent; }   ///< [m] half side of the plaza
    const double* viewProjection() const { return mViewProjection; }
    const std::vector<cc::CharacterId>& characters() const { return mCharacters; }
    const std::vector<cc::GarmentId>& garments() const { return mGarments; }
    const std::vector<int>& garmentKinds() const { return mKinds; }  ///< cc::GarmentKind per garment
    /// Outside colour (RGB in [0, 1]) of each garment; the inside is a darker shade of it.
    const std::vector<std::array<float, 3>>& garmentColours() const { return mColours; }
    /// The camera path in use (the settings' or the built-in one).
    const std::vector<CameraKey>& cameraPath() const { return mCamera; }
    /// The built-in camera path for a plaza of this many characters (written out as the example scene).
    static std::vector<CameraKey> defaultCameraPath(const PlazaSettings& settings);

private:
    struct Walker {
        double cx, cz, radius, phase, angularSpeed;  ///< [rad/s] signed: the direction round
        double gaitOffset = -1.0;  ///< [s] where in its stop-and-start cycle it is at t = 0; < 0: never stops
    };
    cc::Status pointCamera(cc::World& world, double t, int viewportWidth, int viewportHeight);

    std::vector<Walker> mWalkers;
    std::vector<cc::CharacterId> mCharacters;
    std::vector<cc::GarmentId> mGarments;
    struct Joiner {  ///< how character i was added, to add it again (respawn)
        cc::CharacterDesc character;
        cc::AssetId asset;
        cc::GarmentDesc garment;
    };
    std::vector<Joiner> mJoiners;
    std::string mClip;  ///< the imported characters' clip (their descs point into it)
    std::vector<int> mKinds;
    std::vector<std::array<float, 3>> mColours;
    std::vector<CameraKey> mCamera;
    std::vector<std::array<double, 4>> mRoots;  ///< this frame's x, y, z, yaw per character
    double mExtent = 10.0;
    double mViewProjection[16] = {};
};

} // namespace crowd
