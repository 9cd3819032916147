#include "crowdcloth/collision/CollisionDevice.h"

#include "EmbreeDevice.h"

namespace cc::collision {

Status CollisionDeviceSettings::validate() const {
    if (threads < 1 || threads > 256) {
        return Status::invalidArgument("CollisionDeviceSettings.threads = " + std::to_string(threads) +
                                       " is outside [1, 256]");
    }
    return Status::ok();
}

namespace {
void onEmbreeError(void* user, RTCError code, const char* message) {
    auto* impl = static_cast<CollisionDevice::Impl*>(user);
    std::lock_guard<std::mutex> lock(impl->errorMutex);
    if (impl->firstError.empty()) {
        impl->firstError = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "(no message)");
    }
}
} // namespace

Result<std::unique_ptr<CollisionDevice>> CollisionDevice::create(const CollisionDeviceSettings& settings) {
    if (Status s = settings.validate(); !s) return s;
    auto impl = std::make_unique<Impl>();
    const std::string config = "threads=" + std::to_string(settings.threads);
    impl->device = rtcNewDevice(config.c_str());
    if (!impl->device) {
        return Status::error(StatusCode::InvalidOperation,
                             "CollisionDevice: rtcNewDevice(\"" + config + "\") failed with Embree error " +
                                 std::to_string(int(rtcGetDeviceError(nullptr))));
    }
    rtcSetDeviceErrorFunction(impl->device, onEmbreeError, impl.get());
    return std::unique_ptr<CollisionDevice>(new CollisionDevice(std::move(impl)));
}

CollisionDevice::CollisionDevice(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}

CollisionDevice::~CollisionDevice() {
    if (mImpl && mImpl->device) rtcReleaseDevice(mImpl->device);
}

Status CollisionDevice::takeError() {
    std::lock_guard<std::mutex> lock(mImpl->errorMutex);
    if (mImpl->firstError.empty()) return Status::ok();
    Status s = Status::error(StatusCode::InvalidOperation, mImpl->firstError);
    mImpl->firstError.clear();
    return s;
}

} // namespace cc::collision
