#include "crowdcloth/lod/CrowdScheduler.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace cc::lod {
namespace {

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

std::string where(const char* what, std::size_t index) {
    return std::string(what) + " " + std::to_string(index);
}

Status validateInputs(std::vector<uint64_t>& ids, const SchedulerSettings& settings, Span<const SchedulerCamera> cameras,
                      Span<const GarmentProfile> profiles, Span<const GarmentRequest> requests,
                      Span<GarmentSchedule> outSchedules) {
    if (Status s = settings.validate(); !s) return s;
    for (std::size_t c = 0; c < cameras.size(); ++c) {
        const SchedulerCamera& camera = cameras[c];
        if (!camera.viewProjection.allFinite())
            return Status::invalidArgument(where("camera", c) + ": viewProjection is not finite");
        if (!finitePositive(camera.viewportWidth) || !finitePositive(camera.viewportHeight))
            return Status::invalidArgument(where("camera", c) + ": viewport must be > 0 pixels");
    }
    for (std::size_t p = 0; p < profiles.size(); ++p) {
        if (profiles[p].levels.empty())
            return Status::invalidArgument(where("profile", p) + " has no levels");
        for (std::size_t l = 0; l < profiles[p].levels.size(); ++l) {
            const LevelProfile& level = profiles[p].levels[l];
            auto at = [&] { return where("profile", p) + " " + where("level", l); };  // on error only
            if (!std::isfinite(level.errorMetres) || level.errorMetres < 0.0)
                return Status::invalidArgument(at() + ": errorMetres must be finite and >= 0");
            for (double e : level.errorPerRadius)
                if (!std::isfinite(e) || e < 0.0)
                    return Status::invalidArgument(at() + ": errorPerRadius must be finite and >= 0");
            if (!std::isfinite(level.errorSpeeds[0]) || !std::isfinite(level.errorSpeeds[1]) ||
                !(level.errorSpeeds[1] > level.errorSpeeds[0]))
                return Status::invalidArgument(at() + ": errorSpeeds must be finite and ascending");
            for (double cost : level.collisionCostMs)
                if (!std::isfinite(cost) || cost < 0.0)
                    return Status::invalidArgument(at() + ": collisionCostMs must be finite and >= 0");
            if (!std::isfinite(level.selfCollisionCostMs) || level.selfCollisionCostMs < 0.0)
                return Status::invalidArgument(at() + ": selfCollisionCostMs must be finite and >= 0");
            bool offered = false;
            for (double cost : level.costMs) {
                if (!std::isfinite(cost))
                    return Status::invalidArgument(at() + ": costMs is not finite");
                offered = offered || cost > 0.0;
            }
            if (!offered) return Status::invalidArgument(at() + " offers no solver (all costMs <= 0)");
            if (level.substeps < 1 || level.iterations < 1)
                return Status::invalidArgument(at() + ": substeps and iterations must be >= 1");
        }
    }
    if (outSchedules.size() != requests.size())
        return Status::invalidArgument("scheduleGarments: outSchedules holds " +
                                       std::to_string(outSchedules.size()) + " entries for " +
                                       std::to_string(requests.size()) + " requests");
    ids.clear();
    for (std::size_t i = 0; i < requests.size(); ++i) {
        const GarmentRequest& r = requests[i];
        auto at = [&] { return "garment " + std::to_string(r.id); };  // on error only
        if (r.profile >= profiles.size())
            return Status::invalidArgument(at() + ": profile " + std::to_string(r.profile) +
                                           " out of range (" + std::to_string(profiles.size()) + ")");
        if (!isFinite(r.center)) return Status::invalidArgument(at() + ": center is not finite");
        if (!finitePositive(r.radius)) return Status::invalidArgument(at() + ": radius must be > 0");
        if (!std::isfinite(r.speed) || r.speed < 0.0)
            return Status::invalidArgument(at() + ": speed must be finite and >= 0");
        if (!finitePositive(r.importance))
            return Status::invalidArgument(at() + ": importance must be > 0");
        ids.push_back(r.id);
    }
    std::sort(ids.begin(), ids.end());
    if (auto dup = std::adjacent_find(ids.begin(), ids.end()); dup != ids.end())
        return Status::invalidArgument("garment id " + std::to_string(*dup) + " appears twice");
    return Status::ok();
}

bool atLeast(double value, double threshold, bool wasAbove, double hysteresis) {
    return value >= (wasAbove ? threshold * (1.0 - hysteresis) : threshold);
}

/// The two halves of wantsSelfCollision's rule: seen at least selfCollisionRadiusPx large (with
/// hysteresis against last frame's answer), at one of the finest two levels.
bool largeForSelfCollision(bool visible, double screenRadiusPx, bool wasOn, const SchedulerSettings& s) {
    return visible && atLeast(screenRadiusPx, s.selfCollisionRadiusPx, wasOn, s.hysteresis);
}
bool selfCollisionLevel(int level, int levelCount) { return level >= levelCount - 2; }

/// The decision variables of one garment while the budget is balanced.
struct Choice {
    int level = 0;
    int interval = 1;
};

/// Everything about one garment that does not change while the budget is balanced.
struct GarmentView {
    const GarmentRequest* request = nullptr;
    const GarmentProfile* profile = nullptr;
    bool visible = false;
    bool asleep = false;             ///< unseen and at rest: costs nothing, never changes
    double pixelsPerMetre = 0.0;
    double lagMetresPerFrame2 = 0.0; ///< [m] lag of one extrapolated frame, times frames^2
    CollisionDetail collision = CollisionDetail::None;
    bool largeForSelfCollision = false;  ///< seen at least selfCollisionRadiusPx large (hysteresis)
    Choice choice;

    int levelCount() const { return static_cast<int>(profile->levels.size()); }
    double stepCost(int level) const {
        const LevelProfile& l = profile->levels[level];
        double best = 0.0;
        for (double cost : l.costMs)
            if (cost > 0.0 && (best == 0.0 || cost < best)) best = cost;
        const bool self = largeForSelfCollision && selfCollisionLevel(level, levelCount());
        return best + l.collisionCostMs[static_cast<int>(collision)] + (self ? l.selfCollisionCostMs : 0.0);
    }
    double cost(const Choice& c) const { return asleep ? 0.0 : stepCost(c.level) / c.interval; }
    double levelErrorPx(int level) const {
        const LevelProfile& l = profile->levels[level];
        const double t = std::clamp((request->speed - l.errorSpeeds[0]) / (l.errorSpeeds[1] - l.errorSpeeds[0]), 0.0, 1.0);
        const double perRadius = (1.0 - t) * l.errorPerRadius[0] + t * l.errorPerRadius[1];
        return (l.errorMetres + perRadius * request->radius) * pixelsPerMetre;
    }
    double lagErrorPx(int interval) const {
        const double frames = interval - 1;
        return lagMetresPerFrame2 * frames * frames * pixelsPerMetre;
    }
    double errorPx(const Choice& c) const {
        return visible ? std::max(levelErrorPx(c.level), lagErrorPx(c.interval)) : 0.0;
    }
};

/// Coarsest level (lowest index) whose error is within `limitPx`; the finest if none is.
int coarsestLevelWithin(const GarmentView& g, double limitPx) {
    for (int l = 0; l < g.levelCount(); ++l)
        if (g.levelErrorPx(l) <= limitPx) return l;
    return g.levelCount() - 1;
}

/// Longest interval (power of two) whose lag is within `limitPx`.
int longestIntervalWithin(const GarmentView& g, double limitPx, int maxInterval) {
    int interval = 1;
    while (interval * 2 <= maxInterval && g.lagErrorPx(interval * 2) <= limitPx) interval *= 2;
    return interval;
}

Choice toleranceChoice(const GarmentView& g, const SchedulerSettings& s) {
    const GarmentSchedule& prev = g.request->previous;
    if (!g.visible) return {0, s.maxUpdateInterval};
    const double tol = s.pixelTolerance;
    const double strict = s.pixelTolerance * (1.0 - s.hysteresis);
    // Where no level is within the tolerance, the least error any level offers is the target:
    // the coarsest level that offers it, not the finest (measured errors level off: refining
    // past that buys nothing on screen). With the formula the finest level errs 0, so this is
    // the tolerance itself.
    double best = g.levelErrorPx(0);
    for (int l = 1; l < g.levelCount(); ++l) best = std::min(best, g.levelErrorPx(l));
    const double reachable = best * (1.0 + 1e-9);  // levels pooled to one error differ by rounding
    Choice c;
    // Finer (higher level) at once when the tolerance needs it; coarser only once the coarser
    // setting is clearly inside it.
    c.level = coarsestLevelWithin(g, std::max(tol, reachable));
    if (prev.level > c.level && prev.level < g.levelCount())
        c.level = std::min(prev.level, coarsestLevelWithin(g, std::max(strict, reachable)));
    c.interval = longestIntervalWithin(g, tol, s.maxUpdateInterval);
    if (prev.updateInterval >= 1 && prev.updateInterval < c.interval)
        c.interval = std::max(prev.updateInterval, longestIntervalWithin(g, strict, s.maxUpdateInterval));
    return c;
}

/// Asleep: none; unseen or small on screen: the capsules; large: the body mesh, with continuous
/// tests when the body moves fast (with hysteresis on the size, as the levels have).
CollisionDetail collisionFor(const GarmentView& g, const SchedulerSettings& s) {
    if (g.asleep) return CollisionDetail::None;
    const GarmentRequest& r = *g.request;
    const bool wasMesh = r.previous.collision >= CollisionDetail::Mesh;
    if (g.visible && atLeast(r.radius * g.pixelsPerMetre, s.meshCollisionRadiusPx, wasMesh, s.hysteresis))
        return r.speed >= s.continuousSpeed ? CollisionDetail::MeshContinuous : CollisionDetail::Mesh;
    return CollisionDetail::Proxies;
}

/// With slack spent, a seen garment starts from last frame's choice where that was finer than the
/// tolerance needs: the budget then moves garments only when the total leaves the band between
/// budget * (1 - slackHeadroom) and the budget. Rebuilt from the tolerance every frame instead, the
/// refined set followed every wobble of the costs and the budget: 17 % of a 1000-garment crowd's
/// updates switched level, half of them back and forth.
void keepSpentSlack(GarmentView& g) {
    const GarmentSchedule& prev = g.request->previous;
    if (!g.visible || prev.level < 0 || prev.level >= g.levelCount() || prev.updateInterval < 1) return;
    g.choice.level = std::max(g.choice.level, prev.level);
    g.choice.interval = std::min(g.choice.interval, prev.updateInterval);
}

/// A candidate change of one garment's choice, ranked by weighted error per millisecond.
struct Move {
    double ratio = 0.0;
    uint64_t id = 0;
    std::size_t garment = 0;
    int version = 0;
    Choice to;
};

/// Degrading: the smallest error added per millisecond saved comes first; then the lower id.
struct CheapestLoss {
    bool operator()(const Move& a, const Move& b) const {
        if (a.ratio != b.ratio) return a.ratio > b.ratio;
        return a.id > b.id;
    }
};
/// Refining: the largest error removed per millisecond spent comes first; then the lower id.
struct LargestGain {
    bool operator()(const Move& a, const Move& b) const {
        if (a.ratio != b.ratio) return a.ratio < b.ratio;
        return a.id > b.id;
    }
};

bool bestDegrade(const GarmentView& g, std::size_t index, int version, int maxInterval, Move& out) {
    const Choice now = g.choice;
    Choice options[2] = {{now.level - 1, now.interval}, {now.level, now.interval * 2}};
    bool found = false;
    for (const Choice& to : options) {
        if (to.level < 0 || to.interval > maxInterval) continue;
        const double saved = g.cost(now) - g.cost(to);
        if (saved <= 0.0) continue;
        const double ratio = g.request->importance * (g.errorPx(to) - g.errorPx(now)) / saved;
        if (!found || ratio < out.ratio) out = {ratio, g.request->id, index, version, to};
        found = true;
    }
    return found;
}

bool bestRefine(const GarmentView& g, std::size_t index, int version, Move& out) {
    const Choice now = g.choice;
    Choice options[2] = {{now.level + 1, now.interval}, {now.level, now.interval / 2}};
    bool found = false;
    for (const Choice& to : options) {
        if (to.level >= g.levelCount() || to.interval < 1) continue;
        const double spent = g.cost(to) - g.cost(now);
        const double gained = g.errorPx(now) - g.errorPx(to);
        if (spent <= 0.0 || gained <= 0.0) continue;
        const double ratio = g.request->importance * gained / spent;
        if (!found || ratio > out.ratio) out = {ratio, g.request->id, index, version, to};
        found = true;
    }
    return found;
}

double totalCost(const std::vector<GarmentView>& garments) {
    double total = 0.0; // summed in id order: the same total for any input order
    for (const GarmentView& g : garments) total += g.cost(g.choice);
    return total;
}

/// A priority queue on a kept vector (std::priority_queue cannot lend its storage back).
template <typename Order>
struct MoveQueue {
    std::vector<Move>& heap;
    Order order;
    bool empty() const { return heap.empty(); }
    const Move& top() const { return heap.front(); }
    void push(const Move& m) {
        heap.push_back(m);
        std::push_heap(heap.begin(), heap.end(), order);
    }
    void pop() {
        std::pop_heap(heap.begin(), heap.end(), order);
        heap.pop_back();
    }
};

} // namespace

bool wantsSelfCollision(const GarmentSchedule& schedule, int level, int levelCount, bool wasOn,
                        const SchedulerSettings& settings) {
    return largeForSelfCollision(schedule.visible, schedule.screenRadiusPx, wasOn, settings) &&
           selfCollisionLevel(level, levelCount);
}

struct SchedulerWorkspace::Buffers {
    std::vector<uint64_t> ids;
    std::vector<std::size_t> byId;
    std::vector<GarmentView> garments;
    std::vector<int> versions;
    std::vector<Move> heap;
    std::vector<double> nearW;  ///< per camera: clip w on its near plane (nearPlaneW)
};

SchedulerWorkspace::SchedulerWorkspace() : mBuffers(std::make_unique<Buffers>()) {}
SchedulerWorkspace::~SchedulerWorkspace() = default;
SchedulerWorkspace::SchedulerWorkspace(SchedulerWorkspace&&) noexcept = default;
SchedulerWorkspace& SchedulerWorkspace::operator=(SchedulerWorkspace&&) noexcept = default;

namespace {

void degradeToBudget(std::vector<GarmentView>& garments, const SchedulerSettings& s, SchedulerWorkspace::Buffers& w) {
    double total = totalCost(garments);
    if (total <= s.budgetMs) return;
    std::vector<int>& versions = w.versions;
    versions.assign(garments.size(), 0);
    w.heap.clear();
    MoveQueue<CheapestLoss> queue{w.heap, {}};
    for (std::size_t i = 0; i < garments.size(); ++i) {
        Move m;
        if (bestDegrade(garments[i], i, 0, s.maxUpdateInterval, m)) queue.push(m);
    }
    while (total > s.budgetMs && !queue.empty()) {
        const Move m = queue.top();
        queue.pop();
        if (m.version != versions[m.garment]) continue;
        GarmentView& g = garments[m.garment];
        total -= g.cost(g.choice) - g.cost(m.to);
        g.choice = m.to;
        Move next;
        if (bestDegrade(g, m.garment, ++versions[m.garment], s.maxUpdateInterval, next)) queue.push(next);
    }
}

void refineWithSlack(std::vector<GarmentView>& garments, const SchedulerSettings& s, SchedulerWorkspace::Buffers& w) {
    const double ceiling = s.budgetMs * (1.0 - s.slackHeadroom);
    double total = totalCost(garments);
    if (total >= ceiling) return;
    std::vector<int>& versions = w.versions;
    versions.assign(garments.size(), 0);
    w.heap.clear();
    MoveQueue<LargestGain> queue{w.heap, {}};
    for (std::size_t i = 0; i < garments.size(); ++i) {
        Move m;
        if (bestRefine(garments[i], i, 0, m)) queue.push(m);
    }
    while (!queue.empty()) {
        const Move m = queue.top();
        queue.pop();
        if (m.version != versions[m.garment]) continue;
        GarmentView& g = garments[m.garment];
        const double spent = g.cost(m.to) - g.cost(g.choice);
        if (total + spent > ceiling) continue; // does not fit: this garment stays where it is
        total += spent;
        g.choice = m.to;
        Move next;
        if (bestRefine(g, m.garment, ++versions[m.garment], next)) queue.push(next);
    }
}

GarmentSchedule finalSchedule(const GarmentView& g, const SchedulerSettings& s) {
    const GarmentRequest& r = *g.request;
    const GarmentSchedule& prev = r.previous;
    GarmentSchedule out;
    out.visible = g.visible;
    out.screenRadiusPx = r.radius * g.pixelsPerMetre;
    out.level = g.choice.level;
    const LevelProfile& level = g.profile->levels[g.choice.level];
    int solver = -1;
    for (int k = 0; k < kSolverChoiceCount; ++k)
        if (level.costMs[k] > 0.0 && (solver < 0 || level.costMs[k] < level.costMs[solver])) solver = k;
    out.solver = static_cast<SolverChoice>(solver);
    out.substeps = level.substeps;
    out.iterations = level.iterations;

    if (g.asleep) {
        out.updateInterval = 0;
        out.collision = CollisionDetail::None;
        out.predictedCostMs = 0.0;
        return out;
    }
    out.updateInterval = g.choice.interval;
    out.predictedCostMs = g.cost(g.choice);
    out.predictedErrorPx = g.errorPx(g.choice);
    out.collision = g.collision;
    out.selfCollision = wantsSelfCollision(out, g.choice.level, g.levelCount(), prev.selfCollision, s);
    return out;
}

/// Clip w on the near plane of a perspective camera; 0 for an orthographic one (w is 1 everywhere)
/// or a matrix without a near plane. The eye is where clip x, y and w vanish; its signed distance
/// to the near plane (rows 3 + 2, Gribb & Hartmann 2001) times w's growth per metre is the answer.
double nearPlaneW(const Mat4& m) {
    Eigen::Matrix3d rows;
    rows << m.block<1, 3>(0, 0), m.block<1, 3>(1, 0), m.block<1, 3>(3, 0);
    const Eigen::Vector3d offsets(-m(0, 3), -m(1, 3), -m(3, 3));
    const double depthScale = m.row(3).head<3>().norm();
    if (depthScale == 0.0 || std::abs(rows.determinant()) < 1e-12) return 0.0;
    const Eigen::Vector3d eye = rows.partialPivLu().solve(offsets);
    const Eigen::Vector4d nearPlane = m.row(3).transpose() + m.row(2).transpose();
    const double normal = nearPlane.head<3>().norm();
    if (normal == 0.0) return 0.0;
    const double eyeToNear = -(nearPlane.head<3>().dot(eye) + nearPlane(3)) / normal;
    return std::isfinite(eyeToNear) && eyeToNear > 0.0 ? eyeToNear * depthScale : 0.0;
}

} // namespace

Status SchedulerSettings::validate() const {
    if (!finitePositive(budgetMs)) return Status::invalidArgument("SchedulerSettings.budgetMs must be > 0");
    if (!finitePositive(pixelTolerance))
        return Status::invalidArgument("SchedulerSettings.pixelTolerance must be > 0");
    if (!(hysteresis >= 0.0 && hysteresis < 1.0))
        return Status::invalidArgument("SchedulerSettings.hysteresis must be in [0, 1)");
    if (!(slackHeadroom >= 0.0 && slackHeadroom < 1.0))
        return Status::invalidArgument("SchedulerSettings.slackHeadroom must be in [0, 1)");
    if (!finitePositive(frameDt)) return Status::invalidArgument("SchedulerSettings.frameDt must be > 0");
    if (!std::isfinite(typicalAcceleration) || typicalAcceleration < 0.0)
        return Status::invalidArgument("SchedulerSettings.typicalAcceleration must be finite and >= 0");
    if (maxUpdateInterval < 1 || maxUpdateInterval > 64 || (maxUpdateInterval & (maxUpdateInterval - 1)) != 0)
        return Status::invalidArgument("SchedulerSettings.maxUpdateInterval must be a power of two in [1, 64]");
    if (!std::isfinite(meshCollisionRadiusPx) || meshCollisionRadiusPx < 0.0)
        return Status::invalidArgument("SchedulerSettings.meshCollisionRadiusPx must be finite and >= 0");
    if (!std::isfinite(continuousSpeed) || continuousSpeed < 0.0)
        return Status::invalidArgument("SchedulerSettings.continuousSpeed must be finite and >= 0");
    if (!std::isfinite(selfCollisionRadiusPx) || selfCollisionRadiusPx < 0.0)
        return Status::invalidArgument("SchedulerSettings.selfCollisionRadiusPx must be finite and >= 0");
    return Status::ok();
}

namespace {

/// projectSphere with the camera's near-plane w already found (once per camera and frame).
ScreenProjection projectSphereNear(const SchedulerCamera& camera, double nearW, const Vec3& center, double radius) {
    // Frustum planes from the rows of the view-projection matrix (Gribb & Hartmann 2001).
    const Mat4& m = camera.viewProjection;
    const Eigen::Vector4d p(center.x(), center.y(), center.z(), 1.0);
    ScreenProjection out;
    out.visible = true;
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {1.0, -1.0}) {
            const Eigen::Vector4d plane = m.row(3).transpose() + sign * m.row(axis).transpose();
            const double norm = plane.head<3>().norm();
            if (norm == 0.0) continue;
            if (plane.dot(p) / norm < -radius) out.visible = false;
        }
    }
    // Clip w is the view depth for a perspective camera (and 1 for an orthographic one); the
    // nearest point of the sphere sets the largest scale, so the estimate errs on the fine side.
    // Nothing nearer than the near plane is drawn, so a sphere around the eye (a close-up, the
    // camera inside a skirt) is seen at most at the near plane's scale, not at a vanishing depth.
    const double depthScale = m.row(3).head<3>().norm();
    const double nearest = m.row(3).dot(p) - radius * depthScale;
    const double w = std::max(nearest, std::max(nearW, 1e-3 * std::max(depthScale, 1e-9)));
    out.pixelsPerMetre = m.row(1).head<3>().norm() / w * 0.5 * camera.viewportHeight;
    return out;
}

} // namespace

ScreenProjection projectSphere(const SchedulerCamera& camera, const Vec3& center, double radius) {
    return projectSphereNear(camera, nearPlaneW(camera.viewProjection), center, radius);
}

Status scheduleGarments(const SchedulerSettings& settings, Span<const SchedulerCamera> cameras,
                        Span<const GarmentProfile> profiles, Span<const GarmentRequest> requests,
                        Span<GarmentSchedule> outSchedules) {
    SchedulerWorkspace work;
    return scheduleGarments(settings, cameras, profiles, requests, outSchedules, work);
}

Status scheduleGarments(const SchedulerSettings& settings, Span<const SchedulerCamera> cameras,
                        Span<const GarmentProfile> profiles, Span<const GarmentRequest> requests,
                        Span<GarmentSchedule> outSchedules, SchedulerWorkspace& work) {
    SchedulerWorkspace::Buffers& w = *work.mBuffers;
    if (Status s = validateInputs(w.ids, settings, cameras, profiles, requests, outSchedules); !s) return s;

    std::vector<std::size_t>& byId = w.byId;
    byId.resize(requests.size());
    for (std::size_t i = 0; i < byId.size(); ++i) byId[i] = i;
    std::sort(byId.begin(), byId.end(),
              [&](std::size_t a, std::size_t b) { return requests[a].id < requests[b].id; });

    w.nearW.clear();
    for (const SchedulerCamera& camera : cameras) w.nearW.push_back(nearPlaneW(camera.viewProjection));
    std::vector<GarmentView>& garments = w.garments;
    garments.assign(requests.size(), GarmentView{});
    for (std::size_t k = 0; k < byId.size(); ++k) {
        const GarmentRequest& r = requests[byId[k]];
        GarmentView& g = garments[k];
        g.request = &r;
        g.profile = &profiles[r.profile];
        for (std::size_t c = 0; c < cameras.size(); ++c) {
            const ScreenProjection p = projectSphereNear(cameras[c], w.nearW[c], r.center, r.radius);
            if (!p.visible) continue;
            g.visible = true;
            g.pixelsPerMetre = std::max(g.pixelsPerMetre, p.pixelsPerMetre);
        }
        // Extrapolating a garment over n - 1 frames lags by a t^2 / 2 with a ~ speed-driven
        // acceleration of the cloth (limbs swinging at the gait frequency).
        g.asleep = !g.visible && r.atRest;
        g.lagMetresPerFrame2 = 0.5 * settings.typicalAcceleration * r.speed * settings.frameDt * settings.frameDt;
        g.collision = collisionFor(g, settings);
        g.largeForSelfCollision =
            largeForSelfCollision(g.visible, r.radius * g.pixelsPerMetre, r.previous.selfCollision, settings);
        g.choice = toleranceChoice(g, settings);
        if (settings.refineWithSlack) keepSpentSlack(g);
    }
    degradeToBudget(garments, settings, w);
    if (settings.refineWithSlack) refineWithSlack(garments, settings, w);
    for (std::size_t k = 0; k < byId.size(); ++k) outSchedules[byId[k]] = finalSchedule(garments[k], settings);
    return Status::ok();
}

} // namespace cc::lod
