// Bad input and blow-ups in the core: wrench limits without overflow, the divergence latch, re-anchoring.
#include <gtest/gtest.h>

#include <limits>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/world.hpp"
#include "rigid_body_sim/wrench_limits.hpp"

using namespace rigid_body;

TEST(WrenchLimits, VerdictsByReason) {
  WrenchLimits limits;
  limits.max_force = 10.0;
  limits.max_torque = 1.0;
  Wrench wrench;
  wrench.force = Eigen::Vector3d(6.0, 8.0, 0.0);  // |F| = 10: on the limit, accepted
  EXPECT_EQ(checkWrench(wrench, limits), WrenchVerdict::kAccepted);
  wrench.force.z() = 0.1;
  EXPECT_EQ(checkWrench(wrench, limits), WrenchVerdict::kForceOverLimit);
  wrench.force.setZero();
  wrench.torque = Eigen::Vector3d(0.0, 0.0, -1.5);
  EXPECT_EQ(checkWrench(wrench, limits), WrenchVerdict::kTorqueOverLimit);
  wrench.torque.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(checkWrench(wrench, limits), WrenchVerdict::kNonFinite);
  EXPECT_STREQ(verdictName(WrenchVerdict::kForceOverLimit), "force_over_limit");
}

TEST(WrenchLimits, HugeComponentsDoNotOverflowIntoInfinity) {
  Wrench wrench;
  wrench.force = Eigen::Vector3d(1e308, 1e308, 1e308);  // |F|² would overflow; |F| = 1.7e308 does not
  EXPECT_EQ(checkWrench(wrench, WrenchLimits()), WrenchVerdict::kAccepted);  // no limit set: accepted
  WrenchLimits limits;
  limits.max_force = 1e308;
  EXPECT_EQ(checkWrench(wrench, limits), WrenchVerdict::kForceOverLimit);  // and compared, not Inf > Inf
}

namespace {

Nanoseconds seconds(double s) { return toNanoseconds(s); }

World makeWorld(const Model& model, const State& start, IntegratorType type, double dt) {
  WorldSettings settings;
  settings.dt = dt;
  settings.max_energy_growth = 2.0;
  World world({BodyDefinition{model, start, true}}, type, IntegratorSettings(), settings);
  world.start(0);
  return world;
}

World thinRod(IntegratorType type) {
  // A fast thin rod: ω₁ = 100 rad/s about the long axis with a transverse wobble. Its kinetic energy is
  // constant in truth and may rise toward G²/(2 I_min), 10⁴ times more, under a method that fails.
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1e-4, 1, 1).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  const State start = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d(100, 5, 0));
  return makeWorld(model, start, type, 0.05);
}

}  // namespace

TEST(Divergence, EnergyBlowUpIsLatchedWithTheLastGoodStateAndResetRecovers) {
  World sim = thinRod(IntegratorType::kExplicitEuler);  // |ω|h = 5: far beyond explicit Euler's reach
  const State start = sim.scene().state();
  const UpdateResult result = sim.update(seconds(0.05));
  EXPECT_TRUE(result.diverged);
  EXPECT_EQ(sim.scene().divergence(), Divergence::kEnergyGrowth);
  EXPECT_EQ(sim.scene().state().L_W, start.L_W);  // the last good state: the one before the tick
  EXPECT_EQ(sim.scene().state().q_WB.coeffs(), start.q_WB.coeffs());
  // Frozen: the clock advances, the state does not.
  EXPECT_EQ(sim.update(seconds(0.5)).steps, 0);
  EXPECT_EQ(sim.clockSteps(), 10);
  EXPECT_EQ(sim.scene().state().t, start.t);
  sim.reset(seconds(0.5));
  EXPECT_EQ(sim.scene().divergence(), Divergence::kNone);
}

TEST(Divergence, AStableMethodOnTheSameRodDoesNotTrip) {
  // The splitting turns the rod exactly about its axes: energy bounded, no false alarm over 200 ticks.
  World sim = thinRod(IntegratorType::kSymplecticSplitting);
  for (int k = 1; k <= 200; ++k) ASSERT_FALSE(sim.update(seconds(0.05 * k)).diverged) << k;
  EXPECT_EQ(sim.scene().divergence(), Divergence::kNone);
}

TEST(Divergence, FallingUnderGravityIsNotABlowUp) {
  // Explicit Euler gains O(h) of gravity's work: from rest, 1/n of it in a tick of n steps (0.1 here), less
  // later. That is inside the budget (E + |W_g|)·(growth − 1) at the node's default growth of 2.
  Model model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  model.forces.gravity_W = Eigen::Vector3d(0, 0, -9.81);
  World sim = makeWorld(model, State(), IntegratorType::kExplicitEuler, 0.001);
  for (int k = 1; k <= 500; ++k) ASSERT_FALSE(sim.update(seconds(0.01 * k)).diverged) << k;
}

TEST(Divergence, StiffDampingWithAnExplicitMethodTrips) {
  // c/m = 1000 1/s at h = 10 ms: explicit Euler multiplies v by (1 − 10) a step. Damping only removes
  // energy, so any growth is numerical.
  Model model{MassProperties::sphere(1.0, 0.5), ForceModel{}};
  model.forces.linear_damping = 1000.0;
  State start;
  start.P_W = Eigen::Vector3d(1, 0, 0);
  World sim = makeWorld(model, start, IntegratorType::kExplicitEuler, 0.01);
  EXPECT_TRUE(sim.update(seconds(0.01)).diverged);
  EXPECT_EQ(sim.scene().state().P_W, start.P_W);
}

TEST(Divergence, OverflowOfTheMomentumIsANonFiniteStateNotANaNOnTheWire) {
  World sim = makeWorld(Model{MassProperties::box(1.0, Eigen::Vector3d::Ones()), ForceModel{}}, State(),
                        IntegratorType::kRk4, 0.001);
  AppliedWrench huge;
  huge.world.force = Eigen::Vector3d(1e308, 0, 0);  // accepted when no limit is set
  ASSERT_TRUE(sim.setWrench(0, huge, 0).accepted);
  // 1e305 kg m/s a step: the momentum overflows after ~1800 steps.
  UpdateResult result;
  for (int k = 1; k <= 300 && !result.diverged; ++k) result = sim.update(seconds(0.01 * k));
  EXPECT_TRUE(result.diverged);
  EXPECT_EQ(sim.scene().divergence(), Divergence::kNonFiniteState);
  EXPECT_TRUE(isFinite(sim.scene().state()));
}
