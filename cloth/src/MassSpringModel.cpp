#include "crowdcloth/cloth/MassSpringModel.h"

#include <cmath>
#include <string>

#include "StencilEvaluation.h"

namespace cc::cloth {
namespace {

// tan(22.5 deg): a rest direction closer than this to the u or v axis counts as warp/weft.
constexpr double kAxisTolerance = 0.41421356237309503;

bool isAxisAligned(const Vec2& d) {
    const double du = std::abs(d.x()), dv = std::abs(d.y());
    return std::min(du, dv) <= kAxisTolerance * std::max(du, dv);
}

struct SpringKernel {
    const std::vector<Spring>& springs;

    // E = 1/2 k (L - L0)^2, with n = d/L:
    //   grad_b E = k (L - L0) n = -grad_a E
    //   H_bb = k [n n^T + (1 - L0/L)(I - n n^T)], H_aa = H_bb, H_ab = -H_bb.
    // Under compression (L < L0) the transverse term is negative; Definite mode drops it.
    void operator()(uint32_t k, const Eigen::Matrix<double, 6, 1>& x, bool wantHessian, HessianMode mode,
                    detail::LocalElement<2>& out) const {
        const Spring& s = springs[k];
        const Vec3 d = x.segment<3>(3) - x.segment<3>(0);
        const double length = d.norm();
        const double stretch = length - s.restLength;
        out.energy = 0.5 * s.stiffness * stretch * stretch;
        // A collapsed spring has no direction: it exerts no force and resists isotropically.
        const bool collapsed = length <= 1e-12 * s.restLength;
        const Vec3 n = collapsed ? Vec3::Zero() : Vec3(d / length);
        const Vec3 f = s.stiffness * stretch * n;
        out.force.segment<3>(0) = f;
        out.force.segment<3>(3) = -f;
        if (!wantHessian) return;
        Mat3 h;
        if (collapsed) {
            h = s.stiffness * Mat3::Identity();
        } else {
            double transverse = 1.0 - s.restLength / length;
            if (mode == HessianMode::Definite) transverse = std::max(transverse, 0.0);
            const Mat3 nn = n * n.transpose();
            h = s.stiffness * (nn + transverse * (Mat3::Identity() - nn));
        }
        out.hessian.block<3, 3>(0, 0) = h;
        out.hessian.block<3, 3>(3, 3) = h;
        out.hessian.block<3, 3>(0, 3) = -h;
        out.hessian.block<3, 3>(3, 0) = -h;
    }
};

} // namespace

Result<std::unique_ptr<MassSpringModel>> MassSpringModel::fromSprings(uint32_t vertexCount, std::vector<Spring> springs) {
    for (std::size_t i = 0; i < springs.size(); ++i) {
        const Spring& s = springs[i];
        const std::string where = "spring " + std::to_string(i) + " (" + std::to_string(s.a) + "-" + std::to_string(s.b) + ")";
        if (s.a >= vertexCount || s.b >= vertexCount || s.a == s.b) {
            return Status::invalidArgument(where + " has an invalid vertex index for " +
                                           std::to_string(vertexCount) + " vertices");
        }
        if (!(s.stiffness >= 0.0) || !std::isfinite(s.stiffness)) {
            return Status::invalidArgument(where + " has stiffness " + std::to_string(s.stiffness) + "; need finite >= 0");
        }
        if (!(s.restLength > 0.0) || !std::isfinite(s.restLength)) {
            return Status::invalidArgument(where + " has rest length " + std::to_string(s.restLength) + "; need finite > 0");
        }
    }
    std::unique_ptr<MassSpringModel> model(new MassSpringModel());
    model->mVertexCount = vertexCount;
    for (const Spring& s : springs) model->mStencils.vertices.push_back({s.a, s.b});
    model->mSprings = permute(springs, model->mStencils.colour(vertexCount));
    return model;
}

std::vector<Spring> provotSprings(const ClothMesh& mesh, const ClothTopology& topo, const ClothMaterial& material) {
    const auto& rest = mesh.restPositions;
    std::vector<Spring> springs;
    springs.reserve(topo.edges.size() + topo.hinges.size());
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        const auto [a, b] = topo.edges[e];
        double area = restArea(mesh, topo.edgeTriangles[e][0]);
        if (topo.edgeTriangles[e][1] != ClothTopology::kNone) area += restArea(mesh, topo.edgeTriangles[e][1]);
        const Vec2 d = rest[b] - rest[a];
        const double length2 = d.squaredNorm();
        if (isAxisAligned(d)) {
            springs.push_back({a, b, material.stretchStiffness * area / length2, std::sqrt(length2), SpringKind::Structural});
        } else {
            springs.push_back({a, b, 2.0 * material.shearStiffness * area / length2, std::sqrt(length2), SpringKind::Shear});
        }
    }
    for (const Hinge& h : topo.hinges) {
        const double area = restArea(mesh, h.triangleA) + restArea(mesh, h.triangleB);
        const Vec2 d = rest[h.wingB] - rest[h.wingA];
        const double length2 = d.squaredNorm();
        if (isAxisAligned(d)) {
            const double edge2 = (rest[h.edge1] - rest[h.edge0]).squaredNorm();
            springs.push_back({h.wingA, h.wingB, material.bendStiffness * edge2 / (area * length2),
                               std::sqrt(length2), SpringKind::Bend});
        } else {
            // The hinge across a square's diagonal joins its other two corners: the second shear diagonal.
            springs.push_back({h.wingA, h.wingB, 2.0 * material.shearStiffness * area / length2,
                               std::sqrt(length2), SpringKind::Shear});
        }
    }
    return springs;
}

Result<std::unique_ptr<MassSpringModel>> MassSpringModel::fromMesh(const ClothMesh& mesh, const ClothTopology& topo,
                                                                   const ClothMaterial& material) {
    if (Status s = material.validate(); !s) return s;
    return fromSprings(static_cast<uint32_t>(mesh.vertexCount()), provotSprings(mesh, topo, material));
}

double MassSpringModel::energy(Span<const Vec3> positions) const {
    return detail::sumStencilEnergy(mStencils, positions, SpringKernel{mSprings});
}

void MassSpringModel::evaluate(const ForceEvaluation& request) const {
    detail::evaluateStencils(mStencils, request, SpringKernel{mSprings});
}

void MassSpringModel::appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const {
    mStencils.appendCouplings(out);
}

void MassSpringModel::bindMatrix(const BlockSparseMatrix& matrix) { mStencils.bindSlots(matrix); }

} // namespace cc::cloth
