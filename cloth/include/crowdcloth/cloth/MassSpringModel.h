#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothMaterial.h"
#include "crowdcloth/cloth/ClothTopology.h"
#include "crowdcloth/cloth/ForceModel.h"
#include "crowdcloth/cloth/StencilSet.h"

namespace cc::cloth {

enum class SpringKind { Structural, Shear, Bend };

/// A linear spring between two vertices: E = 1/2 k (|xb - xa| - L0)^2.
struct Spring {
    uint32_t a = 0, b = 0;
    double stiffness = 0.0;   ///< [N/m] k; >= 0
    double restLength = 0.0;  ///< [m] L0; > 0
    SpringKind kind = SpringKind::Structural;
};

/// Provot's springs for a mesh (see MassSpringModel for the constants), in topology order:
/// one spring per edge, then one per hinge. Shared by the force model and the substepped solvers,
/// so every solver simulates the same springs.
std::vector<Spring> provotSprings(const ClothMesh& mesh, const ClothTopology& topology, const ClothMaterial& material);

/// Provot's mass-spring cloth (Provot 1995): structural springs along warp and weft, shear
/// springs along diagonals, bend springs across every hinge.
///
/// Spring constants come from the material's moduli and the local rest geometry, so refining the
/// mesh keeps the sheet's stiffness:
///   structural  k = Y * (A1 + A2) / L^2      (a strip of width ~A/L; k = Y on a square grid)
///   shear       k = 2 S * (A1 + A2) / L^2    (both diagonals of a square together give S)
///   bend        k = B * |e|^2 / ((A1 + A2) * L^2)
/// where A1, A2 are the rest areas beside the edge or hinge. Warp/weft vs diagonal is decided by
/// the rest direction (within 22.5 degrees of the u or v axis). Bend springs resist folding only
/// to second order in the angle: the continuum model is the one to use when bending matters.
class MassSpringModel final : public ForceModel {
public:
    static Result<std::unique_ptr<MassSpringModel>> fromSprings(uint32_t vertexCount, std::vector<Spring> springs);
    static Result<std::unique_ptr<MassSpringModel>> fromMesh(const ClothMesh& mesh, const ClothTopology& topology,
                                                             const ClothMaterial& material);

    const char* name() const override { return "mass-spring"; }
    uint32_t vertexCount() const override { return mVertexCount; }
    double energy(Span<const Vec3> positions) const override;
    void evaluate(const ForceEvaluation& request) const override;
    void appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const override;
    void bindMatrix(const BlockSparseMatrix& matrix) override;

private:
    MassSpringModel() = default;
    uint32_t mVertexCount = 0;
    std::vector<Spring> mSprings;
    StencilSet<2> mStencils;
};

} // namespace cc::cloth
