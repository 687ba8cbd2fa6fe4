// What a located impact takes in besides its first touch (docs/contact.md, step 3): the rest of the pair's
// surfaces that arrive within the rest of the step (a face landing almost flat meets the ground first at one
// corner, and the others follow within the step), and, without restitution, the contacts the struck body
// rests on (a heavy body landing on a light one lying on the ground). Without them the rest of the step was
// free motion into the ground: the far side of a face, or the light body knocked down at the heavy one's
// speed, went down by up to a step's travel before the resting solve saw it. No state handed out after a
// step may then be deeper than what a resting contact is allowed: the slop, and one step's fall under
// gravity before the solve lifts it (g h²).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();
const double kSlop = ContactSettings().penetration_slop;

using reference::collisionShape;
using reference::depthBelowGround;
using reference::groundPlane;
using reference::solidMass;

// Half the extent of the shape along z in its own frame: where its centre stands above a face it lies on.
double halfHeight(const CollisionShape& shape) {
  if (shape.type == ShapeType::kSphere) return shape.size.x();
  return 0.5 * (shape.type == ShapeType::kCylinder ? shape.size.y() : shape.size.z());
}

}  // namespace

// Boxes (a cube-like block and a thin plate) and a disc (a cylinder on its cap) dropped almost flat, turned
// 0.3°, 1° and 3° about a horizontal axis oblique to their edges, at 5 and 20 m/s, with and without
// restitution, at h = 1 and 5 ms. The first corner's impact is located; the others arrive within the same
// step (0.3° over 0.3 m is 1.6 mm: 0.08 ms at 20 m/s), and before they were taken in they went up to 5 mm
// deep at 1 ms.
TEST(ImpactArrivals, AFaceLandingAlmostFlatNeverGoesDeeperThanARestingContact) {
  const std::vector<CollisionShape> shapes = {
      collisionShape(ShapeType::kBox, Eigen::Vector3d(0.3, 0.3, 0.2), 0.5, 0.0),
      collisionShape(ShapeType::kBox, Eigen::Vector3d(0.5, 0.4, 0.04), 0.5, 0.0),
      collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.2, 0.05, 0), 0.5, 0.0)};
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 0.37, 0.0).normalized();
  for (const CollisionShape& base : shapes) {
    for (double restitution : {0.0, 0.5}) {
        for (double tilt_degrees : {0.3, 1.0, 3.0}) {
          for (double speed : {5.0, 20.0}) {
            for (double h : {1e-3, 5e-3}) {
              CollisionShape shape = base;
              shape.material.restitution = restitution;
              ContactSetup setup;
              setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.5, restitution)};
              setup.bodies = {shape};
              const Eigen::Quaterniond q(Eigen::AngleAxisd(tilt_degrees * M_PI / 180.0, axis));
              // Its lowest point a step's travel and a half above the ground: the impact comes within a step.
              State start;
              start.q_WB = q;
              const double reach_down = depthBelowGround(start, shape);  // its lowest point below its centre
              const Eigen::Vector3d p(0.0, 0.0, reach_down + 1.5 * speed * h);
              const BodyDefinition body =
                  reference::contactBody(solidMass(shape, 2.0), p, q, Eigen::Vector3d(0, 0, -speed), kZero, kDown);
              Scene scene({body}, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
              double deepest = 0.0;
              for (int step = 0; step < static_cast<int>(0.3 / h); ++step) {
                scene.step(1);
                deepest = std::max(deepest, depthBelowGround(scene.state(0), shape));
              }
              const std::string what = "shape " + std::to_string(static_cast<int>(shape.type)) + " size " +
                                       std::to_string(shape.size.x()) + ", e " + std::to_string(restitution) +
                                       ", tilt " + std::to_string(tilt_degrees) + "°, " + std::to_string(speed) +
                                       " m/s, h " + std::to_string(h);
              EXPECT_GE(scene.contactStatistics().located_impacts, 1) << what;
              EXPECT_LE(deepest, kSlop + kG * h * h) << what;
            }
          }
        }
    }
  }
}

// A heavy body dropped onto a light one lying flat on the ground (mass ratios 10, 10³ and 10⁴; a box on a
// plate, a disc on a box, a ball on a small cube, each centred), at 3 and 10 m/s, at h = 1 and 10 ms, without
// restitution and with e = 0.5. The impact is located on the falling pair; without restitution, solved on
// that pair alone, it knocked the light body down at about the heavy one's speed for the rest of the step,
// into the ground (a capsule under a cylinder 900 times its mass, 8 mm at h = 10 ms). With the contacts it
// rests on stopped in the same impact neither goes deeper than a resting contact, and the inelastic landing
// leaves both at rest on the ground. At 10⁴ the impact's sweeps run out before every point stops (each
// carries the cube's share of the ball's momentum), and the cube went 1 to 22 mm into the ground until the
// compression was solved at once. With restitution the chain's pairwise impacts, 16 per pair at most, ran
// out with the pairs still approaching (each round moves the light body's share), and the cube went up to
// 36 mm in until the rest was one impact of the whole chain.
TEST(ImpactArrivals, AHeavyBodyLandingOnALightOneLyingOnTheGroundDoesNotDriveItIn) {
  const std::vector<std::pair<CollisionShape, CollisionShape>> pairs = {
      {collisionShape(ShapeType::kBox, Eigen::Vector3d(0.2, 0.2, 0.2), 0.5, 0.0),
       collisionShape(ShapeType::kBox, Eigen::Vector3d(0.4, 0.4, 0.02), 0.5, 0.0)},
      {collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.12, 0.1, 0), 0.5, 0.0),
       collisionShape(ShapeType::kBox, Eigen::Vector3d(0.3, 0.3, 0.06), 0.5, 0.0)},
      {collisionShape(ShapeType::kSphere, Eigen::Vector3d(0.3, 0, 0), 0.5, 0.0),
       collisionShape(ShapeType::kBox, Eigen::Vector3d(0.08, 0.08, 0.08), 0.5, 0.0)}};
  for (const auto& [heavy_shape, light_shape] : pairs) {
    for (double restitution : {0.0, 0.5}) {
      for (double ratio : {10.0, 1e3, 1e4}) {
        for (double speed : {3.0, 10.0}) {
          for (double h : {1e-3, 1e-2}) {
            CollisionShape heavy = heavy_shape, light = light_shape;
            heavy.material.restitution = light.material.restitution = restitution;
            ContactSetup setup;
            setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.5, restitution)};
            setup.bodies = {light, heavy};
            const double light_z = halfHeight(light);
            const double gap = 0.5 * speed * h;  // the impact comes within the first step
            const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
            const std::vector<BodyDefinition> bodies = {
                reference::contactBody(solidMass(light, 0.1), Eigen::Vector3d(0, 0, light_z), q, kZero, kZero, kDown),
                reference::contactBody(solidMass(heavy, 0.1 * ratio),
                                       Eigen::Vector3d(0, 0, 2.0 * light_z + halfHeight(heavy) + gap), q,
                                       Eigen::Vector3d(0, 0, -speed), kZero, kDown)};
            Scene scene(bodies, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
            double deepest = 0.0, sunk = 0.0;
            for (int step = 0; step < static_cast<int>(0.5 / h); ++step) {
              scene.step(1);
              deepest = std::max(deepest, depthBelowGround(scene.state(0), light));
              // How far the heavy body's lower face went below the light one's top face (both stay level).
              sunk = std::max(sunk, scene.state(0).p_WB.z() + light_z - (scene.state(1).p_WB.z() - halfHeight(heavy)));
            }
            const std::string what = "e " + std::to_string(restitution) + ", ratio " + std::to_string(ratio) + ", " +
                                     std::to_string(speed) + " m/s, h " + std::to_string(h) + ", heavy shape " +
                                     std::to_string(static_cast<int>(heavy.type));
            EXPECT_GE(scene.contactStatistics().located_impacts, 1) << what;
            EXPECT_LE(deepest, kSlop + kG * h * h) << what;
            EXPECT_LE(sunk, kSlop + kG * h * h) << what;
            for (std::size_t b = 0; b < 2 && restitution == 0.0; ++b) {
              EXPECT_LT(scene.state(b).P_W.norm() / bodies[b].model.mass.mass(), kG * h) << what << ", body " << b;
            }
          }
        }
      }
    }
  }
}
