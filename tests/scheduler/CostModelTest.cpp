#include <gtest/gtest.h>

#include "crowdcloth/lod/CostModel.h"

namespace cc::lod {
namespace {

TEST(CostModel, FixedModelIsTheFormulaAndIgnoresMeasurements) {
    CostCoefficients c;
    CostModel model(CostModel::Mode::Fixed, c);
    const double newton = model.predictMs(0, 2, SolverChoice::SubstepNewton, 1000, 4, 3);
    EXPECT_DOUBLE_EQ(newton, c.perUpdateMs + 1000 * c.perVertexMs[0] * 4 * 3);
    EXPECT_DOUBLE_EQ(model.predictMs(0, 2, SolverChoice::SubstepLocalGlobal, 1000, 50, 1),
                     c.perUpdateMs + 1000 * c.perVertexMs[1] * 50);
    model.record(0, 2, SolverChoice::SubstepNewton, 123.0);
    EXPECT_DOUBLE_EQ(model.predictMs(0, 2, SolverChoice::SubstepNewton, 1000, 4, 3), newton);
}

TEST(CostModel, LearnedModelConvergesToMeasuredTimes) {
    CostModel model(CostModel::Mode::Learned);
    for (int i = 0; i < 200; ++i) model.record(3, 1, SolverChoice::SubstepNewton, 2.5);
    EXPECT_NEAR(model.predictMs(3, 1, SolverChoice::SubstepNewton, 10, 1, 1), 2.5, 1e-9);
    model.record(3, 1, SolverChoice::SubstepNewton, std::nan(""));
    model.record(3, 1, SolverChoice::SubstepNewton, -1.0);
    EXPECT_NEAR(model.predictMs(3, 1, SolverChoice::SubstepNewton, 10, 1, 1), 2.5, 1e-9) << "bad samples ignored";
    EXPECT_NE(model.predictMs(3, 2, SolverChoice::SubstepNewton, 10, 1, 1), 2.5) << "other levels keep their seed";
}

TEST(CostModel, LearnedModelPlansForTheSpread) {
    CostModel model(CostModel::Mode::Learned);
    // Alternating 1 ms and 3 ms updates: mean 2, mean absolute deviation 1 -> predicts ~4 ms.
    for (int i = 0; i < 400; ++i) model.record(0, 0, SolverChoice::SubstepNewton, i % 2 ? 3.0 : 1.0);
    EXPECT_NEAR(model.predictMs(0, 0, SolverChoice::SubstepNewton, 10, 1, 1), 4.0, 0.25);
}

TEST(CostModel, ValidateNamesTheField) {
    CostCoefficients c;
    c.learningRate = 0.0;
    EXPECT_NE(CostModel(CostModel::Mode::Learned, c).validate().message().find("learningRate"), std::string::npos);
}

} // namespace
} // namespace cc::lod
