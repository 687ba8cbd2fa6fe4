// The core runner: the step grid and its clock, inputs on the timeline, commands at their arrival step,
// pause and step N, reset, the catch-up cap and the limits of time. Every time here is explicit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/world.hpp"

using namespace rigid_body;

namespace {

constexpr double kDt = 0.001;
constexpr double kMass = 1.0;

Nanoseconds seconds(double s) { return toNanoseconds(s); }

WorldSettings settingsWith(std::int64_t max_substeps = 1000) {
  WorldSettings settings;
  settings.dt = kDt;
  settings.max_substeps = max_substeps;
  settings.jitter_tolerance = seconds(0.01);  // as a node ticking at 100 Hz
  return settings;
}

// A 1 kg box at (0, 0, 1), at rest, no forces: its velocity is the impulse it received.
World makeWorld(const WorldSettings& settings = settingsWith()) {
  const Model model{MassProperties::box(kMass, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  State initial;
  initial.p_WB = Eigen::Vector3d(0.0, 0.0, 1.0);
  World world({BodyDefinition{model, initial, true}}, IntegratorType::kRk4, IntegratorSettings(), settings);
  world.start(0);
  return world;
}

AppliedWrench worldForce(double fx) {
  AppliedWrench wrench;
  wrench.world.force = Eigen::Vector3d(fx, 0.0, 0.0);
  return wrench;
}

double velocityX(const World& world) { return linearVelocity(world.scene().model().mass, world.scene().state()).x(); }

}  // namespace

TEST(World, WholeStepsToleratesRoundingOfTheRatio) {
  EXPECT_EQ(wholeStepsIn(0.03, 0.001), 30);  // 0.03/0.001 = 29.999999999999996 in binary
  EXPECT_EQ(wholeStepsIn(0.0299, 0.001), 29);
  EXPECT_EQ(wholeStepsIn(0.0, 0.001), 0);
  EXPECT_EQ(wholeStepsIn(-1.0, 0.001), 0);
  EXPECT_EQ(wholeStepsIn(std::numeric_limits<double>::quiet_NaN(), 0.001), 0);
  EXPECT_EQ(wholeStepsIn(1e300, 1e-300), std::int64_t(1) << 62);  // saturated, not undefined
}

TEST(World, AdvancesInWholeStepsOfTheClock) {
  World world = makeWorld();
  EXPECT_EQ(world.update(seconds(0.0105)).steps, 10);
  EXPECT_EQ(world.clockSteps(), 10);
  EXPECT_EQ(world.update(seconds(0.0109)).steps, 0);  // no new grid point
  EXPECT_FALSE(world.update(seconds(0.0109)).advanced);
  EXPECT_EQ(world.update(seconds(0.0095)).steps, 0);  // the clock went back within jitter: nothing
  EXPECT_EQ(world.clockSteps(), 10);
  EXPECT_EQ(world.update(seconds(0.02)).steps, 10);
  EXPECT_NEAR(world.scene().state().t, 0.02, 1e-15);
  EXPECT_EQ(world.stamp(), seconds(0.02));
}

TEST(World, AWrenchArrivingBetweenTwoStepsActsFromTheStepOfItsArrival) {
  World world = makeWorld();
  world.update(seconds(0.1));
  // Arrives at 0.1004 s, inside step 100 (which starts at 0.100 s): it acts from step 100 on, even though
  // the next update comes only at 0.2 s. Callbacks never integrate; the update applies it at its step.
  ASSERT_TRUE(world.setWrench(0, worldForce(1.0), seconds(0.1004)).accepted);
  EXPECT_EQ(velocityX(world), 0.0);  // nothing happened yet: no step was integrated by the command
  world.update(seconds(0.2));
  EXPECT_NEAR(velocityX(world), 0.1, 1e-12);  // F/M over the 100 steps 100…199
  // One arriving at 0.2105 s while the world stands at step 200: the old force acts on steps 200…209 and the
  // new one from step 210 to 399.
  world.update(seconds(0.2009));
  ASSERT_TRUE(world.setWrench(0, worldForce(2.0), seconds(0.2105)).accepted);
  world.update(seconds(0.4));
  EXPECT_NEAR(velocityX(world), 0.1 + 1.0 * 0.010 + 2.0 * 0.190, 1e-12);
}

TEST(World, InputActsUntilResetAndResetKeepsTheClockIncreasing) {
  World world = makeWorld();
  world.update(seconds(0.1));
  world.setWrench(0, worldForce(1.0), seconds(0.1));
  world.update(seconds(0.2));
  EXPECT_NEAR(velocityX(world), 0.1, 1e-12);
  world.reset(seconds(0.2));
  EXPECT_EQ(world.scene().state().P_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(world.scene().state().p_WB, Eigen::Vector3d(0.0, 0.0, 1.0));
  EXPECT_EQ(world.scene().input().world.force, Eigen::Vector3d::Zero());
  // The clock does not rewind: stamps keep increasing across a reset.
  EXPECT_EQ(world.clockSteps(), 200);
  const Nanoseconds before = world.stamp();
  EXPECT_EQ(world.update(seconds(0.201)).steps, 1);
  EXPECT_GT(world.stamp(), before);
}

TEST(World, ATopicWrenchTimesOutExactlyAtArrivalPlusTimeout) {
  WorldSettings settings = settingsWith();
  settings.wrench_timeout = 0.25;
  World world = makeWorld(settings);
  world.update(seconds(0.1));
  world.setWrench(0, worldForce(1.0), seconds(0.1));
  const UpdateResult result = world.update(seconds(1.0));  // one late tick: the timeout falls inside it
  ASSERT_EQ(result.timed_out.size(), 1u);
  EXPECT_TRUE(world.wrenchTimedOut(0));
  EXPECT_EQ(world.counters().wrench_timeouts, 1u);
  EXPECT_NEAR(velocityX(world), 1.0 * 0.25, 1e-12);  // acted on steps 100…349: 250 steps, not up to 1.0 s
  EXPECT_EQ(world.scene().input().world.force, Eigen::Vector3d::Zero());
  world.setWrench(0, worldForce(1.0), seconds(1.0));  // a new wrench clears the flag
  EXPECT_FALSE(world.wrenchTimedOut(0));
}

TEST(World, ATimedWrenchsImpulseIsExactToOneStep) {
  World world = makeWorld();
  world.update(seconds(0.05));
  // 0.2504 s of 2 N starting at 0.1 s: rounded to 250 whole steps, so the impulse is 2 N · 0.250 s.
  ASSERT_TRUE(world.applyWrench(0, worldForce(2.0), seconds(0.1), 0.2504, seconds(0.05)).accepted);
  world.update(seconds(0.12));
  EXPECT_NEAR(velocityX(world), 2.0 * 0.020, 1e-12);  // steps 100…119 so far
  world.update(seconds(1.0));
  EXPECT_NEAR(velocityX(world), 2.0 * 0.250, 1e-12);
  // A second, open-ended one sums with nothing left, and clear_wrenches ends it.
  world.applyWrench(0, worldForce(1.0), 0, -1.0, seconds(1.0));
  world.update(seconds(1.1));
  world.clearWrenches(seconds(1.1));
  world.update(seconds(2.0));
  EXPECT_NEAR(velocityX(world), 0.5 + 0.1, 1e-12);
}

TEST(World, StepsBeyondTheSubstepCapAreDroppedAndCounted) {
  World world = makeWorld(settingsWith(50));
  const UpdateResult result = world.update(seconds(0.2));  // 200 due after a "stall"
  EXPECT_EQ(result.steps, 50);
  EXPECT_EQ(result.dropped, 150);
  EXPECT_EQ(world.counters().dropped_steps, 150u);
  EXPECT_EQ(world.clockSteps(), 200);
  EXPECT_NEAR(world.scene().state().t, 0.05, 1e-15);  // the body lived through 50 steps only
}

TEST(World, TheCatchUpCapCountsBodySteps) {
  WorldSettings settings = settingsWith(1000);
  settings.max_body_steps_per_tick = 300;  // 3 bodies: at most 100 steps each per update
  const Model model{MassProperties::sphere(1.0, 0.1), ForceModel{}};
  World world(std::vector<BodyDefinition>(3, BodyDefinition{model, State(), true}), IntegratorType::kRk4,
              IntegratorSettings(), settings);
  world.start(0);
  const UpdateResult result = world.update(seconds(0.5));
  EXPECT_EQ(result.steps, 100);
  EXPECT_EQ(result.dropped, 400);
}

TEST(World, AFailedStepKeepsTheLastGoodState) {
  World world = makeWorld();
  world.update(seconds(0.01));
  const State good = world.scene().state();
  // A non-finite wrench never reaches the scene: the core refuses it at the command.
  AppliedWrench bad;
  bad.world.torque = Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.0, 0.0);
  EXPECT_FALSE(world.setWrench(0, bad, seconds(0.01)).accepted);
  // A finite one whose momentum overflows within the step latches the divergence with the last good state.
  AppliedWrench huge;
  huge.world.force = Eigen::Vector3d(1e308, 0.0, 0.0);
  ASSERT_TRUE(world.setWrench(0, huge, seconds(0.01)).accepted);
  for (int k = 2; k < 400 && !world.update(seconds(0.01 * k)).diverged; ++k) {
  }
  EXPECT_EQ(world.scene().divergence(), Divergence::kNonFiniteState);
  EXPECT_TRUE(isFinite(world.scene().state()));
  EXPECT_GT(world.scene().state().t, good.t);
}

TEST(World, RefusesInvalidConstruction) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d::Ones()), ForceModel{}};
  const auto make = [&](const State& state, const WorldSettings& settings) {
    return World({BodyDefinition{model, state, true}}, IntegratorType::kRk4, IntegratorSettings(), settings);
  };
  WorldSettings zero_dt = settingsWith();
  zero_dt.dt = 0.0;
  EXPECT_THROW(make(State(), zero_dt), std::invalid_argument);
  WorldSettings tiny_dt = settingsWith();
  tiny_dt.dt = 1e-300;  // below the clock's nanosecond
  EXPECT_THROW(make(State(), tiny_dt), std::invalid_argument);
  EXPECT_THROW(make(State(), settingsWith(0)), std::invalid_argument);
  State nan_state;
  nan_state.p_WB.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(make(nan_state, settingsWith()), std::invalid_argument);
}

TEST(World, PausedTheClockRunsAndTheStateHoldsAndStepTakesExactlyNSteps) {
  World world = makeWorld(settingsWith(100));  // a cap below the requested N: step N is not capped
  world.setWrench(0, worldForce(1.0), 0);
  world.update(seconds(0.1));
  const State before = world.scene().state();
  world.pause(seconds(0.1));
  EXPECT_EQ(world.update(seconds(5.0)).steps, 0);  // 4900 steps due, none integrated and none "dropped"
  EXPECT_EQ(world.counters().dropped_steps, 0u);
  EXPECT_EQ(world.clockSteps(), 5000);
  EXPECT_EQ(world.scene().state().P_W, before.P_W);
  ASSERT_TRUE(world.step(370, seconds(5.0)).accepted);  // exactly N steps, the clock untouched
  EXPECT_EQ(world.clockSteps(), 5000);
  EXPECT_EQ(world.scene().integratedSteps(), 470);
  EXPECT_NEAR(world.scene().state().P_W.x() - before.P_W.x(), 370 * kDt, 1e-12);
  world.unpause(seconds(5.0));
  EXPECT_FALSE(world.step(1, seconds(5.0)).accepted);  // not paused
  EXPECT_EQ(world.update(seconds(5.01)).steps, 10);
}

TEST(World, WithItsOwnClockStepNMovesTheClockByNWhateverTheCap) {
  WorldSettings settings = settingsWith(100);
  settings.owns_clock = true;
  settings.start_paused = true;
  World world = makeWorld(settings);
  world.setWrench(0, worldForce(1.0), world.stamp());
  ASSERT_TRUE(world.step(5000, world.stamp()).accepted);  // 50 times the cap: exactly 5000 steps
  EXPECT_EQ(world.clockSteps(), 5000);
  EXPECT_EQ(world.scene().integratedSteps(), 5000);
  EXPECT_NEAR(velocityX(world), 5.0, 1e-9);
  EXPECT_EQ(world.stamp(), seconds(5.0));
  // Paused, our own time stands still.
  world.update(world.timeOfStep(world.clockSteps() + 10));
  EXPECT_EQ(world.clockSteps(), 5000);
  // A timed wrench on our own timeline: acts over its steps while step N passes them.
  world.clearWrenches(world.stamp());
  world.applyWrench(0, worldForce(-1.0), 0, 0.25, world.stamp());
  ASSERT_TRUE(world.step(1000, world.stamp()).accepted);
  EXPECT_NEAR(velocityX(world), 5.0 - 0.25, 1e-9);
  // rewind: time and state back to the start.
  ASSERT_TRUE(world.rewind().accepted);
  EXPECT_EQ(world.clockSteps(), 0);
  EXPECT_EQ(velocityX(world), 0.0);
}

TEST(World, StepRequestsAreBoundedInBodySteps) {
  WorldSettings settings = settingsWith();
  settings.max_body_steps_per_request = 1000;
  settings.start_paused = true;
  World world = makeWorld(settings);
  const CommandReply refused = world.step(1001, 0);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.message.find("at most 1000 steps"), std::string::npos) << refused.message;
  EXPECT_FALSE(world.step(std::numeric_limits<std::int64_t>::max(), 0).accepted);
  EXPECT_FALSE(world.step(0, 0).accepted);
  EXPECT_FALSE(world.step(-5, 0).accepted);
  EXPECT_EQ(world.scene().integratedSteps(), 0);
  EXPECT_TRUE(world.step(1000, 0).accepted);
}

TEST(World, AStepRequestStopsAtItsWallTimeBudgetWhereItGotToAndTheRestContinuesTheSameRun) {
  // A wall clock that advances 0.1 s at every reading, against a budget of 0.25 s: the request stops after
  // the second chunk (readings at 0.1 and 0.2 s after its start; a third, taking 0.1 s as each did, would
  // end 0.3 s after it, past the budget), each chunk kRequestChunkBodySteps steps of this one body.
  for (const bool owns_clock : {false, true}) {
    Nanoseconds wall = 0;
    WorldSettings settings = settingsWith();
    settings.owns_clock = owns_clock;
    settings.start_paused = true;
    settings.max_request_seconds = 0.25;
    settings.wall_clock = [&wall] { return wall += seconds(0.1); };
    World budgeted = makeWorld(settings);
    budgeted.setWrench(0, worldForce(1.0), budgeted.stamp());
    const std::int64_t steps = 10 * kRequestChunkBodySteps + 7;
    const CommandReply stopped = budgeted.step(steps, budgeted.stamp());
    EXPECT_FALSE(stopped.accepted);
    const std::int64_t done = 2 * kRequestChunkBodySteps;
    EXPECT_NE(stopped.message.find("stopped after " + std::to_string(done) + " of " + std::to_string(steps) + " steps"),
              std::string::npos)
        << stopped.message;
    EXPECT_EQ(budgeted.scene().integratedSteps(), done);
    EXPECT_EQ(budgeted.clockSteps(), owns_clock ? done : 0);
    // The rest, in requests within the budget, ends where one uninterrupted request ends, bit for bit.
    for (std::int64_t left = steps - done; left > 0; left -= 2 * kRequestChunkBodySteps) {
      ASSERT_TRUE(budgeted.step(std::min(left, 2 * kRequestChunkBodySteps), budgeted.stamp()).accepted);
    }
    settings.wall_clock = nullptr;
    settings.max_request_seconds = std::numeric_limits<double>::infinity();
    World whole = makeWorld(settings);
    whole.setWrench(0, worldForce(1.0), whole.stamp());
    ASSERT_TRUE(whole.step(steps, whole.stamp()).accepted);
    EXPECT_EQ(budgeted.scene().integratedSteps(), steps);
    EXPECT_EQ(budgeted.scene().state().p_WB, whole.scene().state().p_WB);
    EXPECT_EQ(budgeted.scene().state().P_W, whole.scene().state().P_W);
    EXPECT_EQ(budgeted.clockSteps(), whole.clockSteps());
    EXPECT_NEAR(velocityX(whole), steps * kDt, 1e-9);  // F = 1 N on 1 kg over every step
  }
  WorldSettings settings = settingsWith();
  settings.max_request_seconds = 0.0;
  EXPECT_THROW(makeWorld(settings), std::invalid_argument);
  settings.max_request_seconds = std::nan("");
  EXPECT_THROW(makeWorld(settings), std::invalid_argument);
}

TEST(World, AStepRequestOnASceneWithManyCollidersReadsTheClockAfterEveryStep) {
  // 16 boxes resting apart on the ground: 16 × kColliderChunkWeight body-steps a step, so a chunk is one
  // step and a request against a 0.25 s budget, with a clock that advances 0.1 s a reading (the update
  // before the request reads 0.1 s, the request's budget starts at 0.2 s and ends at 0.45 s), stops after
  // the second step: the third would take 0.1 s as the second did and end at 0.5 s, past the budget (a chunk
  // of kMinChunkSteps would run 16 steps between readings: over a second for a pile).
  Nanoseconds wall = 0;
  WorldSettings settings = settingsWith();
  settings.start_paused = true;
  settings.max_request_seconds = 0.25;
  settings.wall_clock = [&wall] { return wall += seconds(0.1); };
  ContactSetup contact;
  CollisionShape ground;
  ground.type = ShapeType::kPlane;
  contact.environment = {ground};
  std::vector<BodyDefinition> boxes;
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  for (int i = 0; i < 16; ++i) {
    CollisionShape box;
    box.type = ShapeType::kBox;
    box.size = size;
    contact.bodies.push_back(box);
    State initial;
    initial.p_WB = Eigen::Vector3d(0.5 * i, 0.0, 0.1);
    boxes.push_back(BodyDefinition{Model{MassProperties::box(kMass, size), ForceModel{}}, initial, true});
  }
  World world(boxes, IntegratorType::kRk4, IntegratorSettings(), settings, StepAssembly::kLeaveOut, contact);
  world.start(0);
  const CommandReply stopped = world.step(100, world.stamp());
  EXPECT_FALSE(stopped.accepted);
  EXPECT_NE(stopped.message.find("stopped after 2 of 100 steps"), std::string::npos) << stopped.message;
  EXPECT_EQ(world.scene().integratedSteps(0), 2);
}

TEST(World, AnUpdatePastItsWallTimeBudgetDropsTheRestOfItsStepsAndTheNextOneGoesOn) {
  // A wall clock that advances 0.1 s at every reading, against an update budget of 0.25 s (deadline 0.35 s
  // after the first reading at 0.1 s): an update 5 s late integrates two chunks of kRequestChunkBodySteps
  // (readings at 0.2 and 0.3 s; a third, taking 0.1 s as each did, would end at 0.4 s, past the deadline)
  // and lets the rest pass without motion, counted as dropped.
  Nanoseconds wall = 0;
  WorldSettings settings = settingsWith(100000);  // the catch-up cap out of the way
  settings.max_tick_seconds = 0.25;
  settings.wall_clock = [&wall] { return wall += seconds(0.1); };
  World world = makeWorld(settings);
  world.setWrench(0, worldForce(1.0), 0);
  const UpdateResult late = world.update(seconds(5.0));
  const std::int64_t done = 2 * kRequestChunkBodySteps;
  EXPECT_EQ(late.steps, done);
  EXPECT_EQ(late.dropped, 5000 - done);
  EXPECT_EQ(world.counters().dropped_steps, static_cast<std::uint64_t>(5000 - done));
  EXPECT_EQ(world.clockSteps(), 5000);  // the clock is the caller's: it moved on
  EXPECT_NEAR(velocityX(world), done * kDt, 1e-9);  // F = 1 N on 1 kg over the steps integrated only
  // The next tick's 10 steps fit into its own budget.
  const UpdateResult next = world.update(seconds(5.01));
  EXPECT_EQ(next.steps, 10);
  EXPECT_EQ(next.dropped, 0);
  // Without a budget the same late update integrates every step.
  settings.max_tick_seconds = std::numeric_limits<double>::infinity();
  World unlimited = makeWorld(settings);
  unlimited.setWrench(0, worldForce(1.0), 0);
  EXPECT_EQ(unlimited.update(seconds(5.0)).steps, 5000);
  // A world with its own clock (lockstep) never drops steps for wall time.
  settings.max_tick_seconds = 1e-9;
  settings.owns_clock = true;
  World own = makeWorld(settings);
  EXPECT_EQ(own.update(own.timeOfStep(3000)).steps, 3000);
  settings.max_tick_seconds = -1.0;
  EXPECT_THROW(makeWorld(settings), std::invalid_argument);
}

TEST(World, ReanchoringAfterABackwardJumpContinuesTheClockWithoutNegativeSteps) {
  WorldSettings settings = settingsWith();
  settings.dt = 0.01;
  settings.jitter_tolerance = seconds(0.1);
  World world = makeWorld(settings);
  EXPECT_EQ(world.update(seconds(1.0)).steps, 100);
  const UpdateResult jump = world.update(seconds(0.2));  // time went back to 0.2 s
  EXPECT_TRUE(jump.reanchored);
  EXPECT_EQ(world.counters().backward_time_jumps, 1u);
  EXPECT_EQ(world.stamp(), seconds(0.2));  // the current state, at the new time
  EXPECT_EQ(world.update(seconds(0.15)).steps, 0);  // before the anchor, within the jitter: nothing, no negative step
  EXPECT_EQ(world.counters().backward_time_jumps, 1u);
  EXPECT_EQ(world.update(seconds(0.2)).steps, 0);
  EXPECT_EQ(world.update(seconds(0.25)).steps, 5);
  EXPECT_EQ(world.clockSteps(), 105);
  EXPECT_NEAR(world.scene().state().t, 1.05, 1e-12);
}

TEST(World, TheClockStopsCleanlyAtTheEndOfRepresentableTime) {
  WorldSettings settings = settingsWith();
  settings.end_of_time = seconds(10.0);
  World world = makeWorld(settings);
  world.start(seconds(9.0));
  const UpdateResult result = world.update(std::numeric_limits<Nanoseconds>::max());  // far past the end
  EXPECT_TRUE(result.end_of_time);
  EXPECT_TRUE(world.endOfTime());
  EXPECT_EQ(world.clockSteps(), 1000);
  EXPECT_EQ(world.stamp(), seconds(10.0));
  EXPECT_EQ(world.update(std::numeric_limits<Nanoseconds>::max()).steps, 0);  // stays, never wraps
  EXPECT_EQ(world.timeOfStep(std::numeric_limits<std::int64_t>::max()), seconds(10.0));  // saturated
  // With its own clock, a step past the end is refused and nothing moves.
  settings.owns_clock = true;
  settings.start_paused = true;
  World own = makeWorld(settings);
  EXPECT_FALSE(own.step(10001, 0).accepted);
  EXPECT_EQ(own.clockSteps(), 0);
  EXPECT_TRUE(own.step(10000, 0).accepted);
  EXPECT_EQ(own.stamp(), seconds(10.0));
}

TEST(World, TheCommandQueueIsBoundedAndALaterWrenchOnTheSameStepReplacesAWaitingOne) {
  WorldSettings settings = settingsWith();
  settings.max_pending_commands = 3;
  World world = makeWorld(settings);
  world.update(seconds(0.01));
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(world.setWrench(0, worldForce(i), seconds(0.0201)).accepted);
  EXPECT_EQ(world.pendingCommands(), 1u);  // same step: latest wins while waiting
  EXPECT_TRUE(world.pause(seconds(0.03)).accepted);
  EXPECT_TRUE(world.unpause(seconds(0.04)).accepted);
  EXPECT_FALSE(world.reset(seconds(0.05)).accepted);  // the fourth one waiting: refused and counted
  EXPECT_EQ(world.counters().refused_commands, 1u);
  world.update(seconds(0.1));
  EXPECT_EQ(world.pendingCommands(), 0u);
  // 99 N from step 20, paused over steps 30…39: 70 steps of it.
  EXPECT_NEAR(velocityX(world), 99.0 * 0.070, 1e-9);
}

TEST(World, ResetForgetsDopri5sMemory) {
  // dopri5 keeps its last internal step between calls. After a reset the run must be the run of a fresh
  // world, bit for bit: nothing of the trajectory before the reset may leak into the one after it.
  const Model model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  const State spinning = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                             Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(0.3, 2.0, 0.1));
  const auto make = [&] {
    World world({BodyDefinition{model, spinning, true}}, IntegratorType::kDopri5, IntegratorSettings(), settingsWith());
    world.start(0);
    return world;
  };
  World used = make(), fresh = make();
  used.setWrench(0, worldForce(1.0), 0);
  used.update(seconds(0.7));
  used.reset(seconds(0.7));
  for (int k = 1; k <= 50; ++k) {
    used.update(seconds(0.7 + 0.01 * k));
    fresh.update(seconds(0.01 * k));
  }
  const State& a = used.scene().state();
  const State& b = fresh.scene().state();
  EXPECT_EQ(a.q_WB.coeffs(), b.q_WB.coeffs());
  EXPECT_EQ(a.p_WB, b.p_WB);
  EXPECT_EQ(a.L_W, b.L_W);
}

TEST(World, TimeoutsOfSeveralBodiesEachExpireAtTheirOwnStep) {
  // Three bodies, wrenches arriving at different times, one timeout: each body's wrench acts from its own
  // arrival to its own arrival + timeout, also when the expiries fall inside one late update.
  WorldSettings settings = settingsWith();
  settings.wrench_timeout = 0.1;
  const Model model{MassProperties::sphere(1.0, 0.1), ForceModel{}};
  World world(std::vector<BodyDefinition>(3, BodyDefinition{model, State(), true}), IntegratorType::kRk4,
              IntegratorSettings(), settings);
  world.start(0);
  world.setWrench(0, worldForce(1.0), seconds(0.0));
  world.update(seconds(0.02));
  world.setWrench(1, worldForce(1.0), seconds(0.02));
  world.setWrench(2, worldForce(1.0), seconds(0.05));  // arrives between updates: waits for its step
  world.setWrench(0, worldForce(1.0), seconds(0.05));  // renews body 0's wrench (and its timeout)
  const UpdateResult late = world.update(seconds(1.0));
  EXPECT_EQ(late.timed_out.size(), 3u);
  const auto v = [&](std::size_t body) { return linearVelocity(model.mass, world.scene().state(body)).x(); };
  EXPECT_NEAR(v(0), 0.15, 1e-12);  // steps 0…149: the renewal at 0.05 s moved its expiry to 0.15 s
  EXPECT_NEAR(v(1), 0.10, 1e-12);  // steps 20…119
  EXPECT_NEAR(v(2), 0.10, 1e-12);  // steps 50…149
  EXPECT_EQ(world.counters().wrench_timeouts, 3u);
  world.setWrench(1, worldForce(2.0), seconds(1.0));  // a body can be scheduled again after it expired
  world.update(seconds(1.5));
  EXPECT_NEAR(v(1), 0.10 + 0.2, 1e-12);
}
