#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/lod/CostModel.h"

namespace cc::lod {
namespace {

TEST(CostModel, FixedModelIsTheFormulaAndIgnoresMeasurements) {
    CostCoefficients c;
    CostModel model(CostModel::Mode::Fixed, c);
    const double newton = model.predictMs(0, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 1000, 4, 3);
    EXPECT_DOUBLE_EQ(newton, c.perUpdateMs + 1000 * c.perVertexMs[0] * 4 * 3);
    EXPECT_DOUBLE_EQ(model.predictMs(0, 2, SolverChoice::SubstepLocalGlobal, CollisionDetail::Proxies, 1000, 50, 1),
                     c.perUpdateMs + 1000 * c.perVertexMs[1] * 50);
    model.record(0, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 123.0);
    EXPECT_DOUBLE_EQ(model.predictMs(0, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 1000, 4, 3), newton);
}

TEST(CostModel, LearnedModelConvergesToMeasuredTimes) {
    CostModel model(CostModel::Mode::Learned);
    for (int i = 0; i < 200; ++i) model.record(3, 1, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 2.5);
    EXPECT_NEAR(model.predictMs(3, 1, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 10, 1, 1), 2.5, 1e-9);
    model.record(3, 1, SolverChoice::SubstepNewton, CollisionDetail::Proxies, std::nan(""));
    model.record(3, 1, SolverChoice::SubstepNewton, CollisionDetail::Proxies, -1.0);
    EXPECT_NEAR(model.predictMs(3, 1, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 10, 1, 1), 2.5, 1e-9) << "bad samples ignored";
    EXPECT_NE(model.predictMs(3, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 10, 1, 1), 2.5) << "other levels keep their seed";
}

TEST(CostModel, LearnedModelPlansForTheSpread) {
    // Alternating 1 ms and 3 ms updates: mean 2, mean absolute deviation 1 -> mean + spread x 1.
    for (double spread : {0.0, 0.5, 2.0}) {
        CostCoefficients c;
        c.spread = spread;
        CostModel model(CostModel::Mode::Learned, c);
        for (int i = 0; i < 400; ++i)
            model.record(0, 0, SolverChoice::SubstepNewton, CollisionDetail::Proxies, i % 2 ? 3.0 : 1.0);
        EXPECT_NEAR(model.predictMs(0, 0, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 10, 1, 1),
                    2.0 + spread, 0.25) << "spread " << spread;
    }
}

TEST(CostModel, EachCollisionDetailLearnsItsOwnCost) {
    // Near garments meeting the body mesh cost far more than far ones on capsules: learned apart,
    // neither moves the other's prediction.
    CostModel model(CostModel::Mode::Learned);
    for (int i = 0; i < 200; ++i) {
        model.record(1, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 0.07);
        if (i % 50 == 0) model.record(1, 2, SolverChoice::SubstepNewton, CollisionDetail::MeshContinuous, 2.1);
    }
    EXPECT_NEAR(model.predictMs(1, 2, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 100, 2, 2), 0.07, 1e-9);
    EXPECT_NEAR(model.predictMs(1, 2, SolverChoice::SubstepNewton, CollisionDetail::MeshContinuous, 100, 2, 2), 2.1,
                1e-9);
    // Unmeasured, the mesh is seeded above the capsules by the collision coefficients.
    CostCoefficients c;
    CostModel fixed(CostModel::Mode::Fixed, c);
    const double proxies = fixed.predictMs(0, 0, SolverChoice::SubstepNewton, CollisionDetail::Proxies, 100, 1, 1);
    EXPECT_DOUBLE_EQ(fixed.predictMs(0, 0, SolverChoice::SubstepNewton, CollisionDetail::Mesh, 100, 1, 1),
                     proxies + c.collisionPerUpdateMs[2] + 100 * c.collisionPerVertexMs[2]);
}

TEST(CostModel, SelfCollisionLearnsApartAndSurvivesASnapshot) {
    // Self-collision's time is learned in an entry of its own per level, seeded per vertex; the
    // update's entry of the same level does not move, and learned() / setLearned() carry both.
    CostCoefficients c;
    CostModel model(CostModel::Mode::Learned, c);
    EXPECT_DOUBLE_EQ(model.predictSelfCollisionMs(1, 4, 500), 500 * c.selfCollisionPerVertexMs);
    for (int i = 0; i < 200; ++i) {
        model.record(1, 4, SolverChoice::SubstepNewton, CollisionDetail::Mesh, 1.0);
        model.recordSelfCollision(1, 4, 3.0);
    }
    EXPECT_NEAR(model.predictSelfCollisionMs(1, 4, 500), 3.0, 1e-9);
    EXPECT_NEAR(model.predictMs(1, 4, SolverChoice::SubstepNewton, CollisionDetail::Mesh, 500, 4, 4), 1.0, 1e-9);
    EXPECT_DOUBLE_EQ(model.predictSelfCollisionMs(1, 3, 500), 500 * c.selfCollisionPerVertexMs) << "another level";

    const auto entries = model.learned();
    ASSERT_EQ(entries.size(), 2u);
    CostModel restored(CostModel::Mode::Learned, c);
    ASSERT_TRUE(restored.setLearned(entries).isOk());
    EXPECT_EQ(restored.predictSelfCollisionMs(1, 4, 500), model.predictSelfCollisionMs(1, 4, 500));
    auto bad = entries;
    for (auto& e : bad)
        if (e.selfCollision) e.collision = CollisionDetail::Mesh;  // a self-collision entry names no detail
    EXPECT_FALSE(restored.setLearned(bad).isOk());
    CostModel fixed(CostModel::Mode::Fixed, c);
    fixed.recordSelfCollision(1, 4, 3.0);
    EXPECT_DOUBLE_EQ(fixed.predictSelfCollisionMs(1, 4, 500), 500 * c.selfCollisionPerVertexMs);
}

TEST(CostModel, ValidateNamesTheField) {
    CostCoefficients c;
    c.learningRate = 0.0;
    EXPECT_NE(CostModel(CostModel::Mode::Learned, c).validate().message().find("learningRate"), std::string::npos);
    c = CostCoefficients{};
    c.spread = -1.0;
    EXPECT_NE(CostModel(CostModel::Mode::Learned, c).validate().message().find("spread"), std::string::npos);
    c = CostCoefficients{};
    c.collisionPerVertexMs[3] = std::nan("");
    EXPECT_NE(CostModel(CostModel::Mode::Learned, c).validate().message().find("collisionPer"), std::string::npos);
}

} // namespace
} // namespace cc::lod
