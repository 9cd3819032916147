#pragma once

#include <cstddef>
#include <cstring>
#include <type_traits>
#include <utility>

#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"

/// The C structs field by field next to the C++ ones: one list per struct serves both directions
/// (X(c_field, cppField)), and a compile-time check below fails when either struct has a field its
/// list does not name, so the C API cannot fall behind the C++ one.
#define CC_WORLD_FIELDS(X)                                                                         \
    X(max_threads, maxThreads)                                                                     \
    X(frame_budget_ms, frameBudgetMs) X(budget_threads, budgetThreads)                             \
        X(pixel_tolerance, pixelTolerance) X(fixed_cost_model, fixedCostModel) X(gravity, gravity) \
            X(task_runner, taskRunner) X(task_runner_user_data, taskRunnerUserData)                \
                X(max_update_interval, maxUpdateInterval) X(substeps, substeps)                    \
                    X(solver_iterations, solverIterations) X(batch_size, batchSize)                \
                        X(strain_limit, strainLimit) X(self_collision, selfCollision)              \
                            X(spend_slack, spendSlack)
#define CC_ASSET_FIELDS(X)                                                                         \
    X(kind, kind)                                                                                  \
    X(cut, cut) X(width, width) X(length, length) X(cell_size, cellSize)                           \
        X(level_count, levelCount) X(render_level, renderLevel) X(areal_density, arealDensity)     \
            X(stretch_stiffness, stretchStiffness) X(shear_stiffness, shearStiffness)              \
                X(bend_stiffness, bendStiffness) X(damping, damping) X(thickness, thickness)       \
                    X(friction, friction) X(fold_radius, foldRadius)                               \
                        X(relative_length, relativeLength) X(hem_width, hemWidth) X(ease, ease)     \
                            X(velocity_damping, velocityDamping)                               \
                                X(compression_stiffness, compressionStiffness)
#define CC_MANNEQUIN_FIELDS(X)                                                                     \
    X(height, height)                                                                              \
    X(shoulder_width, shoulderWidth) X(hip_width, hipWidth) X(waist_width, waistWidth)             \
        X(limb_girth, limbGirth)
#define CC_BODY_FIELDS(X) X(height, height)
#define CC_LANDMARK_FIELDS(X)                                                                      \
    X(forward, forward)                                                                            \
    X(neck_y, neckY)                                                                               \
    X(shoulder_y, shoulderY) X(chest_y, chestY) X(waist_y, waistY) X(hip_y, hipY)                  \
        X(neck_girth, neckGirth) X(chest_girth, chestGirth) X(waist_girth, waistGirth)             \
            X(hip_girth, hipGirth) X(shoulder_width, shoulderWidth) X(stride, stride)
#define CC_CHARACTER_FIELDS(X)                                                                     \
    X(body, body)                                                                                  \
    X(clip, clip) X(clip_index, clipIndex) X(clip_time, clipTime) X(clip_phase, clipPhase)         \
        X(playback_rate, playbackRate) X(position, position) X(yaw, yaw)
#define CC_GARMENT_FIELDS(X) X(importance, importance) X(force_level, forceLevel) X(inertia_scale, inertiaScale)
#define CC_CAMERA_FIELDS(X)                                                                        \
    X(view_projection, viewProjection)                                                             \
    X(viewport_width, viewportWidth) X(viewport_height, viewportHeight)
#define CC_RENDER_MESH_FIELDS(X)                                                                   \
    X(positions, positions)                                                                        \
    X(normals, normals) X(vertex_count, vertexCount) X(indices, indices)                           \
        X(triangle_count, triangleCount)
#define CC_GARMENT_STATS_FIELDS(X)                                                                 \
    X(level, level)                                                                                \
    X(vertex_count, vertexCount) X(solver, solver) X(substeps, substeps) X(iterations, iterations) \
        X(update_interval, updateInterval) X(updated, updated) X(level_switched, levelSwitched)    \
            X(collision, collision) X(self_collision, selfCollision) X(contacts, contacts)         \
                X(fail_safes, failSafes) X(failed, failed) X(screen_radius_px, screenRadiusPx)     \
                    X(predicted_error_px, predictedErrorPx) X(predicted_ms, predictedMs)           \
                        X(measured_ms, measuredMs) X(collision_ms, collisionMs)                    \
                            X(max_strain, maxStrain) X(max_attachment_error, maxAttachmentError)      \
                                X(self_collision_ms, selfCollisionMs) X(restarted, restarted)
#define CC_SHADOW_RESULT_FIELDS(X)                                                                 \
    X(garment, garment)                                                                            \
    X(level, level) X(reference_level, referenceLevel) X(update_interval, updateInterval)          \
        X(screen_radius_px, screenRadiusPx) X(predicted_error_px, predictedErrorPx)                \
            X(measured_error_px, measuredErrorPx) X(measured_rms_metres, measuredRmsMetres)        \
                X(measured_max_metres, measuredMaxMetres) X(reference_check_px, referenceCheckPx)  \
                    X(measured_rms_px, measuredRmsPx) X(reference_check_rms_px, referenceCheckRmsPx)
#define CC_FRAME_STATS_FIELDS(X)                                                                   \
    X(frame, frame)                                                                                \
    X(schedule_ms, scheduleMs) X(simulate_ms, simulateMs) X(total_ms, totalMs)                     \
        X(predicted_cpu_ms, predictedCpuMs) X(measured_cpu_ms, measuredCpuMs)                      \
            X(budget_cpu_ms, budgetCpuMs) X(garments, garments) X(updated, updated)                \
                X(asleep, asleep) X(visible, visible) X(failed, failed)                            \
                    X(level_switches, levelSwitches) X(batches, batches)                           \
                        X(garments_per_level, garmentsPerLevel) X(threads, threads)

namespace cc::detail {

/// One field from the other API: C flags (int32_t) and codes (uint32_t) to C++ bools and enums
/// and back, arrays element by element.
template <typename To, typename From>
void copyField(To& to, const From& from) {
    if constexpr (std::is_enum_v<From>) {
        // A C enum field may hold any int (C allows it); read as a C++ enum, a value outside its
        // enumerators is undefined. Its bytes are read as the underlying integer instead, and the
        // World's validation refuses what names no enumerator.
        std::underlying_type_t<From> raw;
        std::memcpy(&raw, &from, sizeof raw);
        to = static_cast<To>(raw);
    } else {
        to = static_cast<To>(from);
    }
}
template <typename To, typename From, std::size_t N>
void copyField(To (&to)[N], const From (&from)[N]) {
    for (std::size_t k = 0; k < N; ++k) copyField(to[k], from[k]);
}

/// Converts to any field type: counts the initialiser slots of an aggregate.
struct AnyField {
    template <typename T>
    constexpr operator T() const noexcept;
};

// The probe braces a partial list on purpose: clang warns of the missing braces and fields anyway.
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wmissing-braces"
#pragma clang diagnostic ignored "-Wmissing-field-initializers"
#endif
template <typename T, typename... Slots>
constexpr auto acceptsSlots(int) -> decltype(T{std::declval<Slots>()...}, true) {
    return true;
}
#if defined(__clang__)
#pragma clang diagnostic pop
#endif
template <typename T, typename... Slots>
constexpr bool acceptsSlots(...) {
    return false;
}

/// Initialiser slots of an aggregate (an array member counts its elements, a struct member one).
template <typename T, typename... Slots>
constexpr std::size_t aggregateSlots() {
    if constexpr (acceptsSlots<T, Slots..., AnyField>(0)) {
        return aggregateSlots<T, Slots..., AnyField>();
    } else {
        return sizeof...(Slots);
    }
}

/// Slots of one listed field.
template <typename T>
constexpr std::size_t fieldSlots() {
    if constexpr (std::is_array_v<T>) {
        return std::extent_v<T> * fieldSlots<std::remove_extent_t<T>>();
    } else {
        return 1;
    }
}

} // namespace cc::detail

#define CC_C_SLOTS(c, cpp) +cc::detail::fieldSlots<decltype(CStruct::c)>()
#define CC_CPP_SLOTS(c, cpp) +cc::detail::fieldSlots<decltype(CppStruct::cpp)>()
/// Fails to compile when the C or the C++ struct has a field the list does not name; `stamp` is 1
/// for the C descs (their version field), 0 for the structs the library fills in.
#define CC_CHECK_FIELDS(name, LIST, C, Cpp, stamp)                                                 \
    namespace cc::detail::fields_##name {                                                          \
        using CStruct = C;                                                                         \
        using CppStruct = Cpp;                                                                     \
        static_assert(aggregateSlots<CppStruct>() == 0 LIST(CC_CPP_SLOTS),                         \
                      #Cpp " has a field that " #LIST " (engine/src/CApiFields.h) does not list"); \
        static_assert(aggregateSlots<CStruct>() == (stamp)LIST(CC_C_SLOTS),                        \
                      #C " has a field that " #LIST " (engine/src/CApiFields.h) does not list");   \
    }
