// Sleeping (docs/contact.md, "Sleeping"): an island at rest sleeps after the sleep time and then holds its
// state exactly; a new wrench, a set state, a changed force model, a body that reaches it and a contact
// report that starts being read each wake it at once, the whole island and only it; a block creeping near
// the friction angle never sleeps; and the trajectories with and without sleeping agree within the slop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../../src/contact/collision_world.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
constexpr double kH = 1e-3;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
const Eigen::Vector3d kBox(0.3, 0.3, 0.2);

ContactSettings sleeping(bool on) {
  ContactSettings settings;
  settings.sleep = on;
  return settings;
}

BodyDefinition box(const Eigen::Vector3d& p, const Eigen::Vector3d& v = Eigen::Vector3d::Zero(),
                   const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  BodyDefinition body = reference::contactBody(MassProperties::box(1.0, kBox), p, q, v, Eigen::Vector3d::Zero(), kDown);
  body.takes_input = true;
  return body;
}

// Stacks of `height` boxes on the ground at x = 0, 1, 2, … (touching, at rest), plus `extra` bodies.
Scene stacks(int count, int height, bool sleep, std::vector<BodyDefinition> extra = {},
             std::vector<CollisionShape> extra_shapes = {}, double h = kH) {
  ContactSetup setup;
  setup.settings = sleeping(sleep);
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
  std::vector<BodyDefinition> bodies;
  for (int s = 0; s < count; ++s) {
    for (int i = 0; i < height; ++i) {
      bodies.push_back(box(Eigen::Vector3d(1.0 * s, 0, 0.1 + 0.2 * i)));
      setup.bodies.push_back(reference::collisionShape(ShapeType::kBox, kBox, 0.5, 0.0));
    }
  }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    bodies.push_back(extra[i]);
    setup.bodies.push_back(extra_shapes[i]);
  }
  return Scene(bodies, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

std::int64_t steps(double seconds) { return static_cast<std::int64_t>(std::llround(seconds / kH)); }

// Steps until every body sleeps (or `limit` seconds); returns the time it took [s], or infinity.
double stepUntilAsleep(Scene& scene, std::int64_t bodies, double limit) {
  for (std::int64_t i = 1; i <= steps(limit); ++i) {
    scene.step(1);
    if (scene.contactStatistics().sleeping_bodies == bodies) return static_cast<double>(i) * kH;
  }
  return INFINITY;
}

double largestDistance(const Scene& a, const Scene& b) {
  double largest = 0.0;
  for (std::size_t body = 0; body < a.bodyCount(); ++body) {
    largest = std::max(largest, (a.state(body).p_WB - b.state(body).p_WB).norm());
  }
  return largest;
}

}  // namespace

TEST(Sleeping, ABoxAtRestSleepsAfterTheSleepTimeAndThenHoldsItsStateBitForBit) {
  Scene scene = stacks(1, 1, true);
  const double slept = stepUntilAsleep(scene, 1, 3.0);
  const double sleep_time = ContactSettings().sleep_time;
  // It is at rest from the start: quiet from the first step, so asleep once the sleep time has passed.
  EXPECT_GE(slept, sleep_time);
  EXPECT_LE(slept, sleep_time + 2 * kH);
  const State asleep = scene.state();
  EXPECT_EQ(asleep.P_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(asleep.L_W, Eigen::Vector3d::Zero());
  scene.step(steps(2.0));
  EXPECT_EQ(scene.state().p_WB, asleep.p_WB);
  EXPECT_EQ(scene.state().q_WB.coeffs(), asleep.q_WB.coeffs());
  EXPECT_EQ(scene.contactStatistics().sleeping_bodies, 1);
}

TEST(Sleeping, ASleepingBodyStillReportsTheContactsThatHoldIt) {
  Scene scene = stacks(1, 1, true);
  scene.setRecordContacts(true);
  ASSERT_LT(stepUntilAsleep(scene, 1, 3.0), INFINITY);
  scene.step(100);
  double normal = 0.0;
  for (const Contact& contact : scene.contacts(0)) normal += contact.normal_impulse * contact.normal_W.z();
  EXPECT_NEAR(normal, 1.0 * kG * kH, 1e-6 * kG * kH);  // the ground carries its weight over each step
}

TEST(Sleeping, AWrenchWakesItsIslandAtOnceAndOnlyIt) {
  Scene scene = stacks(2, 3, true);
  ASSERT_LT(stepUntilAsleep(scene, 6, 5.0), INFINITY);
  // Push the top box of the first stack sideways beyond its friction: the whole first stack wakes.
  AppliedWrench push;
  push.world.force = Eigen::Vector3d(10.0, 0, 0);
  const Eigen::Vector3d top = scene.state(2).p_WB;
  scene.setInput(2, push);
  scene.step(1);
  EXPECT_EQ(scene.contactStatistics().sleeping_bodies, 3);  // the other stack sleeps on
  for (std::size_t body = 3; body < 6; ++body) EXPECT_EQ(scene.state(body).P_W, Eigen::Vector3d::Zero());
  EXPECT_GT(scene.state(2).P_W.x(), 0.0);
  scene.step(steps(0.2));
  // It slides on the box below (μ = 0.5, 10 N on 1 kg against 4.905 N): a = 10 − 4.905 m/s².
  const double a = 10.0 - 0.5 * kG, t = 0.2 + kH;
  EXPECT_NEAR(scene.state(2).p_WB.x() - top.x(), 0.5 * a * t * t, 0.02 * 0.5 * a * t * t);
}

TEST(Sleeping, TheSameWrenchAgainDoesNotWakeAndANewForceModelDoes) {
  Scene scene = stacks(1, 1, true);
  AppliedWrench hold;
  hold.world.force = Eigen::Vector3d(1.0, 0, 0);  // within friction (4.905 N): the box stays
  scene.setInput(0, hold);
  ASSERT_LT(stepUntilAsleep(scene, 1, 3.0), INFINITY);
  scene.setInput(0, hold);  // a controller sending the same command again
  scene.step(1);
  EXPECT_EQ(scene.contactStatistics().sleeping_bodies, 1);
  ForceModel tilted = scene.model(0).forces;
  tilted.gravity_W = Eigen::Vector3d(kG, 0, -kG);  // now beyond friction: it must slide
  scene.setForceModel(0, tilted);
  scene.step(steps(0.1));
  EXPECT_EQ(scene.contactStatistics().sleeping_bodies, 0);
  EXPECT_GT(scene.state(0).P_W.x(), 0.0);
}

TEST(Sleeping, ASetStateWakesTheScene) {
  Scene scene = stacks(1, 1, true);
  ASSERT_LT(stepUntilAsleep(scene, 1, 3.0), INFINITY);
  State lifted = scene.state(0);
  lifted.p_WB.z() += 0.5;
  ASSERT_TRUE(scene.setState(0, lifted));
  scene.step(steps(0.2));
  const double t = 0.2;
  EXPECT_NEAR(scene.state(0).p_WB.z(), lifted.p_WB.z() - 0.5 * kG * t * t, 1e-9);  // in free fall
}

TEST(Sleeping, ABodyThatReachesASleepingIslandWakesItAndBothMoveAsWithoutSleep) {
  // A ball dropped from 4 m lands on a box that fell asleep while it fell (the fall takes 0.9 s), and one
  // thrown at 20 m/s strikes a second box from the side; each pair moves as it does with sleep off.
  const double r = 0.1;
  const CollisionShape ball = reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(r, 0, 0), 0.5, 0.5);
  std::vector<BodyDefinition> balls;
  BodyDefinition dropped = reference::contactBody(MassProperties::sphere(2.0, r), Eigen::Vector3d(0.05, 0.03, 4.2),
                                                  Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                                                  Eigen::Vector3d::Zero(), kDown);
  BodyDefinition thrown = dropped;
  thrown.initial.p_WB = Eigen::Vector3d(-19.0, 0.0, 0.12);
  thrown.initial.P_W = Eigen::Vector3d(40.0, 0, 0);  // 20 m/s, level (no gravity on it)
  thrown.model.forces.gravity_W.setZero();
  Scene with = stacks(2, 1, true, {dropped, thrown}, {ball, ball});
  Scene without = stacks(2, 1, false, {dropped, thrown}, {ball, ball});
  // Thrown from x = −19 m at 20 m/s, the ball meets the box at x = 1 at about 0.99 s, after it fell asleep.
  for (int i = 0; i < steps(0.8); ++i) with.step(1), without.step(1);
  EXPECT_EQ(with.contactStatistics().sleeping_bodies, 2);  // both boxes, before either ball arrives
  for (int i = 0; i < steps(1.5); ++i) with.step(1), without.step(1);
  EXPECT_GT(with.contactStatistics().wakes, 0);
  EXPECT_GT((with.state(1).p_WB - Eigen::Vector3d(1.0, 0, 0.1)).norm(), 0.01);  // struck and moved
  EXPECT_LT(largestDistance(with, without), ContactSettings().penetration_slop);
}

TEST(Sleeping, ABlockCreepingJustBeyondTheFrictionAngleNeverSleepsAndOneJustWithinDoes) {
  // On an incline with tan θ = μ (1 + ε) a block slides at a = g (sin θ − μ cos θ); at ε = 5e-5 that is
  // 2.2e-4 m/s², slower than the sleep speed for the whole sleep time: only its friction at the limit keeps
  // it awake. At ε = −1e-2 it sticks, and sleeps.
  const double mu = 0.5;
  for (double epsilon : {5e-5, -1e-2}) {
    const double theta = std::atan(mu * (1.0 + epsilon));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
    const Eigen::Vector3d size(0.2, 0.2, 0.1), start = 0.05 * (q * Eigen::Vector3d::UnitZ());
    ContactSetup setup;
    setup.environment = {reference::groundPlane(q * Eigen::Vector3d::UnitZ(), mu)};
    setup.bodies = {reference::collisionShape(ShapeType::kBox, size, mu, 0.0)};
    Scene scene({reference::contactBody(MassProperties::box(1.0, size), start, q, Eigen::Vector3d::Zero(),
                                        Eigen::Vector3d::Zero(), kDown)},
                IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    const double duration = 3.0;
    const double slept = stepUntilAsleep(scene, 1, duration);
    if (epsilon > 0.0) {
      EXPECT_EQ(slept, INFINITY) << "a sliding block fell asleep";
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      const double travelled = (scene.state().p_WB - start).dot(q * Eigen::Vector3d::UnitX());
      EXPECT_NEAR(travelled, 0.5 * a * duration * duration, 0.05 * 0.5 * a * duration * duration);
    } else {
      EXPECT_LT(slept, duration) << "a sticking block stayed awake";
    }
  }
}

TEST(Sleeping, AStackOfTenSleepsAndStaysWithinTheSlopOfItsTrajectoryWithoutSleep) {
  Scene with = stacks(1, 10, true);
  Scene without = stacks(1, 10, false);
  const double settle = 3.0;
  for (int i = 0; i < steps(settle); ++i) with.step(1), without.step(1);
  EXPECT_EQ(with.contactStatistics().sleeping_bodies, 10);
  EXPECT_EQ(without.contactStatistics().sleeping_bodies, 0);
  EXPECT_LT(largestDistance(with, without), ContactSettings().penetration_slop);
}

TEST(Sleeping, StartingToReadContactReportsWakesTheSceneAndTheReportsAreFresh) {
  Scene scene = stacks(1, 2, true);
  ASSERT_LT(stepUntilAsleep(scene, 2, 3.0), INFINITY);
  scene.setRecordContacts(true);
  scene.step(1);
  EXPECT_EQ(scene.contactStatistics().sleeping_bodies, 0);
  EXPECT_FALSE(scene.contacts(0).empty());
  EXPECT_FALSE(scene.contacts(1).empty());
}

TEST(Sleeping, OffByTheSettingNothingSleeps) {
  Scene scene = stacks(1, 1, false);
  EXPECT_EQ(stepUntilAsleep(scene, 1, 2.0), INFINITY);
}

// A sleeping island's touching pairs and warm starts are set aside while it sleeps and put back when it
// wakes. Woken by a push far within friction, a stack is still at rest to rounding, at 1 ms and at 20 ms,
// twice over; had it woken without them, its contacts would be new ones, which the step lifts only as far
// as the surface, and at h = 20 ms a stack of three moved 3.8 mm.
TEST(Sleeping, AWokenIslandKeepsItsContactsMemoryAndStaysAtRest) {
  for (const double h : {kH, 0.02}) {
    Scene scene = stacks(2, 3, true, {}, {}, h);
    std::vector<Eigen::Vector3d> rest;
    for (int round = 0; round < 2; ++round) {
      for (int i = 0; i < 5000 && scene.contactStatistics().sleeping_bodies < 6; ++i) scene.step(1);
      ASSERT_EQ(scene.contactStatistics().sleeping_bodies, 6) << "h " << h;
      if (round == 0) {
        for (std::size_t body = 0; body < 6; ++body) rest.push_back(scene.state(body).p_WB);
      }
      AppliedWrench nudge;
      nudge.world.force = Eigen::Vector3d(1e-6 * (round + 1), 0, 0);  // a new input: it wakes the first stack
      scene.setInput(2, nudge);
      double moved = 0.0;
      for (int i = 0; i < std::llround(0.1 / h); ++i) {
        scene.step(1);
        for (std::size_t body = 0; body < 3; ++body) moved = std::max(moved, (scene.state(body).p_WB - rest[body]).norm());
      }
      EXPECT_GT(scene.contactStatistics().wakes, round);
      EXPECT_LT(moved, 1e-9) << "h " << h << ", woken " << round + 1 << " times";
      for (std::size_t body = 3; body < 6; ++body) EXPECT_EQ(scene.state(body).p_WB, rest[body]);  // asleep on
    }
  }
}

// The detection updates only awake bodies' bounding boxes in the broad phase; a sleeping body placed
// elsewhere (a state set from outside) updates its own. Placed on an awake box, it is found there: by the
// pair's points and by a query of the broad phase.
TEST(Sleeping, ASleepingBodyPlacedElsewhereIsFoundWhereItNowIs) {
  using contact::CollisionWorld;
  const CollisionShape shape = reference::collisionShape(ShapeType::kBox, kBox, 0.5, 0.0);
  Eigen::Isometry3d low = Eigen::Isometry3d::Identity(), far = Eigen::Isometry3d::Identity();
  low.translation() = Eigen::Vector3d(0, 0, 0.1);
  far.translation() = Eigen::Vector3d(5, 0, 0.1);
  CollisionWorld world({}, {shape, shape}, {low, far});
  std::vector<contact::ContactPoint> points;
  world.detect(points, 1e-4);
  world.setAsleep(1, true);
  world.detect(points, 1e-4);
  ASSERT_TRUE(points.empty());
  world.setPose(1, Eigen::Vector3d(0, 0, 0.3), Eigen::Quaterniond::Identity());  // on the first box's top face
  world.detect(points, 1e-4);
  EXPECT_EQ(points.size(), 4u);  // the face's four corners
  std::vector<std::size_t> near;
  world.objectsNear(0, Eigen::Vector3d(-0.2, -0.2, 0.0), Eigen::Vector3d(0.2, 0.2, 0.25), near);
  EXPECT_EQ(near, std::vector<std::size_t>{1});
}
