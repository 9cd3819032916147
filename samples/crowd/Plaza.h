#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/World.h"

namespace crowd {

/// How a plaza crowd is laid out; the same settings give the same crowd.
struct PlazaSettings {
    int characters = 200;
    double spacing = 3.2;        ///< [m] mean distance between neighbours
    double runnerFraction = 0.1; ///< [-] characters that run
    double idleFraction = 0.1;   ///< [-] characters that stand
    uint32_t seed = 1;
    /// Imported bodies to dress instead of the mannequins (round robin), each playing `clip` (by
    /// name; empty = its first clip) while walking its circle, in fitted capes and skirts.
    std::vector<cc::BodyId> bodies;
    std::string clip;
    double walkSpeed = 1.2;      ///< [m/s] imported characters' speed round their circles
};

/// A plaza of mannequins (or imported characters) walking circles, each wearing a cape or a
/// skirt, and a camera that circles and dollies through it.
class Plaza {
public:
    static cc::Result<Plaza> create(cc::World& world, const PlazaSettings& settings);

    /// Moves every character to where it is at time t [s] and points the camera.
    cc::Status update(cc::World& world, double t, int viewportWidth, int viewportHeight);

    double extent() const { return mExtent; }   ///< [m] half side of the plaza
    const double* viewProjection() const { return mViewProjection; }
    const std::vector<cc::CharacterId>& characters() const { return mCharacters; }
    const std::vector<cc::GarmentId>& garments() const { return mGarments; }
    const std::vector<int>& garmentKinds() const { return mKinds; }

private:
    struct Walker {
        double cx, cz, radius, phase, angularSpeed;
    };
    std::vector<Walker> mWalkers;
    std::vector<cc::CharacterId> mCharacters;
    std::vector<cc::GarmentId> mGarments;
    std::vector<int> mKinds;  ///< GarmentKind per garment
    double mExtent = 10.0;
    double mViewProjection[16] = {};
};

} // namespace crowd
