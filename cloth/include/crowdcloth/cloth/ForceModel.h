#pragma once

#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Span.h"

namespace cc::cloth {

/// Which second derivative a force model assembles.
enum class HessianMode {
    Exact,     ///< the true Hessian of the energy (finite-difference tests, Newton analysis)
    Definite,  ///< its positive semi-definite part (drops the terms that go indefinite under
               ///< compression), what the implicit solver needs for a convergent PCG
};

/// One evaluation request. Forces are always written; the rest on demand.
struct ForceEvaluation {
    Span<const Vec3> positions;        ///< [m] per vertex
    Span<const Vec3> velocities;       ///< [m/s] per vertex; needed when dampingCoefficient > 0
    double dampingCoefficient = 0.0;   ///< [s] adds -beta * K_e * v_e per element (Rayleigh)
    Span<Vec3> outForces;              ///< [N] accumulated into (caller zeroes)
    BlockSparseMatrix* outStiffness = nullptr; ///< [N/m] K = d2E/dx2 accumulated into, if set
    HessianMode hessianMode = HessianMode::Definite;
    /// [N/m] per vertex and axis, accumulated: sum over the row of |K| entries (Gershgorin), if set.
    Span<Vec3> outStiffnessRowBound;
    ParallelSettings parallel;
};

/// The internal (elastic) forces of one garment. Gravity, contacts and pins are the integrator's.
/// Implementations are immutable after construction and safe to evaluate from several garments'
/// threads at once.
class ForceModel {
public:
    virtual ~ForceModel() = default;
    virtual const char* name() const = 0;
    virtual uint32_t vertexCount() const = 0;
    /// [J] elastic energy at `positions` (serial; for tests and statistics, not the hot path).
    virtual double energy(Span<const Vec3> positions) const = 0;
    virtual void evaluate(const ForceEvaluation& request) const = 0;
    /// The block pattern K needs: every pair of vertices that share an element.
    virtual void appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const = 0;
    /// Binds element blocks to the slots of a matrix built from appendCouplings(). Must be called
    /// (once per pattern) before evaluate() with outStiffness; not thread-safe.
    virtual void bindMatrix(const BlockSparseMatrix& matrix) = 0;
};

} // namespace cc::cloth
