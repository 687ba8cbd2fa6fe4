// Bodies on an environment mesh (its triangles themselves, docs/contact.md, "Shapes") meet the closed forms
// they meet on a half-space: every shape dropped on a slab of triangles rests on its top face, a block
// sliding across the triangles' edges stops after v0²/(2 μ g), a ball rolls across them at constant speed.
// Bullet's algorithm for a convex body on a triangle mesh once put its points in manifolds it freed, and
// every body fell through environment meshes; these tests fail that way. Each touching triangle is clipped
// as a face against the body's face along its normal (as convex pairs are, docs/contact.md, "Shapes").
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
constexpr double kTop = 0.3;  // the slab's top face [m]

// A slab of triangles (two per face) of the given extent, its top face at z = kTop; no half-space.
CollisionShape slab(double extent, double friction) {
  CollisionShape shape;
  shape.type = ShapeType::kMesh;
  shape.name = "slab";
  shape.mesh = primitives::box(Eigen::Vector3d(extent, extent, kTop));
  shape.pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.5 * kTop);
  shape.material.friction = friction;
  return shape;
}

CollisionShape capsule() {
  return reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(0.07, 0.12, 0), 0.5, 0.0);
}
MassProperties capsuleMass() { return MassProperties::cylinder(1.0, 0.07, 0.26); }  // near enough here

struct Dropped {
  CollisionShape shape;
  MassProperties mass;
  Eigen::Quaterniond q;
  double half_height;  // of its centre above the surface it rests on [m]
};

std::vector<Dropped> everyShape() {
  const Eigen::Quaterniond upright = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond lying(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitY()));
  std::vector<Dropped> shapes;
  shapes.push_back({reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(0.3, 0.2, 0.1), 0.5, 0.0),
                    MassProperties::box(1.0, Eigen::Vector3d(0.3, 0.2, 0.1)), upright, 0.05});
  shapes.push_back({reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.5, 0.0),
                    MassProperties::sphere(1.0, 0.1), upright, 0.1});
  shapes.push_back({reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.08, 0.2, 0), 0.5, 0.0),
                    MassProperties::cylinder(1.0, 0.08, 0.2), upright, 0.1});
  shapes.push_back({capsule(), capsuleMass(), lying, 0.07});
  CollisionShape hull = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0.0);
  hull.mesh = primitives::box(Eigen::Vector3d(0.25, 0.25, 0.15));
  shapes.push_back({hull, MassProperties::box(1.0, Eigen::Vector3d(0.25, 0.25, 0.15)), upright, 0.075});
  return shapes;
}

TEST(EnvironmentMeshes, EveryShapeDroppedOnASlabOfTrianglesRestsOnItsTopFace) {
  // Dropped from 5 cm above the face, each at its own place (some over the triangles' shared diagonal);
  // after 1 s each rests on the face: its centre within twice the slop of its height above it, at rest,
  // its contacts all with the slab.
  ContactSetup setup;
  setup.environment = {slab(3.0, 0.5)};
  std::vector<BodyDefinition> bodies;
  const std::vector<Dropped> shapes = everyShape();
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const Eigen::Vector3d p(-0.8 + 0.4 * i, 0.3 - 0.15 * i, kTop + shapes[i].half_height + 0.05);
    bodies.push_back(reference::contactBody(shapes[i].mass, p, shapes[i].q, Eigen::Vector3d::Zero(),
                                            Eigen::Vector3d::Zero(), kDown));
    setup.bodies.push_back(shapes[i].shape);
  }
  Scene scene(bodies, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  scene.step(1000);
  const double slop = setup.settings.penetration_slop;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const State& state = scene.state(i);
    EXPECT_NEAR(state.p_WB.z(), kTop + shapes[i].half_height, 2.0 * slop) << "shape " << i;
    EXPECT_LT(linearVelocity(shapes[i].mass, state).norm(), 1e-3) << "shape " << i;
    ASSERT_FALSE(scene.contacts(i).empty()) << "shape " << i;
    for (const Contact& contact : scene.contacts(i)) EXPECT_FALSE(contact.other.is_body) << "shape " << i;
  }
}

TEST(EnvironmentMeshes, ABlockSlidingAcrossTheTrianglesStopsAfterV0SquaredOver2MuG) {
  // As on a half-space (test_contact.cpp), sliding at 30° to the triangles' edges (it crosses the top
  // face's diagonal): the same closed form to the same tolerance.
  const double mu = 0.4, v0 = 2.0;
  const Eigen::Vector3d size(0.2, 0.2, 0.1), along(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0), 0.0);
  ContactSetup setup;
  setup.environment = {slab(3.0, mu)};
  setup.bodies = {reference::collisionShape(ShapeType::kBox, size, mu, 0.0)};
  const Eigen::Vector3d start(-0.3, -0.4, kTop + 0.05);
  Scene scene({reference::contactBody(MassProperties::box(2.0, size), start, Eigen::Quaterniond::Identity(),
                                      v0 * along, Eigen::Vector3d::Zero(), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  const double stop_time = v0 / (mu * kG), stop_distance = v0 * v0 / (2.0 * mu * kG);
  double stopped_at = -1.0;
  for (int i = 1; i <= 2000; ++i) {
    scene.step(1);
    if (stopped_at < 0.0 && scene.state().P_W.dot(along) <= 1e-9) stopped_at = i * 1e-3;
  }
  EXPECT_NEAR(stopped_at, stop_time, 5e-3 * stop_time);
  EXPECT_NEAR((scene.state().p_WB - start).dot(along), stop_distance, 5e-3 * stop_distance);
  EXPECT_NEAR(scene.state().p_WB.z(), start.z(), 1e-3);  // on the face, neither sunk nor lifted
}

TEST(EnvironmentMeshes, ABallRollsAcrossTheTrianglesAtConstantSpeed) {
  // Rolling without slip (ω = v / r about the horizontal normal to v) on a flat face: no force along it, so
  // the speed holds across the triangles' shared edges; 1 s at 1 m/s.
  const double radius = 0.1, v0 = 1.0;
  const Eigen::Vector3d along(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0), 0.0);
  ContactSetup setup;
  setup.environment = {slab(3.0, 0.5)};
  setup.bodies = {reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, 0.0)};
  const MassProperties ball = MassProperties::sphere(1.0, radius);
  const Eigen::Vector3d start(-0.6, -0.4, kTop + radius);
  const Eigen::Vector3d w = Eigen::Vector3d::UnitZ().cross(along) * (v0 / radius);
  Scene scene({reference::contactBody(ball, start, Eigen::Quaterniond::Identity(), v0 * along, w, kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(1000);
  EXPECT_NEAR((scene.state().p_WB - start).dot(along), v0, 5e-3 * v0);
  EXPECT_NEAR(linearVelocity(ball, scene.state()).norm(), v0, 5e-3 * v0);
  EXPECT_NEAR(scene.state().p_WB.z(), start.z(), 2.0 * setup.settings.penetration_slop);
}

// A capsule lying on a face of triangles comes to rest on both ends of its segment. With Bullet's
// multi-point perturbation alone (before each touching triangle was clipped as a face) it got one point,
// at one end, and kept a momentum of a few mm/s that the solve and the projection cancelled each step.
TEST(EnvironmentMeshes, ACapsuleLyingOnTrianglesComesToRestOnBothEnds) {
  ContactSetup setup;
  setup.environment = {slab(3.0, 0.5)};
  setup.bodies = {capsule()};
  const Eigen::Quaterniond lying(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitY()));
  Scene scene({reference::contactBody(capsuleMass(), Eigen::Vector3d(0.4, -0.15, kTop + 0.12), lying,
                                      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  scene.step(1000);
  EXPECT_LT(linearVelocity(capsuleMass(), scene.state()).norm(), 1e-3);
  EXPECT_GE(scene.contacts(0).size(), 2u);  // both ends of its segment
}

}  // namespace
