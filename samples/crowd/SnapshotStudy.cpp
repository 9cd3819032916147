#include <chrono>
#include <cstdio>
#include <vector>

#include "Plaza.h"
#include "Studies.h"

namespace crowd {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr int kWidth = 1920, kHeight = 1080;
constexpr double kDt = 1.0 / 60.0;

/// A plaza world as the demo makes it, with the fixed cost model so that two runs can agree bit
/// for bit.
struct PlazaWorld {
    WorldPtr world;
    Plaza plaza;
};

cc::Result<PlazaWorld> makePlaza(int characters, int threads) {
    cc::WorldDesc desc;
    desc.fixedCostModel = true;
    desc.budgetThreads = 2;
    desc.maxThreads = uint32_t(threads);
    auto created = cc::World::create(desc);
    if (!created.isOk()) return created.status();
    WorldPtr world(created.value());
    PlazaSettings settings;
    settings.characters = characters;
    auto plaza = Plaza::create(*world, settings);
    if (!plaza.isOk()) return plaza.status();
    return PlazaWorld{std::move(world), std::move(plaza).value()};
}

} // namespace

int runSnapshotStudy(int characters, int threads) {
    auto a = makePlaza(characters, threads);
    if (!a.isOk()) {
        std::fprintf(stderr, "snapshot study: %s\n", a.status().message().c_str());
        return 1;
    }
    PlazaWorld& saving = a.value();
    const int warmup = 300, continued = 120;
    for (int f = 1; f <= warmup; ++f) {
        if (!saving.plaza.update(*saving.world, f * kDt, kWidth, kHeight).isOk() || !saving.world->step(kDt).isOk()) return 1;
    }
    auto start = Clock::now();
    auto saved = saving.world->saveState();
    const double saveMs = msSince(start);
    if (!saved.isOk()) {
        std::fprintf(stderr, "snapshot study: %s\n", saved.status().message().c_str());
        return 1;
    }
    // The restoring World is made as the saving one was (assets, bodies; the plaza's characters
    // too, which the restore replaces).
    auto b = makePlaza(characters, threads);
    if (!b.isOk()) return 1;
    PlazaWorld& restoring = b.value();
    start = Clock::now();
    const cc::Status restored = restoring.world->restoreState(saved.value().data(), saved.value().size());
    const double restoreMs = msSince(start);
    if (!restored) {
        std::fprintf(stderr, "snapshot study: %s\n", restored.message().c_str());
        return 1;
    }
    int identical = 0;
    for (int f = warmup + 1; f <= warmup + continued; ++f) {
        for (PlazaWorld* p : {&saving, &restoring})
            if (!p->plaza.update(*p->world, f * kDt, kWidth, kHeight).isOk() || !p->world->step(kDt).isOk()) return 1;
        identical += saving.world->stateHash() == restoring.world->stateHash();
    }
    std::printf("snapshot of %d characters after %d frames: %zu bytes, saved in %.1f ms, restored into a fresh World "
                "in %.1f ms; %d of the next %d frames identical\n",
                characters, warmup, saved.value().size(), saveMs, restoreMs, identical, continued);
    std::printf("BAR snapshot chars=%d bytes=%zu save_ms=%.2f restore_ms=%.2f identical_frames=%d/%d\n", characters,
                saved.value().size(), saveMs, restoreMs, identical, continued);
    return identical == continued ? 0 : 1;
}

} // namespace crowd
