#include "crowdcloth/crowdcloth_import.h"

#include <new>
#include <string>

#include "CApiFields.h"
#include "CApiWorld.h"
#include "crowdcloth/import/CharacterIO.h"

/// cc_import_settings next to cc::ImportSettings (see engine/src/CApiFields.h).
#define CC_IMPORT_SETTINGS_FIELDS(X)                                                               \
    X(join_identical_vertices, joinIdenticalVertices)                                              \
    X(weight_sum_tolerance, weightSumTolerance) X(unit_scale, unitScale) X(up_axis, upAxis)        \
    X(ticks_per_second, ticksPerSecond) X(isolate, isolate) X(timeout_seconds, timeoutSeconds)     \
    X(max_file_bytes, maxFileBytes) X(max_memory_bytes, maxMemoryBytes)
CC_CHECK_FIELDS(import_settings, CC_IMPORT_SETTINGS_FIELDS, cc_import_settings, cc::ImportSettings, 1)
#define CC_TO_C(c, cpp) cc::detail::copyField(d->c, x.cpp);
#define CC_TO_CPP(c, cpp) cc::detail::copyField(x.cpp, d->c);
#define CC_BODY_TO_CPP(c, cpp) cc::detail::copyField(desc.cpp, bd->c);

extern "C" {

void cc_import_settings_init(cc_import_settings* d) {
    if (!d) return;
    const cc::ImportSettings x{};
    d->version = CC_DESC_VERSION;
    CC_IMPORT_SETTINGS_FIELDS(CC_TO_C)
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
            cc::ImportSettings& x = settings;
            CC_IMPORT_SETTINGS_FIELDS(CC_TO_CPP)
        }
        auto character = cc::importCharacter(path, settings);
        if (!character.isOk()) return cc::detail::reportToC(w, character.status());
        cc::BodyDesc desc;
        if (bd) CC_BODY_FIELDS(CC_BODY_TO_CPP)
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
