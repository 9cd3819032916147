#pragma once

#include <memory>
#include <string>

#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Settings of the world's collision device (one Embree device per world, STYLE.md §7).
struct CollisionDeviceSettings {
    int threads = 1;  ///< [-] Embree build threads; [1, 256]. 1 keeps Embree's TBB pool from
                      ///< competing with the module's OpenMP regions on small machines

    /// Names the first invalid field.
    Status validate() const;
};

/// Owns the Embree device that every BodyCollider of one world is built on. Create one per world;
/// it must outlive its colliders. Not thread-safe to create or destroy; colliders built on it may
/// be queried concurrently.
///
///   auto device = CollisionDevice::create({}).value();
///   auto body = BodyCollider::create(*device, triangles, positions).value();
class CollisionDevice {
public:
    static Result<std::unique_ptr<CollisionDevice>> create(const CollisionDeviceSettings& settings);
    ~CollisionDevice();
    CollisionDevice(const CollisionDevice&) = delete;
    CollisionDevice& operator=(const CollisionDevice&) = delete;

    /// The first error Embree reported since the last call (and clears it); Ok if none.
    Status takeError();

    struct Impl;
    Impl& impl() { return *mImpl; }

private:
    explicit CollisionDevice(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> mImpl;
};

} // namespace cc::collision
