// A sphere's normal force passes through its centre (docs/contact.md, "Spheres"): a ball resting on a flat
// face of a body or of the environment, whatever the sizes, stays where it is and does not turn; and balls
// carried by a box that is pushed diagonally to its axes roll on it as the closed form of docs/references.md
// §4.11 says (SimBenchmark's rolling scene). Thresholds come from the physics, before any run.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

BodyDefinition body(const MassProperties& mass, const Eigen::Vector3d& p) {
  return reference::contactBody(mass, p, Eigen::Quaterniond::Identity(), kZero, kZero, kDown);
}

}  // namespace

// A level face carries a resting ball with a vertical force through its centre and no friction at all, so
// nothing moves it. It may sink into the face by the slop (1e-4 m) and no further (the box into the ground as well); sideways it may move by
// rounding only, so 1e-6 m over 2 s catches a normal force off the centre line (a lateral offset δ rolls the
// ball at (5/7) g δ / r: δ = 1e-3 r moves it 1.4 cm in 2 s) and spin of 1e-4 rad/s catches the same.
TEST(SphereContacts, ABallRestingOnAFlatFaceStaysAndDoesNotTurn) {
  for (double radius : {0.05, 0.5}) {
    for (double side : {0.5, 4.0, 20.0}) {
      for (bool box_is_body : {true, false}) {
        const Eigen::Vector3d size(side, side, 0.5);
        ContactSetup setup;
        setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
        std::vector<BodyDefinition> bodies;
        if (box_is_body) {
          bodies.push_back(body(MassProperties::box(10.0, size), Eigen::Vector3d(0, 0, 0.25)));
          setup.bodies.push_back(reference::collisionShape(ShapeType::kBox, size, 0.5, 0.0));
        } else {
          CollisionShape table = reference::collisionShape(ShapeType::kBox, size, 0.5, 0.0);
          table.pose.translation() = Eigen::Vector3d(0, 0, 0.25);
          setup.environment.push_back(table);
        }
        const Eigen::Vector3d start(side / 5.0, -side / 7.0, 0.5 + radius);
        bodies.push_back(body(MassProperties::sphere(1.0, radius), start));
        setup.bodies.push_back(reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, 0.0));
        Scene scene(bodies, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
        scene.step(2000);
        const std::size_t ball = bodies.size() - 1;
        const State& s = scene.state(ball);
        const std::string what = "r " + std::to_string(radius) + ", box " + std::to_string(side) +
                                 (box_is_body ? " (a body)" : " (the environment)");
        EXPECT_LE((s.p_WB - start).head<2>().norm(), 1e-6) << what;
        const double top = box_is_body ? scene.state(0).p_WB.z() + 0.25 : 0.5;  // the face it rests on
        EXPECT_LE(top + radius - s.p_WB.z(), 1e-4 + 1e-6) << what;
        EXPECT_LE(angularVelocity(scene.model(ball).mass, s).norm(), 1e-4) << what;
      }
    }
  }
}

// A box (mass M) slides on the ground (μ₁) under a force F along a direction diagonal to its axes, carrying n
// balls (mass m, solid, I = 2/5 m r²) that roll on it without slipping (μ₂ large enough). The closed form
// (§4.11): f₁ = μ₁ (M + n m) g, each ball's friction f₂ = (F − f₁) / (3.5 M/m + n), the box accelerates at
// a₁ = (F − f₁ − n f₂)/M and each ball at a₂ = f₂/m, both along F. After 1 s each velocity is within 1 % of its
// closed form (the rolling bound) and along F to 1e-3 rad: a ball pushed off its centre line turns
// aside, one stuck to the box keeps pace with it (a₂ = a₁), one that slips lags.
TEST(SphereContacts, BallsRollOnABoxPushedDiagonallyAsTheClosedFormSays) {
  const double box_mass = 10.0, ball_mass = 1.0, force = 80.0;
  const Eigen::Vector3d size(6.0, 6.0, 0.5);
  for (double radius : {0.1, 0.4}) {
    for (double angle : {0.6, 2.2}) {
      const Eigen::Vector3d direction(std::cos(angle), std::sin(angle), 0.0);
      ContactSetup setup;
      // Combined by the geometric mean: ground–box √(0.2·0.8) = 0.4, box–ball √(0.8·0.8) = 0.8.
      setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.2)};
      std::vector<BodyDefinition> bodies = {body(MassProperties::box(box_mass, size), Eigen::Vector3d(0, 0, 0.25))};
      bodies.front().takes_input = true;
      setup.bodies = {reference::collisionShape(ShapeType::kBox, size, 0.8, 0.0)};
      for (double x : {-1.0, 1.0}) {
        for (double y : {-1.0, 1.0}) {
          bodies.push_back(body(MassProperties::sphere(ball_mass, radius), Eigen::Vector3d(x, y, 0.5 + radius)));
          setup.bodies.push_back(reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.8, 0.0));
        }
      }
      Scene scene(bodies, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      AppliedWrench push;
      push.world.force = force * direction;
      scene.setInput(0, push);
      scene.step(1000);
      const double n = 4.0, f1 = 0.4 * (box_mass + n * ball_mass) * kG;
      const double f2 = (force - f1) / (3.5 * box_mass / ball_mass + n);
      const double a_box = (force - f1 - n * f2) / box_mass, a_ball = f2 / ball_mass;
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const double expected = b == 0 ? a_box : a_ball;
        const Eigen::Vector3d v = linearVelocity(scene.model(b).mass, scene.state(b));
        const std::string what = "body " + std::to_string(b) + ", r " + std::to_string(radius) + ", angle " +
                                 std::to_string(angle);
        EXPECT_NEAR(v.dot(direction), expected, 0.01 * expected) << what;
        EXPECT_LE((v - v.dot(direction) * direction).norm(), 1e-3 * expected) << what;
      }
    }
  }
}
