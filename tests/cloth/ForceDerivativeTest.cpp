// Finite-difference checks of every force and Jacobian (TESTPLAN A5): forces must equal minus the
// central-difference gradient of the energy, and the exact Hessian the central difference of the
// forces, at random, near-degenerate and inverted states.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "crowdcloth/cloth/ContinuumModel.h"
#include "crowdcloth/cloth/MassSpringModel.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::cloth;

namespace {

Eigen::VectorXd forcesAt(const ForceModel& model, const std::vector<Vec3>& x) {
    std::vector<Vec3> f(x.size(), Vec3::Zero());
    ForceEvaluation eval;
    eval.positions = x;
    eval.outForces = f;
    model.evaluate(eval);
    Eigen::VectorXd out(3 * x.size());
    for (std::size_t i = 0; i < x.size(); ++i) out.segment<3>(3 * i) = f[i];
    return out;
}

Eigen::MatrixXd hessianAt(ForceModel& model, const std::vector<Vec3>& x, HessianMode mode) {
    std::vector<std::pair<uint32_t, uint32_t>> couplings;
    model.appendCouplings(couplings);
    BlockSparseMatrix k;
    k.buildPattern(static_cast<uint32_t>(x.size()), couplings);
    model.bindMatrix(k);
    std::vector<Vec3> f(x.size(), Vec3::Zero());
    ForceEvaluation eval;
    eval.positions = x;
    eval.outForces = f;
    eval.outStiffness = &k;
    eval.hessianMode = mode;
    model.evaluate(eval);
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * x.size(), 3 * x.size());
    for (uint32_t i = 0; i < k.size(); ++i)
        for (uint32_t s = k.rowStart()[i]; s < k.rowStart()[i + 1]; ++s)
            dense.block<3, 3>(3 * i, 3 * k.columns()[s]) = k.block(s);
    return dense;
}

// Relative error measured against the larger of the two and a floor from the matrix scale.
double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
}

void checkDerivatives(ForceModel& model, const std::vector<Vec3>& x, const char* where) {
    const double step = 1e-6;
    const std::size_t n = 3 * x.size();
    Eigen::VectorXd gradient(n);
    Eigen::MatrixXd fdHessian(n, n);
    for (std::size_t j = 0; j < n; ++j) {
        std::vector<Vec3> xp = x, xm = x;
        xp[j / 3][j % 3] += step;
        xm[j / 3][j % 3] -= step;
        gradient[j] = (model.energy(xp) - model.energy(xm)) / (2 * step);
        fdHessian.col(j) = -(forcesAt(model, xp) - forcesAt(model, xm)) / (2 * step);
    }
    const Eigen::VectorXd force = forcesAt(model, x);
    EXPECT_LT(relativeError(-force, gradient), 1e-6) << model.name() << " gradient, " << where;
    const Eigen::MatrixXd exact = hessianAt(model, x, HessianMode::Exact);
    EXPECT_LT(relativeError(exact, fdHessian), 1e-6) << model.name() << " Hessian, " << where;
    EXPECT_LT(relativeError(exact, exact.transpose()), 1e-12) << model.name() << " Hessian symmetry, " << where;
    // The definite Hessian must have no negative eigenvalue.
    const Eigen::MatrixXd definite = hessianAt(model, x, HessianMode::Definite);
    const double minEigen = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(definite).eigenvalues().minCoeff();
    EXPECT_GT(minEigen, -1e-9 * definite.cwiseAbs().maxCoeff()) << model.name() << " definite Hessian, " << where;
}

struct Fixture {
    ClothMesh mesh = RectanglePanel{0.3, 0.2, 3, 2}.build().value();
    ClothTopology topology = ClothTopology::build(mesh).value();
    ClothMaterial material;
    Fixture() {
        material.stretchStiffness = 100.0;
        material.shearStiffness = 30.0;
        material.bendStiffness = 0.5;  // comparable energies, so every term is exercised
    }
};

std::vector<Vec3> perturbed(const ClothMesh& mesh, double amplitude, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    std::vector<Vec3> x = mesh.positions;
    for (Vec3& p : x) p += Vec3(u(rng), u(rng), u(rng));
    return x;
}

template <typename Model>
std::unique_ptr<Model> build(const Fixture& f) {
    return Model::fromMesh(f.mesh, f.topology, f.material).value();
}

} // namespace

TEST(ForceDerivatives, MassSpringAtRandomStates) {
    Fixture f;
    auto model = build<MassSpringModel>(f);
    for (unsigned seed = 1; seed <= 3; ++seed) checkDerivatives(*model, perturbed(f.mesh, 0.04, seed), "random");
}

TEST(ForceDerivatives, ContinuumAtRandomStates) {
    Fixture f;
    auto model = build<ContinuumModel>(f);
    for (unsigned seed = 1; seed <= 3; ++seed) checkDerivatives(*model, perturbed(f.mesh, 0.04, seed), "random");
}

TEST(ForceDerivatives, BothModelsAtNearDegenerateAndInvertedStates) {
    Fixture f;
    // Squashed to 1% of its height: near-collinear triangles and springs far below rest length.
    std::vector<Vec3> squashed = perturbed(f.mesh, 1e-3, 7);
    for (Vec3& p : squashed) p.y() *= 0.01;
    // Mirrored through the x = 0.15 plane: every triangle inverted (and wrinkled).
    std::vector<Vec3> inverted = perturbed(f.mesh, 0.02, 11);
    for (Vec3& p : inverted) p.x() = 0.3 - p.x();
    auto springs = build<MassSpringModel>(f);
    auto continuum = build<ContinuumModel>(f);
    for (ForceModel* model : {static_cast<ForceModel*>(springs.get()), static_cast<ForceModel*>(continuum.get())}) {
        checkDerivatives(*model, squashed, "squashed");
        checkDerivatives(*model, inverted, "inverted");
    }
}

TEST(ForceDerivatives, RestStateHasZeroForceAndEnergy) {
    Fixture f;
    auto springs = build<MassSpringModel>(f);
    auto continuum = build<ContinuumModel>(f);
    for (ForceModel* m : {static_cast<ForceModel*>(springs.get()), static_cast<ForceModel*>(continuum.get())}) {
        // Any rigid motion of the rest shape is also at rest.
        const Eigen::AngleAxisd rotation(0.7, Vec3(1, 2, 3).normalized());
        std::vector<Vec3> x = f.mesh.positions;
        for (Vec3& p : x) p = rotation * p + Vec3(0.3, -2.0, 5.0);
        EXPECT_NEAR(m->energy(x), 0.0, 1e-20) << m->name();
        EXPECT_LT(forcesAt(*m, x).cwiseAbs().maxCoeff(), 1e-9) << m->name();
    }
}

TEST(HingeBending, FoldEnergyIsTwoSineHalfAngleSquared) {
    // Two right triangles sharing the edge (0,0)-(0,1), wings at u = -1 and u = +1. Folding one wing
    // by theta about the edge (no stretch) gives E = 1/2 B |e|^2/(A1+A2) (2 sin(theta/2))^2.
    ClothMesh m;
    m.restPositions = {{0, 0}, {0, 1}, {-1, 0.5}, {1, 0.5}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}};
    for (const Vec2& r : m.restPositions) m.positions.push_back(Vec3(r.x(), r.y(), 0));
    ClothMaterial mat;
    mat.bendStiffness = 0.2;
    auto model = ContinuumModel::fromMesh(m, ClothTopology::build(m).value(), mat).value();
    for (double theta : {0.0, 0.1, 1.0, 2.0, 3.0}) {
        std::vector<Vec3> x = m.positions;
        x[3] = Vec3(std::cos(theta), 0.5, std::sin(theta));
        const double expected = 0.5 * 0.2 * 1.0 / 1.0 * std::pow(2 * std::sin(theta / 2), 2);
        // Stretch and shear are zero: the fold is isometric.
        EXPECT_NEAR(model->energy(x), expected, 1e-12) << "theta " << theta;
    }
}
