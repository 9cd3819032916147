#include "crowdcloth/crowdcloth_import.h"

#include <new>
#include <string>

#include "CApiWorld.h"
#include "crowdcloth/import/CharacterIO.h"

extern "C" {

void cc_import_settings_init(cc_import_settings* d) {
    if (!d) return;
    const cc::ImportSettings x;
    d->version = CC_DESC_VERSION;
    d->join_identical_vertices = x.joinIdenticalVertices;
    d->weight_sum_tolerance = x.weightSumTolerance;
    d->unit_scale = x.unitScale;
    d->up_axis = cc_up_axis(x.upAxis);
    d->ticks_per_second = x.ticksPerSecond;
    d->isolate = x.isolate;
    d->timeout_seconds = x.timeoutSeconds;
    d->max_file_bytes = x.maxFileBytes;
    d->max_memory_bytes = x.maxMemoryBytes;
}

cc_status cc_world_add_body_from_file(cc_world* w, const char* path, const cc_import_settings* d, const cc_body_desc* bd,
                                      cc_body_id* out) {
    if (!w || !w->world) return CC_INVALID_ARGUMENT;
    const auto fail = [&](const char* message) {
        w->lastError = message;
        return CC_INVALID_ARGUMENT;
    };
    if (!path) return fail("path is null");
    if (!out) return fail("out_body is null");
    if (const std::string refused = d ? cc::detail::stampError("import settings", "cc_import_settings_init", d->version)
                                      : std::string();
        !refused.empty())
        return fail(refused.c_str());
    if (const std::string refused = bd ? cc::detail::stampError("body desc", "cc_body_desc_init", bd->version)
                                       : std::string();
        !refused.empty())
        return fail(refused.c_str());
    try {
        cc::ImportSettings settings;
        if (d) {
            settings.joinIdenticalVertices = d->join_identical_vertices != 0;
            settings.weightSumTolerance = d->weight_sum_tolerance;
            settings.unitScale = d->unit_scale;
            settings.upAxis = cc::ImportUpAxis(d->up_axis);
            settings.ticksPerSecond = d->ticks_per_second;
            settings.isolate = d->isolate != 0;
            settings.timeoutSeconds = d->timeout_seconds;
            settings.maxFileBytes = std::size_t(d->max_file_bytes);
            settings.maxMemoryBytes = std::size_t(d->max_memory_bytes);
        }
        auto character = cc::importCharacter(path, settings);
        if (!character.isOk()) return cc::detail::reportToC(w, character.status());
        cc::BodyDesc desc;
        if (bd) desc.height = bd->height;
        auto body = w->world->addCharacterBody(character.value(), desc);
        if (body.isOk()) *out = body.value();
        return cc::detail::reportToC(w, body.status());
    } catch (const std::bad_alloc&) {
        w->lastError = "out of memory";
        return CC_OUT_OF_MEMORY;
    } catch (...) {
        w->lastError = "internal error";
        return CC_INVALID_OPERATION;
    }
}

} // extern "C"
