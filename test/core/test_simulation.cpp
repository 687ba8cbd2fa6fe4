#include <gtest/gtest.h>

#include <limits>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/simulation.hpp"

using namespace rigid_body;

namespace {
Simulation makeSimulation(std::int64_t max_substeps = 1000) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  State initial;
  initial.p_WB = Eigen::Vector3d(0.0, 0.0, 1.0);
  return Simulation(model, initial, IntegratorType::kRk4, 0.001, max_substeps);
}
}  // namespace

TEST(Simulation, WholeStepsToleratesRoundingOfTheRatio) {
  EXPECT_EQ(wholeStepsIn(0.03, 0.001), 30);  // 0.03/0.001 = 29.999999999999996 in binary
  EXPECT_EQ(wholeStepsIn(0.0299, 0.001), 29);
  EXPECT_EQ(wholeStepsIn(0.0, 0.001), 0);
  EXPECT_EQ(wholeStepsIn(-1.0, 0.001), 0);
  EXPECT_EQ(wholeStepsIn(std::numeric_limits<double>::quiet_NaN(), 0.001), 0);
}

TEST(Simulation, AdvancesInWholeStepsOfTheClock) {
  Simulation sim = makeSimulation();
  EXPECT_EQ(sim.advanceTo(0.0105).steps, 10);
  EXPECT_EQ(sim.clockSteps(), 10);
  EXPECT_EQ(sim.advanceTo(0.0109).steps, 0);  // no new grid point
  EXPECT_EQ(sim.advanceTo(0.005).steps, 0);   // the clock went back: nothing, and no negative step
  EXPECT_EQ(sim.clockSteps(), 10);
  EXPECT_EQ(sim.advanceTo(0.02).steps, 10);
  EXPECT_NEAR(sim.state().t, 0.02, 1e-15);
}

TEST(Simulation, InputActsFromTheNextStepAndResetClearsIt) {
  Simulation sim = makeSimulation();
  sim.advanceTo(0.1);
  AppliedWrench push;
  push.world.force = Eigen::Vector3d(1.0, 0.0, 0.0);
  sim.setInput(push);
  sim.advanceTo(0.2);
  // Δv = F/M Δt over the 100 steps after the input.
  EXPECT_NEAR(linearVelocity(sim.model().mass, sim.state()).x(), 0.1, 1e-12);
  sim.reset();
  EXPECT_EQ(sim.state().P_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(sim.state().p_WB, Eigen::Vector3d(0.0, 0.0, 1.0));
  EXPECT_EQ(sim.input().world.force, Eigen::Vector3d::Zero());
  // The clock does not rewind: published times keep increasing across a reset.
  EXPECT_EQ(sim.clockSteps(), 200);
  EXPECT_EQ(sim.advanceTo(0.201).steps, 1);
}

TEST(Simulation, StepsBeyondTheSubstepCapAreDroppedAndCounted) {
  Simulation sim = makeSimulation(50);
  const AdvanceResult result = sim.advanceTo(0.2);  // 200 due after a "stall"
  EXPECT_EQ(result.steps, 50);
  EXPECT_EQ(result.dropped, 150);
  EXPECT_EQ(sim.droppedSteps(), 150);
  EXPECT_EQ(sim.clockSteps(), 200);
  EXPECT_NEAR(sim.state().t, 0.05, 1e-15);  // the body lived through 50 steps only
}

TEST(Simulation, AFailedStepKeepsTheLastGoodState) {
  Simulation sim = makeSimulation();
  sim.advanceTo(0.01);
  const State good = sim.state();
  AppliedWrench bad;
  bad.world.torque = Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.0, 0.0);
  sim.setInput(bad);
  const AdvanceResult result = sim.advanceTo(0.02);
  EXPECT_EQ(result.status, StepStatus::kNonFinite);
  EXPECT_EQ(result.steps, 0);
  EXPECT_TRUE(isFinite(sim.state()));
  EXPECT_EQ(sim.state().t, good.t);
}

TEST(Simulation, RefusesInvalidConstruction) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d::Ones()), ForceModel{}};
  EXPECT_THROW(Simulation(model, State(), IntegratorType::kRk4, 0.0, 10), std::invalid_argument);
  EXPECT_THROW(Simulation(model, State(), IntegratorType::kRk4, 0.001, 0), std::invalid_argument);
  State nan_state;
  nan_state.p_WB.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Simulation(model, nan_state, IntegratorType::kRk4, 0.001, 10), std::invalid_argument);
}

TEST(Simulation, PausedTheClockRunsAndTheStateHoldsAndStepNowStillSteps) {
  Simulation sim = makeSimulation();
  AppliedWrench push;
  push.world.force = Eigen::Vector3d(1.0, 0.0, 0.0);
  sim.setInput(push);
  sim.advanceTo(0.1);
  const State before = sim.state();
  sim.setPaused(true);
  EXPECT_EQ(sim.advanceTo(5.0).steps, 0);  // 4900 steps due, none integrated and none "dropped"
  EXPECT_EQ(sim.droppedSteps(), 0);
  EXPECT_EQ(sim.clockSteps(), 5000);
  EXPECT_EQ(sim.state().P_W, before.P_W);
  EXPECT_EQ(sim.stepNow(37).steps, 37);  // exactly N steps, the clock untouched
  EXPECT_EQ(sim.clockSteps(), 5000);
  EXPECT_EQ(sim.integratedSteps(), 137);
  EXPECT_NEAR(sim.state().P_W.x() - before.P_W.x(), 37 * 0.001, 1e-12);
  sim.setPaused(false);
  EXPECT_EQ(sim.advanceTo(5.01).steps, 10);
  sim.rewindClock();
  EXPECT_EQ(sim.clockSteps(), 0);
  EXPECT_EQ(sim.advanceTo(0.002).steps, 2);
}
