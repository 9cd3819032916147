#pragma once

#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/character/Character.h"
#include "crowdcloth/character/SkinnedMesh.h"

namespace cc::test {

/// The character's body skinned at its skeleton's rest pose.
inline std::vector<Vec3> restPositionsOf(const Character& ch) {
    CharacterPose pose(ch);
    EXPECT_TRUE(pose.evaluate(ch, -1, 0.0, ClipWrap::Clamp).isOk());
    std::vector<Vec3> p(ch.body.vertexCount());
    EXPECT_TRUE(skinVertices(ch.body, pose.skinMatrices(), p, {}).isOk());
    return p;
}

} // namespace cc::test
