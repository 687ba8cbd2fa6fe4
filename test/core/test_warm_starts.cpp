// What a contact carries into the next step (docs/contact.md, step 5, "Warm starts"): a sustained contact's
// impulses as the same force over the next step, whatever its length, and an arrival's not at all. Both are
// seen where the sweeps cannot take back a wrong first guess: a heavy body on a light one, whose impulse each
// sweep changes by the light body's share only.
#include <gtest/gtest.h>

#include <algorithm>
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

using reference::collisionShape;
using reference::groundPlane;

BodyDefinition resting(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Vector3d& v = kZero) {
  return reference::contactBody(mass, p, Eigen::Quaterniond::Identity(), v, kZero, kDown);
}

MassProperties massOf(const CollisionShape& shape, double mass) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return MassProperties::sphere(mass, shape.size.x());
    case ShapeType::kCylinder:
      return MassProperties::cylinder(mass, shape.size.x(), shape.size.y());
    default:
      return MassProperties::box(mass, shape.size);
  }
}

double mechanicalEnergy(const Scene& scene) {
  double energy = 0.0;
  for (std::size_t i = 0; i < scene.bodyCount(); ++i) {
    energy += kineticEnergy(scene.model(i).mass, scene.state(i)) +
              potentialEnergy(scene.model(i).mass, scene.model(i).forces, scene.state(i));
  }
  return energy;
}

}  // namespace

// A heavy body dropped onto a light one lying on the ground, mass ratios 10³ and 10⁴, landing flat and tilted
// (a box on its face and on an edge, a cylinder on its rim), with and without restitution, at a fine and a
// coarse step. The landing's impulse is an impact: repeated as the next step's first guess, it pushed the heavy
// body off again, and the sweeps, which move it by the light body's share at a time, could not take it back
// (a cylinder left a sphere with twice the energy it arrived with). At the coarse step the falling body moves
// farther in a step than the light one is thick, so the scene steps in halves near it (docs/contact.md, "No
// tunnelling"), and a sustained contact's impulse taken whole from a longer step into a shorter one was as
// many times its force (a box left a box with 150 J more). The bodies' mechanical energy never exceeds what
// they started with, but for what the position projection may lift the bodies by after a step that let them
// sink (g h² of height each, one step's fall).
TEST(WarmStarts, AHeavyBodyLandingOnALightOneNeverGainsEnergy) {
  const std::vector<CollisionShape> heavy_shapes = {
      collisionShape(ShapeType::kBox, Eigen::Vector3d(0.3, 0.2, 0.1), 0.6, 0.0),
      collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.06, 0.26, 0), 0.6, 0.0)};
  const std::vector<CollisionShape> light_shapes = {
      collisionShape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.6, 0.0),
      collisionShape(ShapeType::kBox, Eigen::Vector3d(0.25, 0.25, 0.08), 0.6, 0.0)};
  for (const CollisionShape& heavy_shape : heavy_shapes) {
    for (const CollisionShape& light_shape : light_shapes) {
      for (double ratio : {1e3, 1e4}) {
        for (double tilt : {0.0, 0.5}) {
          for (double e : {0.0, 0.5}) {
            for (double h : {1e-3, 1e-2}) {
              ContactSetup setup;
              setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.8, e)};
              CollisionShape upper = heavy_shape, lower = light_shape;
              upper.material.restitution = lower.material.restitution = e;
              setup.bodies = {lower, upper};
              const double lower_top = lower.type == ShapeType::kSphere ? 2.0 * lower.size.x() : lower.size.z();
              const MassProperties light = massOf(lower, 0.01), heavy = massOf(upper, 0.01 * ratio);
              const Eigen::Vector3d drop(0.02, -0.01, lower_top + 0.4), axis = Eigen::Vector3d(1, 0.4, 0).normalized();
              BodyDefinition falling = resting(heavy, drop, Eigen::Vector3d(0.3, 0, -3));
              falling.initial.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(tilt, axis));
              Scene scene({resting(light, Eigen::Vector3d(0, 0, 0.5 * lower_top)), falling}, IntegratorType::kRk4, h,
                          IntegratorSettings(), StepAssembly::kLeaveOut, setup);
              const double start = mechanicalEnergy(scene);
              const double allowance = (light.mass() + heavy.mass()) * kG * kG * h * h;
              double highest = start, lowest = scene.state(1).p_WB.z();
              for (int i = 0; i < static_cast<int>(0.6 / h); ++i) {
                scene.step(1);
                highest = std::max(highest, mechanicalEnergy(scene));
                lowest = std::min(lowest, scene.state(1).p_WB.z());
              }
              const std::string what = std::string(shapeTypeName(upper.type)) + " on " + shapeTypeName(lower.type) +
                                       ", ratio " + std::to_string(ratio) + ", tilt " + std::to_string(tilt) +
                                       ", e " + std::to_string(e) + ", h " + std::to_string(h);
              EXPECT_LE(highest, start + allowance) << what << ": gained " << highest - start << " J";
              // It landed: the heavy body came down onto the light one (its centre within its half-extent, at
              // most 0.17 m, of the light one's top; it started 0.4 m above it).
              EXPECT_LT(lowest, lower_top + 0.2) << what;
              if (h == 1e-2) EXPECT_GE(scene.contactStatistics().split_steps, 1) << what;
            }
          }
        }
      }
    }
  }
}

