#pragma once

#include <memory>

#include "crowdcloth/World.h"

namespace cc::test {

/// A World that destroys itself (World::destroy) when the test is done with it.
struct WorldDeleter {
    void operator()(World* w) const { World::destroy(w); }
};
using WorldPtr = std::unique_ptr<World, WorldDeleter>;

} // namespace cc::test
