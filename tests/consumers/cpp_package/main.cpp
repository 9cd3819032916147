// A C++ host: one walking mannequin wearing a cape, through the installed crowdcloth/World.h.
#include <cstdio>

#include "crowdcloth/Version.h"
#include "crowdcloth/World.h"

template <typename T>
static T orExit(cc::Result<T> result, const char* what) {
    if (!result.isOk()) {
        std::fprintf(stderr, "%s failed: %s\n", what, result.status().message().c_str());
        std::exit(1);
    }
    return result.value();
}

int main() {
    if (cc::getVersion() != cc::kVersion) {
        std::fprintf(stderr, "library %x, headers %x\n", unsigned(cc::getVersion()),
                     unsigned(cc::kVersion));
        return 1;
    }
    cc::WorldDesc wd;
    wd.fixedCostModel = true;
    cc::World* world = orExit(cc::World::create(wd), "World::create");
    const cc::AssetId cape = orExit(world->addClothAsset({}), "addClothAsset");
    cc::CharacterDesc cd;
    cd.body = orExit(world->addMannequinBody({}), "addMannequinBody");
    const cc::CharacterId walker = orExit(world->addCharacter(cd), "addCharacter");
    const cc::GarmentId garment = orExit(world->addGarment(cape, walker, {}), "addGarment");
    for (int frame = 0; frame < 10; ++frame) {
        const cc::Status status = world->step(1.0 / 60.0);
        if (!status.isOk()) {
            std::fprintf(stderr, "step failed: %s\n", status.message().c_str());
            return 1;
        }
    }
    const cc::RenderMeshView mesh = orExit(world->renderMesh(garment), "renderMesh");
    std::printf("cpp consumer: crowdcloth %s, %u cape vertices, hash %016llx\n", CC_VERSION_STRING,
                mesh.vertexCount, static_cast<unsigned long long>(world->stateHash()));
    cc::World::destroy(world);
    return mesh.vertexCount > 0 ? 0 : 1;
}
