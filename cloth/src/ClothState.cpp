#include "crowdcloth/cloth/ClothState.h"

#include "crowdcloth/core/Hash.h"

namespace cc::cloth {

double ClothState::kineticEnergy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < velocities.size(); ++i) e += 0.5 * masses[i] * velocities[i].squaredNorm();
    return e;
}

double ClothState::gravityEnergy(const Vec3& gravity) const {
    double e = 0.0;
    for (std::size_t i = 0; i < positions.size(); ++i) e -= masses[i] * gravity.dot(positions[i]);
    return e;
}

uint32_t ClothState::firstNonFinite() const {
    for (uint32_t i = 0; i < vertexCount(); ++i) {
        if (!isFinite(positions[i]) || !isFinite(velocities[i])) return i;
    }
    return vertexCount();
}

uint64_t ClothState::hash() const {
    uint64_t h = hashBytes(positions.data(), positions.size() * sizeof(Vec3));
    return hashBytes(velocities.data(), velocities.size() * sizeof(Vec3), h);
}

} // namespace cc::cloth
