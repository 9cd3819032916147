#include "crowdcloth/cloth/ContinuumModel.h"

#include <cmath>

#include "StencilEvaluation.h"

namespace cc::cloth {
namespace {

using Tri = ContinuumModel::Triangle;
using HingeBend = ContinuumModel::HingeBend;

struct MembraneKernel {
    const std::vector<Tri>& triangles;
    double stretch, shear;

    // Adds 1/2 Y A (|w| - 1)^2 for one of w_u, w_v (g = its corner gradients).
    //   grad_k = Y A (|w| - 1) n g_k
    //   H_kl   = Y A g_k g_l [n n^T + (|w| - 1)/|w| (I - n n^T)]
    void addStretch(const Vec3& w, const std::array<double, 3>& g, double ya, bool wantHessian, HessianMode mode,
                    detail::LocalElement<3>& out) const {
        const double len = w.norm();
        if (len <= 1e-12) {  // fully collapsed direction: no force, isotropic resistance
            out.energy += 0.5 * ya;
            if (wantHessian) {
                for (int k = 0; k < 3; ++k)
                    for (int l = 0; l < 3; ++l) out.hessian.block<3, 3>(3 * k, 3 * l) += ya * g[k] * g[l] * Mat3::Identity();
            }
            return;
        }
        const double strain = len - 1.0;
        const Vec3 n = w / len;
        out.energy += 0.5 * ya * strain * strain;
        for (int k = 0; k < 3; ++k) out.force.segment<3>(3 * k) -= ya * strain * g[k] * n;
        if (!wantHessian) return;
        double transverse = strain / len;
        if (mode == HessianMode::Definite) transverse = std::max(transverse, 0.0);
        const Mat3 nn = n * n.transpose();
        const Mat3 p = ya * (nn + transverse * (Mat3::Identity() - nn));
        for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l) out.hessian.block<3, 3>(3 * k, 3 * l) += (g[k] * g[l]) * p;
    }

    void operator()(uint32_t t, const Eigen::Matrix<double, 9, 1>& x, bool wantHessian, HessianMode mode,
                    detail::LocalElement<3>& out) const {
        const Tri& tri = triangles[t];
        out.energy = 0.0;
        out.force.setZero();
        if (wantHessian) out.hessian.setZero();
        Vec3 wu = Vec3::Zero(), wv = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            wu += tri.gradU[k] * x.segment<3>(3 * k);
            wv += tri.gradV[k] * x.segment<3>(3 * k);
        }
        addStretch(wu, tri.gradU, stretch * tri.area, wantHessian, mode, out);
        addStretch(wv, tri.gradV, stretch * tri.area, wantHessian, mode, out);

        // Shear C = w_u . w_v: grad_k = S A C dC_k with dC_k = gu_k w_v + gv_k w_u;
        // H_kl = S A [dC_k dC_l^T + C (gu_k gv_l + gv_k gu_l) I]; Definite drops the C term.
        const double sa = shear * tri.area;
        const double c = wu.dot(wv);
        out.energy += 0.5 * sa * c * c;
        std::array<Vec3, 3> dc;
        for (int k = 0; k < 3; ++k) {
            dc[k] = tri.gradU[k] * wv + tri.gradV[k] * wu;
            out.force.segment<3>(3 * k) -= sa * c * dc[k];
        }
        if (!wantHessian) return;
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 3; ++l) {
                Mat3 h = sa * dc[k] * dc[l].transpose();
                if (mode == HessianMode::Exact) {
                    h += sa * c * (tri.gradU[k] * tri.gradV[l] + tri.gradV[k] * tri.gradU[l]) * Mat3::Identity();
                }
                out.hessian.block<3, 3>(3 * k, 3 * l) += h;
            }
        }
    }
};

struct HingeKernel {
    const std::vector<HingeBend>& hinges;

    // E = 1/2 c |q|^2, q = sum K_i x_i: force_i = -c K_i q, H_ij = c K_i K_j I (exact and constant).
    void operator()(uint32_t h, const Eigen::Matrix<double, 12, 1>& x, bool wantHessian, HessianMode,
                    detail::LocalElement<4>& out) const {
        const HingeBend& hb = hinges[h];
        Vec3 q = Vec3::Zero();
        for (int i = 0; i < 4; ++i) q += hb.weights[i] * x.segment<3>(3 * i);
        out.energy = 0.5 * hb.coefficient * q.squaredNorm();
        for (int i = 0; i < 4; ++i) out.force.segment<3>(3 * i) = -hb.coefficient * hb.weights[i] * q;
        if (!wantHessian) return;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                out.hessian.block<3, 3>(3 * i, 3 * j) = (hb.coefficient * hb.weights[i] * hb.weights[j]) * Mat3::Identity();
    }
};

// Curvature weights of a flat rest hinge. With the wing's foot point p = (1-t) r0 + t r1 on the
// edge and distance d, (x_wing - p)/d is the unit in-plane normal pointing away from the edge for
// any affine map of the rest shape; the two wings' normals cancel when flat and sum to
// 2 sin(theta/2) when folded by theta.
HingeBend hingeBend(const ClothMesh& mesh, const Hinge& h, double bendStiffness) {
    const auto& r = mesh.restPositions;
    const Vec2 e = r[h.edge1] - r[h.edge0];
    const double e2 = e.squaredNorm();
    auto wing = [&](uint32_t w, double& t, double& d) {
        const Vec2 a = r[w] - r[h.edge0];
        t = a.dot(e) / e2;
        d = std::abs(e.x() * a.y() - e.y() * a.x()) / std::sqrt(e2);
    };
    double tA, dA, tB, dB;
    wing(h.wingA, tA, dA);
    wing(h.wingB, tB, dB);
    HingeBend hb;
    hb.weights = {-(1.0 - tA) / dA - (1.0 - tB) / dB, -tA / dA - tB / dB, 1.0 / dA, 1.0 / dB};
    hb.coefficient = bendStiffness * e2 / (restArea(mesh, h.triangleA) + restArea(mesh, h.triangleB));
    return hb;
}

} // namespace

Result<std::unique_ptr<ContinuumModel>> ContinuumModel::fromMesh(const ClothMesh& mesh, const ClothTopology& topo,
                                                                 const ClothMaterial& material) {
    if (Status s = material.validate(); !s) return s;
    std::unique_ptr<ContinuumModel> model(new ContinuumModel());
    model->mVertexCount = static_cast<uint32_t>(mesh.vertexCount());
    model->mStretch = material.stretchStiffness;
    model->mShear = material.shearStiffness;

    std::vector<Tri> triangles;
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& idx = mesh.triangles[t];
        Mat2 dm;
        dm.col(0) = mesh.restPositions[idx[1]] - mesh.restPositions[idx[0]];
        dm.col(1) = mesh.restPositions[idx[2]] - mesh.restPositions[idx[0]];
        // F = [x1-x0, x2-x0] Dm^-1, so w_u = sum_k gradU[k] x_k with gradU = (-(a+c), a, c) for
        // the first column (a, c) of Dm^-1 (and likewise w_v from the second column).
        const Mat2 inv = dm.inverse();
        Tri tri;
        tri.area = restArea(mesh, t);
        tri.gradU = {-(inv(0, 0) + inv(1, 0)), inv(0, 0), inv(1, 0)};
        tri.gradV = {-(inv(0, 1) + inv(1, 1)), inv(0, 1), inv(1, 1)};
        triangles.push_back(tri);
        model->mTriangleStencils.vertices.push_back(idx);
    }
    model->mTriangles = permute(triangles, model->mTriangleStencils.colour(model->mVertexCount));

    if (material.bendStiffness > 0.0) {
        std::vector<HingeBend> hinges;
        for (const Hinge& h : topo.hinges) {
            hinges.push_back(hingeBend(mesh, h, material.bendStiffness));
            model->mHingeStencils.vertices.push_back({h.edge0, h.edge1, h.wingA, h.wingB});
        }
        model->mHinges = permute(hinges, model->mHingeStencils.colour(model->mVertexCount));
    }
    return model;
}

double ContinuumModel::energy(Span<const Vec3> positions) const {
    return detail::sumStencilEnergy(mTriangleStencils, positions, MembraneKernel{mTriangles, mStretch, mShear}) +
           detail::sumStencilEnergy(mHingeStencils, positions, HingeKernel{mHinges});
}

void ContinuumModel::evaluate(const ForceEvaluation& request) const {
    detail::evaluateStencils(mTriangleStencils, request, MembraneKernel{mTriangles, mStretch, mShear});
    detail::evaluateStencils(mHingeStencils, request, HingeKernel{mHinges});
}

void ContinuumModel::appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const {
    mTriangleStencils.appendCouplings(out);
    mHingeStencils.appendCouplings(out);
}

void ContinuumModel::bindMatrix(const BlockSparseMatrix& matrix) {
    mTriangleStencils.bindSlots(matrix);
    mHingeStencils.bindSlots(matrix);
}

} // namespace cc::cloth
