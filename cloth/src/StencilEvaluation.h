#pragma once

#include <Eigen/Core>

#include "crowdcloth/cloth/ForceModel.h"
#include "crowdcloth/cloth/StencilSet.h"

namespace cc::cloth::detail {

/// Local result of one element with N vertices: energy, forces, Hessian of the energy.
template <int N>
struct LocalElement {
    double energy = 0.0;
    Eigen::Matrix<double, 3 * N, 1> force;
    Eigen::Matrix<double, 3 * N, 3 * N> hessian;
};

/// Evaluates every element of `set` with `kernel(e, x_local, mode, out)` and scatters the results,
/// colour by colour, into the request's forces, stiffness matrix and row bounds. Damping adds
/// -beta * K_e * v_e with the element's definite Hessian.
template <int N, typename Kernel>
void evaluateStencils(const StencilSet<N>& set, const ForceEvaluation& req, Kernel&& kernel) {
    const bool wantHessian = req.outStiffness || req.dampingCoefficient > 0.0 || !req.outStiffnessRowBound.empty();
    for (std::size_t c = 0; c < set.colourCount(); ++c) {
        const int64_t first = set.colourStart[c];
        const int64_t count = int64_t(set.colourStart[c + 1]) - first;
        parallelFor(count, req.parallel, [&](int64_t b, int64_t e) {
            LocalElement<N> el;
            Eigen::Matrix<double, 3 * N, 1> xl, vl;
            for (int64_t k = first + b; k < first + e; ++k) {
                const auto& vs = set.vertices[k];
                for (int a = 0; a < N; ++a) xl.template segment<3>(3 * a) = req.positions[vs[a]];
                kernel(static_cast<uint32_t>(k), xl, wantHessian, req.hessianMode, el);
                if (req.dampingCoefficient > 0.0) {
                    for (int a = 0; a < N; ++a) vl.template segment<3>(3 * a) = req.velocities[vs[a]];
                    el.force.noalias() -= req.dampingCoefficient * (el.hessian * vl);
                }
                for (int a = 0; a < N; ++a) req.outForces[vs[a]] += el.force.template segment<3>(3 * a);
                if (req.outStiffness) {
                    for (int a = 0; a < N; ++a) {
                        for (int bb = 0; bb < N; ++bb) {
                            req.outStiffness->block(set.slots[k][a * N + bb]) +=
                                el.hessian.template block<3, 3>(3 * a, 3 * bb);
                        }
                    }
                }
                if (!req.outStiffnessRowBound.empty()) {
                    const Eigen::Matrix<double, 3 * N, 1> rowAbs = el.hessian.cwiseAbs().rowwise().sum();
                    for (int a = 0; a < N; ++a) req.outStiffnessRowBound[vs[a]] += rowAbs.template segment<3>(3 * a);
                }
            }
        });
    }
}

/// Sum of kernel energies over all elements, in element order.
template <int N, typename Kernel>
double sumStencilEnergy(const StencilSet<N>& set, Span<const Vec3> positions, Kernel&& kernel) {
    LocalElement<N> el;
    Eigen::Matrix<double, 3 * N, 1> xl;
    double total = 0.0;
    for (std::size_t k = 0; k < set.size(); ++k) {
        for (int a = 0; a < N; ++a) xl.template segment<3>(3 * a) = positions[set.vertices[k][a]];
        kernel(static_cast<uint32_t>(k), xl, false, HessianMode::Definite, el);
        total += el.energy;
    }
    return total;
}

} // namespace cc::cloth::detail
