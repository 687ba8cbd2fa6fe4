// Speculative points (docs/contact.md, step 2): a touching pair whose body moves also gets the points of its
// faces that are still apart but may arrive within the step, marked speculative, at the distances the
// geometry gives; a pair at rest, or not touching, gets none; a box pair's points between touching and the
// slop (which Bullet's box detector does not give) come as ordinary points; and no report lists a point
// that does not touch. Distances are worked out by hand before any run.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../../src/contact/collision_world.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;
using contact::CollisionWorld;
using contact::ContactPoint;

namespace {

constexpr double kSlop = 1e-4;         // the detection's reach, the default penetration slop [m]
constexpr double kSpeculative = 0.02;  // how far speculative points reach in these tests [m]
constexpr double kSink = 5e-4;         // how far the pivot edge is set into the support [m]
constexpr double kExact = 1e-9;        // rounding in distances of order 1 m [m]
const Eigen::Vector3d kBox(0.2, 0.15, 0.1);

// The support's top face is z = 0: a table (an environment box, so a box pair) or a half-space.
CollisionShape support(bool table) {
  if (!table) return reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5);
  CollisionShape box = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(1.0, 1.0, 0.2), 0.5, 0.0);
  box.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  return box;
}

// The box turned by θ about y with its lower edge x = −0.1 (body frame) kSink below z = 0: its two far lower
// corners (x = +0.1) are 0.2 sin θ − kSink above the support.
Eigen::Isometry3d tilted(double theta) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d pivot_B(-0.1, 0.0, -0.05);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = Eigen::Vector3d(0.0, 0.0, -kSink) - q * pivot_B;
  return X;
}

std::vector<ContactPoint> detect(bool table, double theta, bool moving) {
  CollisionWorld world({support(table)}, {reference::collisionShape(ShapeType::kBox, kBox, 0.5, 0.0)}, {tilted(theta)});
  std::vector<ContactPoint> points;
  const std::vector<char> moves{static_cast<char>(moving ? 1 : 0)};
  world.detect(points, kSlop, kSpeculative, &moves);
  return points;
}

TEST(SpeculativePoints, AMovingBoxOnAnEdgeGetsItsFarCornersWhereTheGeometryPutsThem) {
  for (const bool table : {false, true}) {
    for (const double theta : {0.02, 0.05, 0.09}) {  // far corners 3.5, 9.5 and 17.5 mm up
      const double far = 0.2 * std::sin(theta) - kSink;
      const std::vector<ContactPoint> points = detect(table, theta, true);
      int pivots = 0, speculative = 0;
      for (const ContactPoint& p : points) {
        ASSERT_EQ(p.a, 0u);
        const Eigen::Vector3d on_B = tilted(theta).inverse() * p.on_a;
        if (p.speculative) {
          ++speculative;
          EXPECT_NEAR(p.distance, far, kExact) << "table " << table << ", theta " << theta;
          EXPECT_NEAR(on_B.x(), 0.1, 1e-7);
          EXPECT_NEAR(on_B.z(), -0.05, 1e-7);
          EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
        } else {
          ++pivots;
          EXPECT_NEAR(p.distance, -kSink, 1e-6) << "table " << table << ", theta " << theta;
          EXPECT_NEAR(on_B.x(), -0.1, 1e-6);
        }
      }
      EXPECT_EQ(pivots, 2) << "table " << table << ", theta " << theta;
      EXPECT_EQ(speculative, 2) << "table " << table << ", theta " << theta;
    }
    // Beyond the speculative reach (far corners 34 mm up), at rest, or not touching: none.
    for (const ContactPoint& p : detect(table, 0.175, true)) EXPECT_FALSE(p.speculative);
    for (const ContactPoint& p : detect(table, 0.05, false)) EXPECT_FALSE(p.speculative);
  }
  CollisionWorld apart({support(true)}, {reference::collisionShape(ShapeType::kBox, kBox, 0.5, 0.0)},
                       {Eigen::Translation3d(0, 0, 0.001) * tilted(0.05)});
  std::vector<ContactPoint> points;
  const std::vector<char> moves{1};
  apart.detect(points, kSlop, kSpeculative, &moves);
  EXPECT_TRUE(points.empty());
}

TEST(SpeculativePoints, ABoxPairsPointsBetweenTouchingAndTheSlopAreOrdinaryPoints) {
  // Far corners 5e-5 m up: within the slop, so the pair's own points, though Bullet's box detector gives
  // penetrating points only.
  const double theta = std::asin((5e-5 + kSink) / 0.2);
  const std::vector<ContactPoint> points = detect(true, theta, true);
  ASSERT_EQ(points.size(), 4u);
  int far = 0;
  for (const ContactPoint& p : points) {
    EXPECT_FALSE(p.speculative);
    if (!(p.distance > 0.0)) continue;
    ++far;
    EXPECT_NEAR(p.distance, 5e-5, kExact);
  }
  EXPECT_EQ(far, 2);
}

TEST(SpeculativePoints, NoReportListsAPointThatDoesNotTouch) {
  // A box standing on its end, leaning past its tipping angle, falls onto its side on a table: for much of
  // the fall it touches with an edge while its far corners come down (speculative points all along).
  ContactSetup setup;
  setup.environment = {support(true)};
  setup.settings.sleep = false;
  const Eigen::Vector3d size(0.05, 0.15, 0.2);
  setup.bodies = {reference::collisionShape(ShapeType::kBox, size, 0.8, 0.0)};
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d pivot_B(0.025, 0.0, -0.1);  // the lowest corner edge
  Scene scene({reference::contactBody(MassProperties::box(1.0, size), Eigen::Vector3d(0, 0, 1e-6) - q * pivot_B, q,
                                      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -9.81))},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  for (int k = 0; k < 1000; ++k) {
    scene.step(1);
    for (const Contact& c : scene.contacts(0)) ASSERT_LE(c.position_W.z(), kSlop + 1e-9) << "step " << k;
  }
  // It did fall onto its side (the 0.05 m face down).
  EXPECT_NEAR(scene.state(0).p_WB.z(), 0.025, 1e-3);
}

}  // namespace
