#pragma once

#include <filesystem>
#include <string>

#include "crowdcloth/World.h"
#include "crowdcloth/import/CharacterIO.h"
#include "support/CrowdScenes.h"

namespace cc::test {

/// `name`'s body added to `world`: "mannequin" is the built-in one, any other name a skinned file
/// in `humanoidsDir` (the shared humanoids, read in place). A missing file sets `absent`, so that
/// the test can skip with a message instead of failing where the shared folder is not beside the
/// clone.
inline Result<BodyId> addNamedBody(World& world, const std::string& name, const char* humanoidsDir,
                                   bool& absent) {
    absent = false;
    if (name == "mannequin") return world.addMannequinBody({});
    const std::filesystem::path file = std::filesystem::path(humanoidsDir) / name;
    if (!std::filesystem::exists(file)) {
        absent = true;
        return Status::invalidArgument("shared humanoid absent: " + file.string());
    }
    Result<Character> character = importCharacter(file.string());
    if (!character.isOk()) return character.status();
    return world.addCharacterBody(character.value());
}

/// A camera close up on a character about `height` tall whose root is at z: a garment's finest
/// level and the body mesh's contacts.
inline CameraDesc closeUpCamera(double height, double z) {
    const Vec3 target(0.0, 0.6 * height, z);
    return cameraLookingAt(target + Vec3(-0.6 * height, 0.2 * height, -1.2 * height), target);
}

} // namespace cc::test
