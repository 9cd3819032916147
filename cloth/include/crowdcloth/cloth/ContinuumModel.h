#pragma once

#include <array>
#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothMaterial.h"
#include "crowdcloth/cloth/ClothTopology.h"
#include "crowdcloth/cloth/ForceModel.h"
#include "crowdcloth/cloth/StencilSet.h"

namespace cc::cloth {

/// Continuum cloth: Baraff-Witkin membrane triangles plus hinge bending.
///
/// Membrane (Baraff & Witkin 1998, "Large steps in cloth simulation"): each triangle maps pattern
/// space (u, v) to world space with deformation gradient F = [w_u w_v]. With rest area A,
///   stretch  E = 1/2 Y A [(|w_u| - 1)^2 + (|w_v| - 1)^2]
///   shear    E = 1/2 S A (w_u . w_v)^2
/// Y and S are the material's N/m moduli, so the energy per rest area is resolution independent.
///
/// Bending: per hinge with rest areas A1, A2 and edge e, the curvature vector q = sum_i K_i x_i
/// (weights from the flat rest geometry: q vanishes under any affine map and |q| = 2 sin(theta/2)
/// for a fold by dihedral angle theta without stretch), and
///   E = 1/2 B |e|^2 / (A1 + A2) |q|^2 .
/// On a regular grid this is B/2 * kappa^2 per area for a cylinder of curvature kappa. It is the
/// discrete-shell dihedral energy (Grinspun et al. 2003) in the quadratic form of Bergou et al.
/// 2006 ("A quadratic bending model for inextensible surfaces"): exact for flat-rest isometric
/// folds, with a constant, positive semi-definite Hessian (cheap and safe for the implicit solve).
class ContinuumModel final : public ForceModel {
public:
    static Result<std::unique_ptr<ContinuumModel>> fromMesh(const ClothMesh& mesh, const ClothTopology& topology,
                                                            const ClothMaterial& material);

    const char* name() const override { return "continuum"; }
    uint32_t vertexCount() const override { return mVertexCount; }
    double energy(Span<const Vec3> positions) const override;
    void evaluate(const ForceEvaluation& request) const override;
    void appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const override;
    void bindMatrix(const BlockSparseMatrix& matrix) override;

    /// Per-triangle rest data: area and the gradients of w_u, w_v with respect to each corner.
    struct Triangle {
        double area;
        std::array<double, 3> gradU, gradV;
    };
    /// Per-hinge bending data: curvature weights and B |e|^2 / (A1 + A2).
    struct HingeBend {
        std::array<double, 4> weights;
        double coefficient;
    };

private:
    ContinuumModel() = default;
    uint32_t mVertexCount = 0;
    double mStretch = 0.0, mShear = 0.0;
    std::vector<Triangle> mTriangles;
    std::vector<HingeBend> mHinges;
    StencilSet<3> mTriangleStencils;
    StencilSet<4> mHingeStencils;
};

} // namespace cc::cloth
