// What a contact carries into the next step and what a solve may leave (docs/contact.md, step 5): a sustained
// contact's impulses as the same force over the next step, whatever its length, an arrival's not at all, and
// never impulses that raise the bodies' kinetic energy. Each is seen where the sweeps cannot take back a wrong
// first guess: a heavy body on a light one, whose impulse each sweep changes by the light body's share only.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"
#include "random_solver_bodies.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

using reference::collisionShape;
using reference::groundPlane;
using reference::solidMass;
using reference::mechanicalEnergy;

BodyDefinition resting(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Vector3d& v = kZero) {
  return reference::contactBody(mass, p, Eigen::Quaterniond::Identity(), v, kZero, kDown);
}

// A solver body's kinetic energy, ½ M v² + ½ ωᵀ I ω.
double kinetic(const contact::SolverBody& body) {
  return 0.5 * (body.v.squaredNorm() / body.inverse_mass + body.w.dot(body.inverse_inertia_W.inverse() * body.w));
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
              const MassProperties light = solidMass(lower, 0.01), heavy = solidMass(upper, 0.01 * ratio);
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
              if (h == 1e-2) {
                EXPECT_GE(scene.contactStatistics().split_steps, 1) << what;
              }
            }
          }
        }
      }
    }
  }
}

// The solve's last guard (limitEnergyGain): random solver bodies and contacts whose impulses (normal ≥ 0,
// friction inside the disc) have been applied to the bodies, as a solve leaves them. Where they raise the
// kinetic energy, they are scaled back, with the bodies' velocities, dP and dL, to the share at which the
// energy is what it was before them: the largest, the root of α a + α² b = 0 computed here from the
// velocities before; the velocities stay those the scaled impulses give. Where they do not raise it, nothing
// changes, to the bit.
TEST(WarmStarts, ImpulsesThatWouldRaiseTheKineticEnergyAreScaledBackToTheLargestShareThatDoesNot) {
  using namespace rigid_body::contact;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int gained = 0, kept = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t count = 2 + trial % 3;
    std::vector<SolverBody> bodies(1, environmentBody());
    for (std::size_t k = 0; k < count; ++k) {
      bodies.push_back(test::randomBody(random));
      bodies.back().v = test::randomUnit(random) * unit(random);
      bodies.back().w = test::randomUnit(random) * unit(random);
    }
    std::vector<SolverContact> contacts;
    for (std::size_t k = 0; k < 2 * count; ++k) {
      SolverContact c;
      c.cross_a.setZero(), c.cross_b.setZero(), c.response_a.setZero(), c.response_b.setZero();  // made below
      c.a = 1 + random() % count, c.b = random() % (count + 1);  // b may be the environment (0)
      if (c.b == c.a) c.b = 0;
      c.n = test::randomUnit(random);
      c.t1 = c.n.unitOrthogonal(), c.t2 = c.n.cross(c.t1);
      c.r_a = 0.3 * test::randomUnit(random), c.r_b = 0.3 * test::randomUnit(random);
      c.friction = 0.8;
      c.normal_impulse = unit(random);
      const Eigen::Vector2d direction = test::randomUnit(random).head<2>().normalized();
      c.friction_impulse = c.friction * c.normal_impulse * unit(random) * direction;
      contacts.push_back(c);
    }
    SolveOptions options;
    prepareContactRows(contacts, bodies, options, 0, contacts.size());
    const std::vector<SolverBody> before = bodies;
    const SolveRange range = SolveRange::all(contacts.size(), bodies.size());
    sumImpulses(contacts, bodies, range);
    double a = 0.0, b = 0.0, start = 0.0;
    for (std::size_t s = 1; s < bodies.size(); ++s) {
      SolverBody& body = bodies[s];
      const Eigen::Vector3d dv = body.inverse_mass * body.dP, dw = body.inverse_inertia_W * body.dL;
      a += body.v.dot(body.dP) + body.w.dot(body.dL);
      b += 0.5 * (dv.dot(body.dP) + dw.dot(body.dL));
      start += kinetic(body);
      body.v += dv, body.w += dw;
    }
    const std::vector<SolverBody> applied = bodies;
    const std::vector<SolverContact> solved = contacts;
    const double share = limitEnergyGain(contacts, bodies, range);
    const std::string what = "trial " + std::to_string(trial);
    if (a + b <= 0.0) {  // no gain: untouched
      ++kept;
      EXPECT_EQ(share, 1.0) << what;
      for (std::size_t s = 1; s < bodies.size(); ++s) EXPECT_EQ(bodies[s].v, applied[s].v) << what;
      for (std::size_t k = 0; k < contacts.size(); ++k) EXPECT_EQ(contacts[k].normal_impulse, solved[k].normal_impulse);
      continue;
    }
    ++gained;
    const double root = a < 0.0 ? -a / b : 0.0;
    EXPECT_NEAR(share, root, 1e-12 * (1.0 + root)) << what;
    double energy = 0.0;
    for (std::size_t s = 1; s < bodies.size(); ++s) {
      const SolverBody& body = bodies[s];
      energy += kinetic(body);
    }
    EXPECT_NEAR(energy, start, 1e-9 * start) << what;
    // The bodies move as the scaled impulses move them: the sum of the contacts' impulses as they now stand.
    std::vector<SolverBody> summed = before;
    sumImpulses(contacts, summed, range);
    for (std::size_t s = 1; s < bodies.size(); ++s) {
      EXPECT_LT((bodies[s].dP - summed[s].dP).norm(), 1e-12) << what;
      EXPECT_LT((bodies[s].v - before[s].v - before[s].inverse_mass * summed[s].dP).norm(), 1e-12) << what;
      EXPECT_LT((bodies[s].w - before[s].w - before[s].inverse_inertia_W * summed[s].dL).norm(), 1e-12) << what;
    }
  }
  // Both kinds came up often enough to have been tried.
  EXPECT_GT(gained, 40);
  EXPECT_GT(kept, 40);
}
