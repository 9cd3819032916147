#include "crowdcloth/cloth/SubstepSolver.h"

#include <cmath>
#include <cstring>
#include <string>

// The kernels index disjoint rows of one array through several pointers; telling the compiler so
// lets it vectorise across lanes.
#define CC_RESTRICT __restrict__

namespace cc::cloth {

Status SubstepSettings::validate() const {
    if (substeps < 1 || substeps > 4096)
        return Status::invalidArgument("SubstepSettings.substeps = " + std::to_string(substeps) + " is outside [1, 4096]");
    if (!(strainLimit >= 0.0 && strainLimit <= 10.0))
        return Status::invalidArgument("SubstepSettings.strainLimit = " + std::to_string(strainLimit) +
                                       " is outside [0, 10]");
    if (method != SubstepMethod::Newton && method != SubstepMethod::LocalGlobal)
        return Status::invalidArgument("SubstepSettings.method is unknown");
    if (iterations < 1 || iterations > 1000)
        return Status::invalidArgument("SubstepSettings.iterations = " + std::to_string(iterations) +
                                       " is outside [1, 1000]");
    if (strainLimitPasses < 1 || strainLimitPasses > 1000)
        return Status::invalidArgument("SubstepSettings.strainLimitPasses = " + std::to_string(strainLimitPasses) +
                                       " is outside [1, 1000]");
    if (!(contactThickness >= 0.0 && contactThickness <= 1.0))
        return Status::invalidArgument("SubstepSettings.contactThickness = " + std::to_string(contactThickness) +
                                       " m is outside [0, 1]");
    if (!(compressionStiffness >= 0.0 && compressionStiffness <= 1.0))
        return Status::invalidArgument("SubstepSettings.compressionStiffness = " + std::to_string(compressionStiffness) +
                                       " is outside [0, 1]");
    if (!(stiffnessDamping >= 0.0 && stiffnessDamping <= 10.0))
        return Status::invalidArgument("SubstepSettings.stiffnessDamping = " + std::to_string(stiffnessDamping) +
                                       " s is outside [0, 10]");
    if (Status s = friction.validate(); !s) return Status::invalidArgument("SubstepSettings." + s.message());
    return Status::ok();
}

namespace {

// How much less a vertex the body pushed this step moves in the strain limit after the push
// than its neighbours: enough that they follow it, while an edge between two pushed vertices can
// still be shortened.
constexpr double kPinnedWeight = 0.05;

bool finite3(const double* x, int stride) {
    return std::isfinite(x[0]) && std::isfinite(x[stride]) && std::isfinite(x[2 * stride]);
}

Status checkLane(const ClothLevel& level, const SubstepLane& lane, std::size_t index) {
    auto where = [&] { return "stepSubsteps: lane " + std::to_string(index); };
    if (lane.positions.size() != level.vertexCount() || lane.velocities.size() != level.vertexCount())
        return Status::invalidArgument(where() + " has " + std::to_string(lane.positions.size()) + " positions and " +
                                       std::to_string(lane.velocities.size()) + " velocities for a level of " +
                                       std::to_string(level.vertexCount()) + " vertices");
    if (lane.targets.size() != level.attachedNodeCount())
        return Status::invalidArgument(where() + " has " + std::to_string(lane.targets.size()) + " targets for " +
                                       std::to_string(level.attachedNodeCount()) + " attached nodes");
    for (const Contact& c : lane.contacts)
        if (c.vertex >= level.vertexCount())
            return Status::invalidArgument(where() + ": a contact names vertex " + std::to_string(c.vertex));
    return Status::ok();
}

/// Sizes a workspace array; new entries (and so the padding of every row) are zero, and entries
/// the kernel writes before it reads them are left as they are.
void ensureSize(std::vector<double>& a, std::size_t n) {
    if (a.size() != n) a.assign(n, 0.0);
}

// Lane arithmetic: the kernels run W instances side by side. With two or more lanes they work on
// pairs of doubles (SSE2, which every x86-64 has, through the compiler's vector extensions); one
// lane is plain double. Every lane sees the same IEEE operations in the same order either way
// (FMA contraction is off), so a lane's result does not depend on its neighbours.
typedef double Pair __attribute__((vector_size(16)));

template <int W>
struct Lanes {
    using V = Pair;
    static constexpr int kStep = 2;
};
template <>
struct Lanes<1> {
    using V = double;
    static constexpr int kStep = 1;
};

template <typename V>
inline V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <typename V>
inline void store(double* p, V v) {
    std::memcpy(p, &v, sizeof v);
}
inline double vsqrt(double x) { return std::sqrt(x); }
inline Pair vsqrt(Pair x) { return Pair{std::sqrt(x[0]), std::sqrt(x[1])}; }
inline bool laneSet(bool mask, int) { return mask; }
template <typename M>
inline bool laneSet(const M& mask, int j) {
    return mask[j] != 0;
}

/// First non-finite input of a lane, described, or empty.
std::string nonFiniteInput(const SubstepLane& lane) {
    for (std::size_t v = 0; v < lane.positions.size(); ++v)
        if (!isFinite(lane.positions[v]) || !isFinite(lane.velocities[v]))
            return "vertex " + std::to_string(v) + " has a non-finite position or velocity";
    for (std::size_t t = 0; t < lane.targets.size(); ++t)
        if (!isFinite(lane.targets[t])) return "attached node " + std::to_string(t) + " has a non-finite target";
    for (const Contact& c : lane.contacts)
        if (!isFinite(c.point) || !isFinite(c.normal) || !isFinite(c.surfaceVelocity))
            return "the contact of vertex " + std::to_string(c.vertex) + " is not finite";
    if (!isFinite(lane.acceleration)) return "the acceleration is not finite";
    if (!isFinite(lane.frameAngularVelocity) || !isFinite(lane.frameAngularAcceleration) ||
        !(lane.fictitiousScale >= 0.0 && lane.fictitiousScale <= 10.0))
        return "the frame's rotation is not finite (or its scale is outside [0, 10])";
    if (!(lane.velocityDamping >= 0.0 && std::isfinite(lane.velocityDamping)))
        return "the velocity damping is negative or not finite";
    return {};
}

/// The solver for W lanes; arrays are [node][coordinate][lane].
template <int W>
class Kernel {
public:
    Kernel(const ClothLevel& level, const SubstepFactor* factor, double dt, const SubstepSettings& settings,
           SubstepWorkspace& w)
        : mLevel(level), mFactor(factor), mDt(dt), mSettings(settings), mW(w) {}

    // Only the strain limit, with the flagged vertices (and their nodes) held in place.
    int limitOnly(const SubstepLane& lane, Span<const uint8_t> fixedVertices) {
        static_assert(W == 1, "one lane");
        gather(Span<const SubstepLane>(&lane, 1));
        for (std::size_t v = 0; v < fixedVertices.size(); ++v)
            if (fixedVertices[v]) mW.fixedNodes[mLevel.nodeOfVertex()[v]] = 1;
        int passes[W] = {};
        limitStrain(passes);
        if (finiteLane(0)) scatter(0, lane);
        return passes[0];
    }

    void run(Span<const SubstepLane> lanes, Span<SubstepLaneReport> reports) {
        gather(lanes);
        const int n = mSettings.substeps;
        for (int s = 0; s < n; ++s) substep(s, n);
        int passes[W] = {};
        if (mSettings.strainLimit > 0.0) limitStrain(passes);
        for (std::size_t l = 0; l < lanes.size(); ++l) {
            reports[l].strainLimitPasses = passes[l];
            reports[l].contactCorrections = mCorrections[l];
            if (!reports[l].status) continue;  // a non-finite input: keep the state
            if (!finiteLane(int(l))) {
                reports[l].status = Status::error(StatusCode::NumericalFailure,
                                                  "stepSubsteps: the step produced a non-finite state; it was undone");
                continue;
            }
            scatter(int(l), lanes[l]);
        }
    }

private:
    // Rows hold x, y, z of every lane ([coordinate][lane]), padded to the factor's SIMD pairs.
    static constexpr int kRow = W == 1 ? 4 : W == 2 ? 8 : 3 * W;
    double& at(std::vector<double>& a, uint32_t node, int c, int lane) const {
        return a[std::size_t(node) * kRow + c * W + lane];
    }

    void gather(Span<const SubstepLane> lanes) {
        const uint32_t nodes = mLevel.nodeCount();
        const uint32_t attached = mLevel.attachedNodeCount();
        // Every entry but the padding is written before it is read; the padding stays zero.
        for (auto* a : {&mW.positions, &mW.velocities, &mW.previous, &mW.predicted, &mW.solution})
            ensureSize(*a, std::size_t(nodes) * kRow);
        ensureSize(mW.attachedStart, std::size_t(attached) * kRow);
        ensureSize(mW.attachedEnd, std::size_t(attached) * kRow);
        mW.fixedNodes.assign(std::size_t(nodes) * W, 0);
        const auto& vertexOfNode = mLevel.vertexOfNode();
        const uint32_t free = mLevel.freeNodeCount();
        for (int l = 0; l < W; ++l) {
            // Lanes past the batch repeat lane 0: their results are thrown away.
            const SubstepLane& lane = lanes[std::size_t(l) < lanes.size() ? std::size_t(l) : 0];
            for (uint32_t k = 0; k < nodes; ++k) {
                const Vec3& x = lane.positions[vertexOfNode[k]];
                const Vec3& v = lane.velocities[vertexOfNode[k]];
                for (int c = 0; c < 3; ++c) at(mW.positions, k, c, l) = x[c], at(mW.velocities, k, c, l) = v[c];
            }
            for (uint32_t k = 0; k < attached; ++k)
                for (int c = 0; c < 3; ++c) {
                    at(mW.attachedStart, k, c, l) = at(mW.positions, free + k, c, l);
                    at(mW.attachedEnd, k, c, l) = lane.targets[k][c];
                }
            for (int c = 0; c < 3; ++c) {
                mAcceleration[c][l] = lane.acceleration[c];
                mOmega[c][l] = lane.fictitiousScale > 0.0 ? lane.frameAngularVelocity[c] : 0.0;
                mOmegaDot[c][l] = lane.fictitiousScale * lane.frameAngularAcceleration[c];
                mScale[l] = lane.fictitiousScale;
            }
            mDecay[l] = mFactor ? std::exp(-lane.velocityDamping * mFactor->substep()) : 1.0;
            if (std::size_t(l) < lanes.size() && lane.fictitiousScale > 0.0 &&
                (lane.frameAngularVelocity != Vec3::Zero() || lane.frameAngularAcceleration != Vec3::Zero()))
                mRotating = true;
            auto& contacts = mW.contacts[l];
            contacts.clear();
            mCorrections[l] = 0;
            if (std::size_t(l) >= lanes.size()) continue;
            contacts.reserve(std::max(lane.contactCapacity, lane.contacts.size()));
            for (const Contact& c : lane.contacts) {
                const uint32_t node = mLevel.nodeOfVertex()[c.vertex];
                if (node >= free) continue;  // attached nodes follow their targets
                contacts.push_back({node, c.normal, c.surfaceVelocity,
                                    c.normal.dot(c.point) + mSettings.contactThickness});
            }
        }
    }

    using V = typename Lanes<W>::V;
    static constexpr int S = Lanes<W>::kStep;

    // The prediction of substep(), plus the forces of a turning frame evaluated at the substep's
    // start (explicit: |w| h is about 0.01 for a character turning on the spot, far inside the
    // stability of an explicit rotation). A lane whose frame does not turn adds exact zeros, so
    // its result does not depend on the other lanes of its batch.
    void predictInRotatingFrame(double* x, const double* v, double* y, double* prev, const double* bend,
                                bool explicitBending) {
        const double h = mFactor->substep();
        const double h2 = h * h;
        const uint32_t free = mLevel.freeNodeCount();
        const auto& mass = mLevel.nodeMasses();
        for (uint32_t k = 0; k < free; ++k) {
            const double scale = h2 / mass[k];
            const std::size_t o = std::size_t(k) * kRow;
            for (int l = 0; l < W; l += S) {
                V r[3], u[3], w[3], dw[3], a[3];
                for (int c = 0; c < 3; ++c) {
                    r[c] = load<V>(x + o + c * W + l);
                    u[c] = load<V>(v + o + c * W + l) * load<V>(&mDecay[l]);
                    w[c] = load<V>(&mOmega[c][l]);
                    dw[c] = load<V>(&mOmegaDot[c][l]);
                }
                const V wr[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
                const V wu[3] = {w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
                const V wwr[3] = {w[1] * wr[2] - w[2] * wr[1], w[2] * wr[0] - w[0] * wr[2],
                                  w[0] * wr[1] - w[1] * wr[0]};
                const V dwr[3] = {dw[1] * r[2] - dw[2] * r[1], dw[2] * r[0] - dw[0] * r[2],
                                  dw[0] * r[1] - dw[1] * r[0]};
                const V s = load<V>(&mScale[l]);
                for (int c = 0; c < 3; ++c)
                    a[c] = load<V>(&mAcceleration[c][l]) - (dwr[c] + s * (2.0 * wu[c] + wwr[c]));
                for (int c = 0; c < 3; ++c) {
                    store(prev + o + c * W + l, r[c]);
                    V next = r[c] + h * u[c] + h2 * a[c];
                    if (explicitBending) next += scale * load<V>(bend + o + c * W + l);
                    store(y + o + c * W + l, next);
                    store(x + o + c * W + l, next);
                }
            }
        }
    }

    void substep(int s, int n) {
        const double h = mFactor->substep();
        const double h2 = h * h;
        const uint32_t free = mLevel.freeNodeCount();
        const uint32_t nodes = mLevel.nodeCount();
        const auto& mass = mLevel.nodeMasses();
        double* x = mW.positions.data();
        double* v = mW.velocities.data();
        double* prev = mW.previous.data();
        double* y = mW.predicted.data();
        const bool newton = mSettings.method == SubstepMethod::Newton;
        // Soft bending the factor leaves out acts explicitly (implicit-explicit splitting, stable
        // by the factor's own test): its forces at the substep's start join the prediction.
        const bool explicitBending = !mFactor->includesBending();
        double* bend = mW.solution.data();
        if (explicitBending) {
            std::fill(bend, bend + std::size_t(nodes) * kRow, 0.0);
            springForces(mLevel.freeBendSprings(), x, bend, nullptr, true, 1.0);
            springForces(mLevel.attachedBendSprings(), x, bend, nullptr, false, 1.0);
        }
        // Inertial prediction y = x + h v + h^2 a; the solve starts from x = y.
        if (mRotating) {
            predictInRotatingFrame(x, v, y, prev, bend, explicitBending);
        } else {
        for (uint32_t k = 0; k < free; ++k) {
            const double scale = h2 / mass[k];
            for (int c = 0; c < 3; ++c) {
                const std::size_t o = std::size_t(k) * kRow + c * W;
                for (int l = 0; l < W; l += S) {
                    store(prev + o + l, load<V>(x + o + l));
                    V next = load<V>(x + o + l) + h * (load<V>(v + o + l) * load<V>(&mDecay[l])) +
                             h2 * load<V>(&mAcceleration[c][l]);
                    if (explicitBending) next += scale * load<V>(bend + o + l);
                    store(y + o + l, next);
                    store(x + o + l, next);
                }
            }
        }
        }
        // Attached nodes on their way to the targets (exactly there after the last substep).
        const bool last = s + 1 == n;
        const double fraction = double(s + 1) / double(n);
        for (uint32_t k = free; k < nodes; ++k) {
            for (int c = 0; c < 3; ++c) {
                const std::size_t o = std::size_t(k) * kRow + c * W;
                const std::size_t t = std::size_t(k - free) * kRow + c * W;
                for (int l = 0; l < W; l += S) {
                    store(prev + o + l, load<V>(x + o + l));
                    const V start = load<V>(&mW.attachedStart[t + l]), end = load<V>(&mW.attachedEnd[t + l]);
                    const V at = last ? end : start + fraction * (end - start);
                    store(x + o + l, at);
                    store(y + o + l, at);
                }
            }
        }

        if (newton) {
            newtonStep(x, mass, h2, mSettings.warmStart && s > 0);
        } else {
            double* b = mW.solution.data();
            for (int it = 0; it < mSettings.iterations; ++it) {
                localStep(x, y, b, mass, h2);
                mFactor->solveInPlace(b, kRow, mW.permuted);  // global step with the shared factor
                std::copy(b, b + std::size_t(free) * kRow, x);
            }
        }

        // Contacts: a vertex behind its moving plane is pushed onto it; Coulomb friction on the
        // tangential motion relative to the surface, bounded by the push (position-level friction).
        const double timeToEnd = mDt - (s + 1) * h;
        const double muS = mSettings.friction.staticCoefficient, muK = mSettings.friction.kineticCoefficient;
        for (int l = 0; l < W; ++l) {
            for (SubstepWorkspace::LaneContact& c : mW.contacts[l]) {
                Vec3 p(at(mW.positions, c.node, 0, l), at(mW.positions, c.node, 1, l), at(mW.positions, c.node, 2, l));
                const double offset = c.offsetAtEnd - timeToEnd * c.normal.dot(c.surfaceVelocity);
                const double push = offset - c.normal.dot(p);
                if (!(push > 0.0)) continue;
                p += push * c.normal;
                const Vec3 before(at(mW.previous, c.node, 0, l), at(mW.previous, c.node, 1, l),
                                  at(mW.previous, c.node, 2, l));
                const Vec3 slide = (p - before) - h * c.surfaceVelocity;
                const Vec3 tangential = slide - c.normal * c.normal.dot(slide);
                const double distance = tangential.norm();
                if (distance <= muS * push) {
                    p -= tangential;
                } else if (distance > 0.0) {
                    p -= tangential * std::min(1.0, muK * push / distance);
                }
                for (int k = 0; k < 3; ++k) at(mW.positions, c.node, k, l) = p[k];
                c.pushed = true;
                ++mCorrections[l];
            }
        }

        for (std::size_t i = 0; i < std::size_t(nodes) * kRow; ++i) v[i] = (x[i] - prev[i]) / h;
        // A push is inelastic: a pushed vertex leaves the substep no faster along the normal than
        // the surface, so correcting a penetration (push / h) adds no kinetic energy that a later
        // substep would turn into a bounce.
        for (int l = 0; l < W; ++l) {
            for (SubstepWorkspace::LaneContact& c : mW.contacts[l]) {
                if (!c.pushed) continue;
                c.pushed = false;
                Vec3 vel(at(mW.velocities, c.node, 0, l), at(mW.velocities, c.node, 1, l), at(mW.velocities, c.node, 2, l));
                const double away = c.normal.dot(vel - c.surfaceVelocity);
                if (!(away > 0.0)) continue;
                vel -= away * c.normal;
                for (int k = 0; k < 3; ++k) at(mW.velocities, c.node, k, l) = vel[k];
            }
        }
    }

    // The right-hand side M / h^2 y + sum_s k_s A_s^T p_s, with p_s the rest-length projection of
    // spring s in the iterate x (an attached end is known, so its k x_b term joins the sum).
    void localStep(const double* CC_RESTRICT x, const double* CC_RESTRICT y, double* CC_RESTRICT b,
                   const std::vector<double>& mass, double h2) const {
        const uint32_t free = mLevel.freeNodeCount();
        for (uint32_t k = 0; k < free; ++k) {
            const double inertia = mass[k] / h2;
            const std::size_t o = std::size_t(k) * kRow;
            for (int i = 0; i < kRow; ++i) b[o + i] = inertia * y[o + i];
        }
        const double compression = mSettings.compressionStiffness;
        projections(mLevel.freeSprings(), x, b, true, compression);
        projections(mLevel.attachedSprings(), x, b, false, compression);
        if (mFactor->includesBending()) {
            projections(mLevel.freeBendSprings(), x, b, true, 1.0);
            projections(mLevel.attachedBendSprings(), x, b, false, 1.0);
        }
    }

    // A spring shorter than rest projects only `compression` of the way back to its rest length
    // (the force k (|d| - p) is then compression x k (|d| - L0)).
    void projections(const std::vector<LevelSpring>& springs, const double* CC_RESTRICT x, double* CC_RESTRICT b,
                     bool bothFree, double compression) const {
        for (const LevelSpring& sp : springs) {
            const double* CC_RESTRICT xa = x + std::size_t(sp.a) * kRow;
            const double* CC_RESTRICT xb = x + std::size_t(sp.b) * kRow;
            double* CC_RESTRICT ba = b + std::size_t(sp.a) * kRow;
            double* CC_RESTRICT bb = b + std::size_t(sp.b) * kRow;
            for (int l = 0; l < W; l += S) {
                const V ax = load<V>(xa + l), ay = load<V>(xa + W + l), az = load<V>(xa + 2 * W + l);
                const V bx = load<V>(xb + l), by = load<V>(xb + W + l), bz = load<V>(xb + 2 * W + l);
                const V dx = ax - bx, dy = ay - by, dz = az - bz;
                const V length = vsqrt(dx * dx + dy * dy + dz * dz);
                V scale = length > 0.0 ? sp.stiffness * sp.restLength / length : V{};
                if (compression < 1.0) {
                    const V target = length + compression * (sp.restLength - length);
                    scale = length < sp.restLength ? (length > 0.0 ? sp.stiffness * target / length : V{}) : scale;
                }
                if (bothFree) {
                    store(ba + l, load<V>(ba + l) + scale * dx);
                    store(ba + W + l, load<V>(ba + W + l) + scale * dy);
                    store(ba + 2 * W + l, load<V>(ba + 2 * W + l) + scale * dz);
                    store(bb + l, load<V>(bb + l) - scale * dx);
                    store(bb + W + l, load<V>(bb + W + l) - scale * dy);
                    store(bb + 2 * W + l, load<V>(bb + 2 * W + l) - scale * dz);
                } else {
                    store(ba + l, load<V>(ba + l) + (sp.stiffness * bx + scale * dx));
                    store(ba + W + l, load<V>(ba + W + l) + (sp.stiffness * by + scale * dy));
                    store(ba + 2 * W + l, load<V>(ba + 2 * W + l) + (sp.stiffness * bz + scale * dz));
                }
            }
        }
    }

    // Spring forces at x added into f (f = -grad E); with `frames`, also each spring's definite
    // Hessian k [n n^T + t (I - n n^T)], t = max(0, 1 - L0 / |d|), stored as (n, k (1 - t), k t).
    // A spring shorter than rest pulls with `compression` of its stiffness (force and Hessian).
    void springForces(const std::vector<LevelSpring>& springs, const double* CC_RESTRICT x, double* CC_RESTRICT f,
                      double* CC_RESTRICT frames, bool bothFree, double compression) const {
        for (std::size_t i = 0; i < springs.size(); ++i) {
            const LevelSpring& sp = springs[i];
            const double* CC_RESTRICT xa = x + std::size_t(sp.a) * kRow;
            const double* CC_RESTRICT xb = x + std::size_t(sp.b) * kRow;
            double* CC_RESTRICT fa = f + std::size_t(sp.a) * kRow;
            double* CC_RESTRICT fb = f + std::size_t(sp.b) * kRow;
            double* CC_RESTRICT frame = frames ? frames + i * 5 * W : nullptr;
            const double compressed = compression * sp.stiffness;
            for (int l = 0; l < W; l += S) {
                const V dx = load<V>(xa + l) - load<V>(xb + l), dy = load<V>(xa + W + l) - load<V>(xb + W + l),
                        dz = load<V>(xa + 2 * W + l) - load<V>(xb + 2 * W + l);
                const V length = vsqrt(dx * dx + dy * dy + dz * dz);
                const V inverse = length > 0.0 ? 1.0 / length : V{};
                const V nx = dx * inverse, ny = dy * inverse, nz = dz * inverse;
                const V stretch = length - sp.restLength;
                V stiffness = V{} + sp.stiffness;
                if (compression < 1.0) stiffness = length < sp.restLength ? V{} + compressed : stiffness;
                const V tension = stiffness * stretch;
                store(fa + l, load<V>(fa + l) - tension * nx);
                store(fa + W + l, load<V>(fa + W + l) - tension * ny);
                store(fa + 2 * W + l, load<V>(fa + 2 * W + l) - tension * nz);
                if (bothFree) {
                    store(fb + l, load<V>(fb + l) + tension * nx);
                    store(fb + W + l, load<V>(fb + W + l) + tension * ny);
                    store(fb + 2 * W + l, load<V>(fb + 2 * W + l) + tension * nz);
                }
                if (frame) {
                    // A collapsed spring has no direction: it resists isotropically.
                    const V stretched = 1.0 - sp.restLength * inverse;
                    const V t = length > 0.0 ? (stretched > 0.0 ? stretched : V{}) : V{} + 1.0;
                    store(frame + l, nx), store(frame + W + l, ny), store(frame + 2 * W + l, nz);
                    store(frame + 3 * W + l, stiffness * (1.0 - t));
                    store(frame + 4 * W + l, sp.stiffness * t);
                }
            }
        }
    }

    // One spring's stored Hessian times u (lanes l..l+S): frame3 (n . u) n + frame4 u.
    static void springHessianTimes(const double* CC_RESTRICT frame, int l, const V (&u)[3],
                                   V (&out)[3]) {
        const V n[3] = {load<V>(frame + l), load<V>(frame + W + l), load<V>(frame + 2 * W + l)};
        const V along = load<V>(frame + 3 * W + l) * (n[0] * u[0] + n[1] * u[1] + n[2] * u[2]);
        const V across = load<V>(frame + 4 * W + l);
        for (int c = 0; c < 3; ++c) out[c] = along * n[c] + across * u[c];
    }

    // out += H u over one list of springs (the stored frames), for the free ends.
    void hessianProduct(const std::vector<LevelSpring>& springs, const double* CC_RESTRICT frames,
                        const double* CC_RESTRICT u, double* CC_RESTRICT out, bool bothFree) const {
        for (std::size_t i = 0; i < springs.size(); ++i) {
            const LevelSpring& sp = springs[i];
            const double* CC_RESTRICT ua = u + std::size_t(sp.a) * kRow;
            const double* CC_RESTRICT ub = u + std::size_t(sp.b) * kRow;
            double* CC_RESTRICT oa = out + std::size_t(sp.a) * kRow;
            double* CC_RESTRICT ob = out + std::size_t(sp.b) * kRow;
            const double* CC_RESTRICT frame = frames + i * 5 * W;
            for (int l = 0; l < W; l += S) {
                V d[3], h[3];
                for (int c = 0; c < 3; ++c) {
                    d[c] = load<V>(ua + c * W + l);
                    if (bothFree) d[c] -= load<V>(ub + c * W + l);
                }
                springHessianTimes(frame, l, d, h);
                for (int c = 0; c < 3; ++c) {
                    store(oa + c * W + l, load<V>(oa + c * W + l) + h[c]);
                    if (bothFree) store(ob + c * W + l, load<V>(ob + c * W + l) - h[c]);
                }
            }
        }
    }

    // Per lane: sum over the free nodes of a . b, in node order.
    void dot(const double* CC_RESTRICT a, const double* CC_RESTRICT b, double (&out)[W]) const {
        V sum[W / S];
        for (int j = 0; j < W / S; ++j) sum[j] = V{};
        for (uint32_t k = 0; k < mLevel.freeNodeCount(); ++k) {
            const std::size_t o = std::size_t(k) * kRow;
            for (int l = 0; l < W; l += S)
                sum[l / S] += load<V>(a + o + l) * load<V>(b + o + l) +
                              load<V>(a + o + W + l) * load<V>(b + o + W + l) +
                              load<V>(a + o + 2 * W + l) * load<V>(b + o + 2 * W + l);
        }
        for (int l = 0; l < W; l += S) store(out + l, sum[l / S]);
    }

    // q = (M / h^2 + H) p over the free nodes, H over the springs in the Newton system.
    void systemProduct(const double* p, double* q, const std::vector<double>& mass, double h2) const {
        const uint32_t free = mLevel.freeNodeCount();
        for (uint32_t k = 0; k < free; ++k) {
            const double inertia = mass[k] / h2;
            const std::size_t o = std::size_t(k) * kRow;
            for (int i = 0; i < kRow; ++i) q[o + i] = inertia * p[o + i];
        }
        const double* frames = mW.springFrames.data();
        for (int k = 0; k < mGroupCount; ++k) {
            const Group& g = mGroups[k];
            hessianProduct(*g.springs, frames, p, q, g.bothFree);
            frames += g.springs->size() * 5 * W;
        }
    }

    // Rayleigh damping beta K v_next (Baraff & Witkin 1998), v_next = (y + d - x_start) / h,
    // linearised at y with the springs' Hessian K there: the residual gains -(beta / h) K (y - x_start)
    // and the system's K becomes (1 + beta / h) K (the stored frames are scaled, so every product
    // after this sees it). An attached node's motion is its target's over the substep, so a spring
    // to the body damps motion relative to the body; a translation is in K's null space.
    void addStiffnessDamping(double* CC_RESTRICT r) {
        const double rate = mSettings.stiffnessDamping / mFactor->substep();
        const double* CC_RESTRICT start = mW.previous.data();
        const double* CC_RESTRICT y = mW.predicted.data();  // attached nodes: their substep targets
        double* CC_RESTRICT frame = mW.springFrames.data();
        for (int k = 0; k < mGroupCount; ++k) {
            const Group& g = mGroups[k];
            for (const LevelSpring& sp : *g.springs) {
                const std::size_t a = std::size_t(sp.a) * kRow, b = std::size_t(sp.b) * kRow;
                for (int l = 0; l < W; l += S) {
                    V relative[3], stiffnessTimes[3];
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t o = std::size_t(c) * W + l;
                        relative[c] = (load<V>(y + a + o) - load<V>(start + a + o)) -
                                      (load<V>(y + b + o) - load<V>(start + b + o));
                    }
                    springHessianTimes(frame, l, relative, stiffnessTimes);
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t o = std::size_t(c) * W + l;
                        const V force = rate * stiffnessTimes[c];
                        store(r + a + o, load<V>(r + a + o) - force);
                        if (g.bothFree) store(r + b + o, load<V>(r + b + o) + force);
                    }
                    store(frame + 3 * W + l, (1.0 + rate) * load<V>(frame + 3 * W + l));
                    store(frame + 4 * W + l, (1.0 + rate) * load<V>(frame + 4 * W + l));
                }
                frame += 5 * W;
            }
        }
    }

    // The springs of the Newton system: stretch and shear, and bending when the factor has it
    // (otherwise it is explicit, in the prediction).
    struct Group {
        const std::vector<LevelSpring>* springs;
        bool bothFree;
        double compression;  // stretch and shear: the settings'; bending: 1
    };

    // d += a p and r -= a q with a per lane scalar: CG's update along its search direction p (q = A p),
    // and the warm start's along the last correction.
    static void advance(const double* a, const double* p, const double* q, double* d, double* r, std::size_t size) {
        for (std::size_t o = 0; o < size; o += kRow)
            for (int c = 0; c < 3; ++c)
                for (int l = 0; l < W; l += S) {
                    const std::size_t i = o + c * W + l;
                    const V scale = load<V>(a + l);
                    store(d + i, load<V>(d + i) + scale * load<V>(p + i));
                    store(r + i, load<V>(r + i) - scale * load<V>(q + i));
                }
    }

    // One Newton step from the prediction (in x): (M / h^2 + H) d = f(x), x += d, by `iterations`
    // CG iterations preconditioned with the shared factor, from d = 0 or (warm) from the line
    // search's multiple of the last correction. Per lane scalars, so lanes never mix; a lane whose
    // residual vanishes stops moving (alpha = 0).
    void newtonStep(double* x, const std::vector<double>& mass, double h2, bool warm) {
        const uint32_t free = mLevel.freeNodeCount();
        const std::size_t size = std::size_t(free) * kRow;
        mGroupCount = 0;
        std::size_t springs = 0;
        auto group = [&](const std::vector<LevelSpring>& list, bool bothFree, double compression) {
            mGroups[mGroupCount++] = {&list, bothFree, compression};
            springs += list.size();
        };
        group(mLevel.freeSprings(), true, mSettings.compressionStiffness);
        group(mLevel.attachedSprings(), false, mSettings.compressionStiffness);
        if (mFactor->includesBending()) {
            group(mLevel.freeBendSprings(), true, 1.0);
            group(mLevel.attachedBendSprings(), false, 1.0);
        }
        for (auto* a : {&mW.search, &mW.product}) ensureSize(*a, size);  // written before read
        for (auto* a : {&mW.residual, &mW.correction}) a->assign(size, 0.0);  // accumulated into
        mW.springFrames.resize(springs * 5 * W);
        double* r = mW.residual.data();
        double* p = mW.search.data();
        double* q = mW.product.data();
        double* d = mW.correction.data();
        double* z = mW.solution.data();
        double* frames = mW.springFrames.data();
        for (int k = 0; k < mGroupCount; ++k) {
            const Group& g = mGroups[k];
            springForces(*g.springs, x, r, frames, g.bothFree, g.compression);
            frames += g.springs->size() * 5 * W;
        }
        if (mSettings.stiffnessDamping > 0.0) addStiffnessDamping(r);
        if (warm) {
            // Line search along the last substep's correction w: alpha = r.w / w.Aw minimises the
            // step's quadratic model along w, so the start is never worse than d = 0 in the energy
            // norm. Starting at w itself diverges at 4+ substeps when CG is cut short: an error the
            // few iterations leave is fed back each substep (measured on the solver front).
            const double* w = mW.lastCorrection.data();
            systemProduct(w, q, mass, h2);
            double rw[W], wq[W], a[W];
            dot(r, w, rw);
            dot(w, q, wq);
            for (int l = 0; l < W; ++l) a[l] = wq[l] > 0.0 && rw[l] > 0.0 ? rw[l] / wq[l] : 0.0;
            advance(a, w, q, d, r, size);  // d was 0
        }
        auto precondition = [&] {
            std::copy(r, r + size, z);
            mFactor->solveInPlace(z, kRow, mW.permuted);
        };
        precondition();
        std::copy(z, z + size, p);
        double rz[W], pq[W], next[W], alpha[W], beta[W];
        dot(r, z, rz);
        for (int it = 0; it < mSettings.iterations; ++it) {
            systemProduct(p, q, mass, h2);
            dot(p, q, pq);
            for (int l = 0; l < W; ++l) alpha[l] = pq[l] > 0.0 && rz[l] > 0.0 ? rz[l] / pq[l] : 0.0;
            advance(alpha, p, q, d, r, size);
            if (it + 1 == mSettings.iterations) break;
            precondition();
            dot(r, z, next);
            for (int l = 0; l < W; ++l) beta[l] = rz[l] > 0.0 ? next[l] / rz[l] : 0.0, rz[l] = next[l];
            for (std::size_t o = 0; o < size; o += kRow)
                for (int c = 0; c < 3; ++c)
                    for (int l = 0; l < W; l += S) {
                        const std::size_t i = o + c * W + l;
                        store(p + i, load<V>(z + i) + load<V>(beta + l) * load<V>(p + i));
                    }
        }
        for (std::size_t i = 0; i < size; ++i) x[i] += d[i];
        if (mSettings.warmStart) std::swap(mW.correction, mW.lastCorrection);
    }

    // Provot's strain limit after the step, tethers first (see StrainLimiter); nodes flagged in
    // mW.fixedNodes move less (kPinnedWeight) than the others.
    void limitStrain(int (&outPasses)[W]) {
        const uint8_t* fixed = mW.fixedNodes.data();
        const double limit = mSettings.strainLimit;
        const double tolerance = 1e-3 * limit;
        const uint32_t free = mLevel.freeNodeCount();
        const auto& mass = mLevel.nodeMasses();
        const auto& tethers = mLevel.tethers();
        double* x = mW.positions.data();
        double* v = mW.velocities.data();
        const double inverseDt = 1.0 / mDt;
        int lastCorrected[W];
        for (int l = 0; l < W; ++l) lastCorrected[l] = -1;
        for (int pass = 0; pass < mSettings.strainLimitPasses; ++pass) {
            bool corrected[W] = {};
            for (uint32_t k = 0; k < tethers.size(); ++k) {
                const uint8_t* pinned = fixed + std::size_t(k) * W;
                double* xi = x + std::size_t(k) * kRow;
                double* vi = v + std::size_t(k) * kRow;
                const double* xa = x + std::size_t(tethers[k].anchor) * kRow;
                const double maxLength = (1.0 + limit) * tethers[k].restLength;
                for (int l = 0; l < W; ++l) {
                    const double dx = xi[l] - xa[l], dy = xi[W + l] - xa[W + l], dz = xi[2 * W + l] - xa[2 * W + l];
                    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
                    if (pinned[l] || !(length > maxLength * (1.0 + tolerance))) continue;
                    const double scale = maxLength / length - 1.0;
                    xi[l] += scale * dx, xi[W + l] += scale * dy, xi[2 * W + l] += scale * dz;
                    vi[l] += scale * dx * inverseDt, vi[W + l] += scale * dy * inverseDt, vi[2 * W + l] += scale * dz * inverseDt;
                    corrected[l] = true;
                }
            }
            for (const LimitedEdge& e : mLevel.limitedEdges()) {
                const double ma = e.a < free ? 1.0 / mass[e.a] : 0.0;
                const double mb = e.b < free ? 1.0 / mass[e.b] : 0.0;
                const uint8_t* pinnedA = fixed + std::size_t(e.a) * W;
                const uint8_t* pinnedB = fixed + std::size_t(e.b) * W;
                double* xa = x + std::size_t(e.a) * kRow;
                double* xb = x + std::size_t(e.b) * kRow;
                double* va = v + std::size_t(e.a) * kRow;
                double* vb = v + std::size_t(e.b) * kRow;
                const double maxLength = (1.0 + limit) * e.restLength;
                const double threshold = maxLength + tolerance * e.restLength;
                for (int l = 0; l < W; l += S) {
                    const V dx = load<V>(xb + l) - load<V>(xa + l), dy = load<V>(xb + W + l) - load<V>(xa + W + l),
                            dz = load<V>(xb + 2 * W + l) - load<V>(xa + 2 * W + l);
                    const V length = vsqrt(dx * dx + dy * dy + dz * dz);
                    V wa, wb;
                    for (int j = 0; j < S; ++j) {
                        if constexpr (S == 1) {
                            wa = pinnedA[l] ? kPinnedWeight * ma : ma, wb = pinnedB[l] ? kPinnedWeight * mb : mb;
                        } else {
                            wa[j] = pinnedA[l + j] ? kPinnedWeight * ma : ma;
                            wb[j] = pinnedB[l + j] ? kPinnedWeight * mb : mb;
                        }
                    }
                    const auto stretched = length > threshold;
                    bool any = false;
                    for (int j = 0; j < S; ++j) any = any || laneSet(stretched, j);
                    if (!any || ma + mb == 0.0) continue;
                    const V scale = (length - maxLength) / (length * (wa + wb));
                    const V sx = scale * dx, sy = scale * dy, sz = scale * dz;
                    // Lanes within the limit keep their values exactly (no +0 added).
                    auto update = [&](double* p, const V& delta) { store(p, stretched ? load<V>(p) + delta : load<V>(p)); };
                    update(xa + l, wa * sx), update(xa + W + l, wa * sy), update(xa + 2 * W + l, wa * sz);
                    update(xb + l, -(wb * sx)), update(xb + W + l, -(wb * sy)), update(xb + 2 * W + l, -(wb * sz));
                    update(va + l, wa * sx * inverseDt), update(va + W + l, wa * sy * inverseDt);
                    update(va + 2 * W + l, wa * sz * inverseDt);
                    update(vb + l, -(wb * sx * inverseDt)), update(vb + W + l, -(wb * sy * inverseDt));
                    update(vb + 2 * W + l, -(wb * sz * inverseDt));
                    for (int j = 0; j < S; ++j) corrected[l + j] = corrected[l + j] || laneSet(stretched, j);
                }
            }
            bool any = false;
            for (int l = 0; l < W; ++l) {
                if (corrected[l]) lastCorrected[l] = pass;
                any = any || corrected[l];
            }
            if (!any) break;
        }
        // As many sweeps as the lane alone would have run: up to its first clean sweep.
        for (int l = 0; l < W; ++l) outPasses[l] = std::min(lastCorrected[l] + 2, mSettings.strainLimitPasses);
    }

    bool finiteLane(int l) const {
        for (uint32_t k = 0; k < mLevel.nodeCount(); ++k) {
            const std::size_t o = std::size_t(k) * kRow + l;
            if (!finite3(&mW.positions[o], W) || !finite3(&mW.velocities[o], W)) return false;
        }
        return true;
    }

    void scatter(int l, const SubstepLane& lane) {
        const auto& node = mLevel.nodeOfVertex();
        for (std::size_t vtx = 0; vtx < node.size(); ++vtx) {
            const std::size_t o = std::size_t(node[vtx]) * kRow + l;
            lane.positions[vtx] = Vec3(mW.positions[o], mW.positions[o + W], mW.positions[o + 2 * W]);
            lane.velocities[vtx] = Vec3(mW.velocities[o], mW.velocities[o + W], mW.velocities[o + 2 * W]);
        }
    }

    const ClothLevel& mLevel;
    const SubstepFactor* mFactor;  // null for the limit-only pass
    double mDt;
    const SubstepSettings& mSettings;
    SubstepWorkspace& mW;
    double mAcceleration[3][W] = {};
    double mOmega[3][W] = {};     // frame rotation rate per lane (0 when its forces are off)
    double mOmegaDot[3][W] = {};  // its rate of change, scaled
    double mScale[W] = {};        // fictitious-force scale per lane
    double mDecay[W] = {};        // velocity kept per substep (1 = undamped: exact, bit for bit)
    bool mRotating = false;       // some lane's frame turns: the prediction adds its forces
    uint32_t mCorrections[W] = {};
    Group mGroups[4] = {};
    int mGroupCount = 0;
};

} // namespace

Status limitStrain(const ClothLevel& level, double dt, const SubstepSettings& settings, const SubstepLane& lane,
                   Span<const uint8_t> fixedVertices, SubstepWorkspace& workspace, int* outPasses) {
    if (Status s = settings.validate(); !s) return s;
    if (!(dt > 0.0 && dt <= 1.0)) return Status::invalidArgument("limitStrain: dt = " + std::to_string(dt) + " s is outside (0, 1]");
    if (Status s = checkLane(level, lane, 0); !s) return s;
    if (!fixedVertices.empty() && fixedVertices.size() != level.vertexCount())
        return Status::invalidArgument("limitStrain: one fixed flag per vertex, or none");
    int passes = 0;
    if (settings.strainLimit > 0.0) {
            passes = Kernel<1>(level, nullptr, dt, settings, workspace)
                     .limitOnly(lane, fixedVertices);
    }
    if (outPasses) *outPasses = passes;
    return Status::ok();
}

Status stepSubsteps(const ClothLevel& level, const SubstepFactor& factor, double dt, const SubstepSettings& settings,
                    Span<const SubstepLane> lanes, SubstepWorkspace& workspace, Span<SubstepLaneReport> outReports) {
    if (Status s = settings.validate(); !s) return s;
    if (!(dt > 0.0 && dt <= 1.0)) return Status::invalidArgument("stepSubsteps: dt = " + std::to_string(dt) + " s is outside (0, 1]");
    if (lanes.empty() || lanes.size() > std::size_t(kMaxSubstepLanes))
        return Status::invalidArgument("stepSubsteps: " + std::to_string(lanes.size()) + " lanes; need 1 to " +
                                       std::to_string(kMaxSubstepLanes));
    if (outReports.size() != lanes.size())
        return Status::invalidArgument("stepSubsteps: one report per lane is needed");
    const double h = dt / settings.substeps;
    if (factor.size() != level.freeNodeCount() || std::abs(factor.substep() - h) > 1e-12 * h)
        return Status::invalidArgument("stepSubsteps: the factor is for substeps of " + std::to_string(factor.substep()) +
                                       " s and " + std::to_string(factor.size()) + " nodes; this step needs " +
                                       std::to_string(h) + " s and " + std::to_string(level.freeNodeCount()));
    for (std::size_t l = 0; l < lanes.size(); ++l) {
        if (Status s = checkLane(level, lanes[l], l); !s) return s;
        outReports[l] = SubstepLaneReport{};
        if (const std::string bad = nonFiniteInput(lanes[l]); !bad.empty())
            outReports[l].status = Status::error(StatusCode::NumericalFailure, "stepSubsteps: " + bad);
    }
    switch (lanes.size()) {
    case 1: Kernel<1>(level, &factor, dt, settings, workspace).run(lanes, outReports); break;
    case 2: Kernel<2>(level, &factor, dt, settings, workspace).run(lanes, outReports); break;
    case 3:
    case 4: Kernel<4>(level, &factor, dt, settings, workspace).run(lanes, outReports); break;
    default: Kernel<8>(level, &factor, dt, settings, workspace).run(lanes, outReports); break;
    }
    return Status::ok();
}

} // namespace cc::cloth
