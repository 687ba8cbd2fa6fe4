// Contact where physics is hard (docs/contact.md): fast bodies on curved paths that must not pass through
// thin obstacles, frictional impacts of spinning bodies that must not create energy, and static friction held
// up to just below the friction angle with the slip diagonal to the tangent basis. Every threshold is derived
// from the physics (a step's sink, the slop, a closed form), not read off a run.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/world.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);

using reference::collisionShape;
using reference::groundPlane;
using reference::mechanicalEnergy;

BodyDefinition body(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                    const Eigen::Vector3d& v, const Eigen::Vector3d& w_B, const Eigen::Vector3d& gravity = kDown) {
  return reference::contactBody(mass, p, q, v, w_B, gravity);
}

// The mass properties of a solid of the collision shape's own type and size.
MassProperties massOf(ShapeType type, const Eigen::Vector3d& size, double mass) {
  switch (type) {
    case ShapeType::kSphere:
      return MassProperties::sphere(mass, size.x());
    case ShapeType::kCylinder:
      return MassProperties::cylinder(mass, size.x(), size.y());
    case ShapeType::kCapsule:
      return MassProperties::cylinder(mass, size.x(), size.y() + 2.0 * size.x());
    default:
      return MassProperties::box(mass, size);
  }
}

}  // namespace

// A fast body under gravity follows a parabola, not the straight chord of its step; a thin plate in its way
// must stop it whatever the step, the speed, the plate's thickness, the body's shape and where in its step the
// path meets the plate (the start heights are spread over a step's travel, so that the touch falls early,
// late and in the middle of a step).
TEST(ContactRegimes, FastBodiesOnCurvedPathsNeverPassThinPlates) {
  const std::vector<ShapeType> shapes = {ShapeType::kSphere, ShapeType::kBox, ShapeType::kCapsule, ShapeType::kCylinder};
  for (double h : {1e-3, 1e-2}) {
    for (double speed : {100.0, 1000.0}) {
      for (double thickness : {1e-3, 1e-2}) {
        for (ShapeType type : shapes) {
          for (double phase : {0.0, 0.31, 0.67, 0.93}) {
            const Eigen::Vector3d size(0.05, 0.06, 0.07);  // a 5 cm ball, or a box, capsule, cylinder of that order
            // Wide enough for the sideways travel (a fifth of the fall, from up to 10.3 m) and two steps more.
            CollisionShape plate = collisionShape(ShapeType::kBox, Eigen::Vector3d(12.0, 12.0, thickness), 0.5, 0.0);
            plate.name = "plate";
            ContactSetup setup;
            setup.environment = {plate};
            setup.bodies = {collisionShape(type, size, 0.5, 0.0)};
            // Sideways as well as down: the path is a parabola in a tilted plane.
            const Eigen::Vector3d v(0.2 * speed, 0.1 * speed, -speed);
            const double start_height = 1.0 + phase * speed * h;
            const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0).normalized()));
            Scene scene({body(massOf(type, size, 1.0), Eigen::Vector3d(0, 0, start_height), q, v, Eigen::Vector3d(3, -2, 1))},
                        IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
            // Until just after the first impact (or, had there been none, until it had passed the plate), then
            // two steps more: the plate is wide enough for the sideways travel over that time.
            const double flight = (start_height + 0.5) / speed;
            for (std::int64_t i = 0; i < static_cast<std::int64_t>(std::ceil(flight / h)) && scene.impacts().empty(); ++i) {
              scene.step(1);
            }
            scene.step(2);
            const std::string what = std::string(shapeTypeName(type)) + " at " + std::to_string(speed) + " m/s, h " +
                                     std::to_string(h) + ", plate " + std::to_string(thickness) + " m, phase " +
                                     std::to_string(phase);
            // Above the plate's top face (its centre is at 0): the body's centre cannot be lower than the top.
            EXPECT_GT(scene.state().p_WB.z(), 0.5 * thickness) << what;
          }
        }
      }
    }
  }
}

// Two bodies both fast, head-on: each moves farther in a step than the other is thick. Equal spheres with
// e = 1 and no friction exchange their velocities (momentum and energy to 1e-9).
TEST(ContactRegimes, FastBodiesMeetingHeadOnExchangeVelocitiesInsteadOfPassing) {
  const double radius = 0.05;
  const MassProperties ball = MassProperties::sphere(1.0, radius);
  for (double speed : {300.0, 1000.0}) {
    for (double h : {1e-3, 1e-2}) {
      ContactSetup setup;
      setup.bodies = {collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0),
                      collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0)};
      const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
      const Eigen::Vector3d va(speed, 0, 0), vb(-0.5 * speed, 0, 0);
      // The gap closes at 1.5 speed; 0.37 of a step's closing moved off the step grid.
      const double gap = 10.0 * 1.5 * speed * h + 0.37 * 1.5 * speed * h;
      Scene scene({body(ball, Eigen::Vector3d(-0.5 * gap - radius, 0, 0), Eigen::Quaterniond::Identity(), va, zero, zero),
                   body(ball, Eigen::Vector3d(0.5 * gap + radius, 0, 0), Eigen::Quaterniond::Identity(), vb, zero, zero)},
                  IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      scene.step(30);
      const std::string what = std::to_string(speed) + " m/s, h " + std::to_string(h);
      EXPECT_LT((scene.state(0).P_W - vb).norm(), 1e-9 * speed) << what;
      EXPECT_LT((scene.state(1).P_W - va).norm(), 1e-9 * speed) << what;
      EXPECT_LT(scene.state(0).p_WB.x(), scene.state(1).p_WB.x()) << what << ": they passed through each other";
    }
  }
}

// Newton's kinematic restitution with Coulomb friction creates energy at a spinning, frictional impact
// (Kane & Levinson's example); the impact law here never does. Boxes, capsules and cylinders dropped turned
// and spinning, with friction from low to high and restitution from 0 to 1: the bodies' mechanical energy
// never exceeds what they started with, but for what the position projection may lift a body by after a step
// that let it sink (at most g h² of height, one step's fall at the scene's g).
TEST(ContactRegimes, FrictionalImpactsOfSpinningBodiesNeverCreateEnergy) {
  const double h = 1e-3;
  const std::vector<ShapeType> shapes = {ShapeType::kBox, ShapeType::kCapsule, ShapeType::kCylinder};
  for (ShapeType type : shapes) {
    for (double mu : {0.3, 1.0}) {
      for (double e : {0.0, 0.5, 1.0}) {
        const Eigen::Vector3d size = type == ShapeType::kBox ? Eigen::Vector3d(0.3, 0.2, 0.1) : Eigen::Vector3d(0.05, 0.4, 0);
        ContactSetup setup;
        setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), mu, e)};
        setup.bodies = {collisionShape(type, size, mu, e)};
        const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0.3).normalized()));
        const MassProperties mass = massOf(type, size, 2.0);
        Scene scene({body(mass, Eigen::Vector3d(0, 0, 0.6), q, Eigen::Vector3d(1.0, -0.5, 0), Eigen::Vector3d(4, -6, 9))},
                    IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
        const double start = mechanicalEnergy(scene);
        const double allowance = mass.mass() * kG * kG * h * h;
        double highest = start;
        for (int i = 0; i < 3000; ++i) {
          scene.step(1);
          highest = std::max(highest, mechanicalEnergy(scene));
        }
        EXPECT_LE(highest, start + allowance)
            << shapeTypeName(type) << " mu " << mu << " e " << e << ": gained " << highest - start << " J";
        EXPECT_GE(scene.contactStatistics().located_impacts + scene.contactStatistics().swept_impacts, 1);
      }
    }
  }
}

// One impact alone, where Newton's law with Coulomb friction gains most: a box landing on one corner while it
// spins, e = 1. The located impact's own energy balance: the kinetic energy just after is at most just before.
TEST(ContactRegimes, ASpinningBoxLandingOnACornerWithEOneDoesNotGainEnergy) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  for (double mu : {0.2, 0.5, 2.0}) {
    ContactSetup setup;
    setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), mu, 1.0)};
    setup.bodies = {collisionShape(ShapeType::kBox, size, mu, 1.0)};
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 1, 0).normalized()));
    const MassProperties box = MassProperties::box(1.0, size);
    Scene scene({body(box, Eigen::Vector3d(0, 0, 0.8), q, Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(3, -2, 5),
                      Eigen::Vector3d::Zero())},  // no gravity: kinetic energy alone is conserved in flight
                IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    State falling = scene.state();
    falling.P_W = Eigen::Vector3d(0.5, 0.0, -3.0);
    scene.setState(0, falling);
    const double before = kineticEnergy(box, scene.state());
    for (int i = 0; i < 1000 && scene.impacts().empty(); ++i) scene.step(1);
    ASSERT_FALSE(scene.impacts().empty()) << "mu " << mu;
    EXPECT_LE(kineticEnergy(box, scene.state()), before * (1.0 + 1e-12)) << "mu " << mu;
  }
}

// A block on an incline at 0.98 of its friction angle, yawed so that the slip it would have is diagonal to the
// contact's tangent basis, for a flat and a taller block (not tall enough to tip: tan θ below width / height),
// at a fine and a coarse step: it holds (drift < 0.1 mm in 10 s). At 1.1 of the angle it slides at
// a = g (sin θ − μ cos θ) (1 % over 1 s).
TEST(ContactRegimes, StaticFrictionHoldsUpToTheFrictionAngleAndGivesWayAboveIt) {
  for (const Eigen::Vector3d& size : {Eigen::Vector3d(0.2, 0.2, 0.1), Eigen::Vector3d(0.3, 0.25, 0.25)}) {
    for (double mu : {0.3, 0.8}) {
      for (double h : {1e-3, 1e-2}) {
        for (double ratio : {0.98, 1.1}) {
          const double theta = std::atan(ratio * mu);
          ASSERT_LT(std::tan(theta), std::min(size.x(), size.y()) / size.z()) << "the block would tip";
          const Eigen::Quaterniond incline(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
          const Eigen::Vector3d normal = incline * Eigen::Vector3d::UnitZ(), down_slope = incline * Eigen::Vector3d::UnitX();
          ContactSetup setup;
          setup.environment = {groundPlane(normal, mu)};
          setup.bodies = {collisionShape(ShapeType::kBox, size, mu, 0.0)};
          const Eigen::Quaterniond q = incline * Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
          const Eigen::Vector3d start = 0.5 * size.z() * normal;
          Scene scene({body(MassProperties::box(1.0, size), start, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())},
                      IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
          const double duration = ratio < 1.0 ? 10.0 : 1.0;
          scene.step(static_cast<std::int64_t>(std::llround(duration / h)));
          const std::string what = "size " + std::to_string(size.z()) + " mu " + std::to_string(mu) + " h " +
                                   std::to_string(h) + " ratio " + std::to_string(ratio);
          if (ratio < 1.0) {
            EXPECT_LT((scene.state().p_WB - start).norm(), 1e-4) << what;
          } else {
            const double a = kG * (std::sin(theta) - mu * std::cos(theta));
            const double expected = 0.5 * a * duration * duration;
            EXPECT_NEAR((scene.state().p_WB - start).dot(down_slope), expected, 0.01 * expected) << what;
          }
        }
      }
    }
  }
}

// At a coarse step a ball with e < 1 bounces while its approach beats the restitution threshold and then
// rests: no limit cycle of small hops (each landing found within a step used to be lifted off again by the
// position update meant for a contact that held over the whole step).
TEST(ContactRegimes, ABouncingBallComesToRestAtCoarseSteps) {
  const double radius = 0.1, slop = ContactSettings().penetration_slop;
  for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kSemiImplicitEuler}) {
    for (double h : {1e-3, 5e-3, 1e-2}) {
      for (double e : {0.5, 0.8}) {
        for (bool located : {true, false}) {
          ContactSetup setup;
          setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.5, e)};
          setup.bodies = {collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, e)};
          setup.settings.event_location = located;
          Scene scene({body(MassProperties::sphere(1.0, radius), Eigen::Vector3d(0, 0, radius + 1.0),
                            Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())},
                      type, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
          // The bounces end (the series of flights 2 eⁿ v₁/g) within t₁ (1 + 2e/(1 − e)) ≤ 4.1 s for e = 0.8.
          scene.step(static_cast<std::int64_t>(std::llround(8.0 / h)));
          double fastest = 0.0, highest = -1.0, lowest = 1.0;
          for (int i = 0; i < static_cast<int>(std::llround(2.0 / h)); ++i) {
            scene.step(1);
            fastest = std::max(fastest, scene.state().P_W.norm());
            highest = std::max(highest, scene.state().p_WB.z() - radius);
            lowest = std::min(lowest, scene.state().p_WB.z() - radius);
          }
          const std::string what = std::string(integratorName(type)) + " h " + std::to_string(h) + " e " +
                                   std::to_string(e) + (located ? " located" : " at the step's end");
          EXPECT_LT(fastest, 1e-9) << what;
          // Resting: neither above the ground by more than one step's free fall (c g h², c = ½ for rk4, 1 for
          // semi-implicit Euler, which moves x with the new velocity) nor in it beyond the slop and that fall.
          const double fall = (type == IntegratorType::kRk4 ? 0.5 : 1.0) * kG * h * h;
          EXPECT_LE(highest, fall * (1.0 + 1e-9)) << what;
          EXPECT_GE(lowest, -slop - fall) << what;
        }
      }
    }
  }
}

// Rolling without slipping at a coarse step: a sphere at (5/7) g sin θ and a cylinder lying across the slope
// at (2/3) g sin θ, within 1 % over 1 s at h = 10 ms, and neither lifts off the incline by more than the slop.
TEST(ContactRegimes, RollingAtCoarseStepsFollowsTheClosedForm) {
  const double theta = 25.0 * 3.14159265358979323846 / 180.0, radius = 0.1, length = 0.3, mu = 0.6;
  const double slop = ContactSettings().penetration_slop;
  const Eigen::Quaterniond incline(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d normal = incline * Eigen::Vector3d::UnitZ(), down_slope = incline * Eigen::Vector3d::UnitX();
  for (ShapeType type : {ShapeType::kSphere, ShapeType::kCylinder}) {
    for (double h : {1e-3, 1e-2}) {
      ContactSetup setup;
      setup.environment = {groundPlane(normal, mu)};
      setup.bodies = {collisionShape(type, Eigen::Vector3d(radius, length, 0), mu, 0.0)};
      // The cylinder's axis (its z) across the slope.
      const Eigen::Quaterniond q = incline * Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Eigen::Vector3d::UnitX()));
      const MassProperties mass = massOf(type, Eigen::Vector3d(radius, length, 0), 1.0);
      const Eigen::Vector3d start = radius * normal;
      Scene scene({body(mass, start, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())}, IntegratorType::kRk4, h,
                  IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      double lift = 0.0;
      for (int i = 0; i < static_cast<int>(std::llround(1.0 / h)); ++i) {
        scene.step(1);
        lift = std::max(lift, (scene.state().p_WB - start).dot(normal));
      }
      const double k = type == ShapeType::kSphere ? 5.0 / 7.0 : 2.0 / 3.0;
      const double expected = 0.5 * k * kG * std::sin(theta);
      const std::string what = std::string(shapeTypeName(type)) + " h " + std::to_string(h);
      EXPECT_NEAR((scene.state().p_WB - start).dot(down_slope), expected, 0.01 * expected) << what;
      EXPECT_LE(lift, slop) << what;
    }
  }
}

// Impacts resolved at the step's end (no event location) never gain energy: a ball with e = 1 keeps its drop
// height over a hundred bounces (it used to climb by the depth the projection lifted it out of at each one),
// and one with e = 0.8 only loses. The energy is read as the height z + v²/(2g) the ball's motion reaches.
// Nor do they lose the bounce: found at the step's end, the ball is up to d ≤ v h + g h² deep and leaves at
// e times its speed there, so its first apex is at least e² (drop + d) − d ≥ e² drop − v h (a new contact
// taken as one that was touching the step before would not bounce at all).
TEST(ContactRegimes, ImpactsResolvedAtTheStepsEndNeverGainEnergy) {
  const double radius = 0.1, drop = 1.0;
  for (double h : {1e-3, 1e-2}) {
    for (double e : {1.0, 0.8}) {
      ContactSetup setup;
      setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.5, e)};
      setup.bodies = {collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, e)};
      setup.settings.event_location = false;
      Scene scene({body(MassProperties::sphere(1.0, radius), Eigen::Vector3d(0, 0, radius + drop),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())},
                  IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      double highest = 0.0, first_apex = 0.0;
      for (int i = 0; i < static_cast<int>(std::llround(45.0 / h)); ++i) {  // ~100 bounces of 0.9 s for e = 1
        scene.step(1);
        const double vz = scene.state().P_W.z();
        highest = std::max(highest, scene.state().p_WB.z() - radius + vz * vz / (2.0 * kG));
        // The first flight back up: the impact at √(2 drop / g) = 0.45 s, the apex 0.36–0.45 s later.
        const double t = (i + 1) * h;
        if (t > 0.5 && t < 1.1) first_apex = std::max(first_apex, scene.state().p_WB.z() - radius);
      }
      EXPECT_LE(highest, drop * (1.0 + 1e-9)) << "h " << h << " e " << e;
      EXPECT_GE(first_apex, e * e * drop - std::sqrt(2.0 * kG * drop) * h) << "h " << h << " e " << e;
    }
  }
}

// Newton's cradle and its relatives: a row of touching equal balls (e = 1, no friction) struck by one or two
// moving ones. The impulse travels through the row pair by pair, so the textbook result holds: as many balls
// leave the far end, at the speed that came in, as struck; the rest stand still; momentum and energy to 1e-9.
// (Solved at once, the touching contacts share the impact and the three-ball cradle ends at (−1/3, 2/3, 2/3) v.)
TEST(ContactRegimes, NewtonsCradleSendsTheImpactThroughTheRow) {
  const double radius = 0.05, speed = 1.5;
  const MassProperties ball = MassProperties::sphere(1.0, radius);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  for (int resting : {2, 4}) {
    for (int striking : {1, 2}) {
      for (double h : {1e-3, 1e-2}) {
        ContactSetup setup;
        std::vector<BodyDefinition> balls;
        for (int i = 0; i < striking + resting; ++i) {
          setup.bodies.push_back(collisionShape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0));
          const bool moving = i < striking;
          // The striking balls touch each other, 0.37 of a step's travel off the step grid from the row.
          const double x = moving ? -(0.2 + 0.37 * speed * h) - 2.0 * radius * (striking - i) : 2.0 * radius * (i - striking);
          balls.push_back(body(ball, Eigen::Vector3d(x, 0, 0), Eigen::Quaterniond::Identity(),
                               moving ? Eigen::Vector3d(speed, 0, 0) : zero, zero, zero));
        }
        Scene scene(balls, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
        scene.step(static_cast<std::int64_t>(std::llround(0.5 / h)));
        const std::size_t n = balls.size();
        double momentum = 0.0, energy = 0.0;
        const std::string what = std::to_string(striking) + " on " + std::to_string(resting) + ", h " + std::to_string(h);
        for (std::size_t i = 0; i < n; ++i) {
          const double expected = i + striking >= n ? speed : 0.0;
          EXPECT_NEAR(scene.state(i).P_W.x(), expected, 1e-9) << what << ", ball " << i;
          momentum += scene.state(i).P_W.x();
          energy += kineticEnergy(ball, scene.state(i));
        }
        EXPECT_NEAR(momentum, striking * speed, 1e-9) << what;
        EXPECT_NEAR(energy, 0.5 * striking * speed * speed, 1e-9) << what;
      }
    }
  }
}

// A 1 000 : 1 pair of boxes stacked on the ground, the upper one set off the lower one's centre, in both
// orders: it stands for 5 s, the upper box sinking less than the penetration slop, sliding less than it and
// turning less than the slop across the box's width. (The heavy box's weight reaches the ground through the
// light one only as fast as the sweeps carry it across the mass ratio: a small scene's solve runs until it
// converges, within its budget.)
TEST(ContactRegimes, AThousandToOneMassRatioStandsInEitherOrder) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  const double slop = ContactSettings().penetration_slop;
  for (double ratio : {1000.0, 1e-3}) {
    for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kSemiImplicitEuler}) {
      ContactSetup setup;
      setup.environment = {groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
      setup.bodies = {collisionShape(ShapeType::kBox, size, 0.5, 0.0), collisionShape(ShapeType::kBox, size, 0.5, 0.0)};
      const Eigen::Vector3d upper(0.03, 0.02, 0.3);
      Scene scene({body(MassProperties::box(1.0, size), Eigen::Vector3d(0, 0, 0.1), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
                   body(MassProperties::box(ratio, size), upper, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                        Eigen::Vector3d::Zero())},
                  type, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      scene.step(5000);
      const State& top = scene.state(1);
      const std::string what = "ratio " + std::to_string(ratio) + " " + integratorName(type);
      EXPECT_GT(top.p_WB.z() - upper.z(), -slop) << what;
      EXPECT_LT((top.p_WB - upper).head<2>().norm(), slop) << what;
      EXPECT_LT(Eigen::AngleAxisd(top.q_WB).angle(), slop / size.x()) << what;
      EXPECT_LE(scene.contactStatistics().max_penetration, slop) << what;
    }
  }
}

// Two boxes pushed into each other through their inputs, hard (an acceleration of 1 000 and 3 000 g... per
// kilogram: 1 000 and 3 000 N on 1 kg), from touching and from 0.3 m apart, aligned and 3 cm off: they never
// pass through each other, and no step leaves them deeper in each other than the slop plus what one step of
// the pushing does to their relative position (a h², both boxes at a = F/M towards each other). Offset, the
// pair turns and slides round itself, which is physics, not tunnelling.
TEST(ContactRegimes, BodiesPushedIntoEachOtherNeverPass) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  const double slop = ContactSettings().penetration_slop;
  for (double force : {1000.0, 3000.0}) {
    for (double h : {1e-3, 1e-2}) {
      for (double gap : {0.0, 0.3}) {
        for (double offset : {0.0, 0.03}) {
          ContactSetup setup;
          setup.bodies = {collisionShape(ShapeType::kBox, size, 0.5, 0.0), collisionShape(ShapeType::kBox, size, 0.5, 0.0)};
          const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
          BodyDefinition a = body(MassProperties::box(1.0, size), Eigen::Vector3d(-0.1 - 0.5 * gap, 0, 0),
                                  Eigen::Quaterniond::Identity(), zero, zero, zero);
          BodyDefinition b = body(MassProperties::box(1.0, size), Eigen::Vector3d(0.1 + 0.5 * gap, offset, 0),
                                  Eigen::Quaterniond::Identity(), zero, zero, zero);
          a.takes_input = b.takes_input = true;
          Scene scene({a, b}, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
          AppliedWrench push_a, push_b;
          push_a.world.force = Eigen::Vector3d(force, 0, 0);
          push_b.world.force = Eigen::Vector3d(-force, 0, 0);
          scene.setInput(0, push_a);
          scene.setInput(1, push_b);
          scene.step(static_cast<std::int64_t>(std::llround(0.5 / h)));
          const std::string what = std::to_string(force) + " N, h " + std::to_string(h) + ", gap " +
                                   std::to_string(gap) + ", offset " + std::to_string(offset);
          EXPECT_LE(scene.contactStatistics().max_penetration, slop + force * h * h) << what;
          ASSERT_TRUE(isFinite(scene.state(0)) && isFinite(scene.state(1))) << what;
        }
      }
    }
  }
}

// The start-up check goes body by body through the broad phase and stops at the first conflict: 5 000 boxes
// at one point are refused, naming two of them, as any pair inside another is (before, the broad phase paired
// all 12.5 million pairs as the bodies entered it, and the check took every one).
TEST(ContactRegimes, ThousandsOfBodiesAtOnePointAreRefusedNamingTwo) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2), zero = Eigen::Vector3d::Zero();
  ContactSetup setup;
  std::vector<BodyDefinition> boxes;
  for (int i = 0; i < 5000; ++i) {
    setup.bodies.push_back(collisionShape(ShapeType::kBox, size, 0.5, 0.0));
    setup.bodies.back()->name = "box" + std::to_string(i);
    boxes.push_back(body(MassProperties::box(1.0, size), Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity(), zero, zero));
  }
  try {
    Scene scene(boxes, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    FAIL() << "5 000 boxes at one point were accepted";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("box"), std::string::npos) << message;
    EXPECT_NE(message.find(" starts inside box"), std::string::npos) << message;
  }
}

// A body wholly inside a closed environment mesh touches none of its triangles, so no pair distance sees it:
// the point-in-mesh test does, at start-up and for a state set from outside, which is refused with a message
// naming both while a state outside is taken.
TEST(ContactRegimes, ABodyInsideAClosedMeshIsRefusedAtStartAndWhenSet) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2), zero = Eigen::Vector3d::Zero();
  CollisionShape hut;
  hut.type = ShapeType::kMesh;
  hut.name = "hut";
  hut.mesh = primitives::box(Eigen::Vector3d(2.0, 2.0, 2.0));
  ContactSetup setup;
  setup.environment = {hut};
  setup.bodies = {collisionShape(ShapeType::kBox, size, 0.5, 0.0)};
  setup.bodies[0]->name = "crate";
  const MassProperties crate = MassProperties::box(1.0, size);
  for (const Eigen::Vector3d& inside : {Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(-0.7, 0.6, -0.5)}) {
    try {
      Scene scene({body(crate, inside, Eigen::Quaterniond::Identity(), zero, zero, zero)}, IntegratorType::kRk4, 1e-3,
                  IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      FAIL() << "a crate inside the closed mesh was accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find("crate starts inside hut"), std::string::npos) << error.what();
    }
  }
  WorldSettings settings;
  settings.owns_clock = true;
  World world({body(crate, Eigen::Vector3d(3, 0.2, 0.3), Eigen::Quaterniond::Identity(), zero, zero, zero)},
              IntegratorType::kRk4, IntegratorSettings(), settings, StepAssembly::kLeaveOut, setup);
  State state = world.scene().state(0);
  for (const Eigen::Vector3d& refused : {Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0.95, 0, 0)}) {
    state.p_WB = refused;
    const CommandReply reply = world.setState(0, state, 0);
    EXPECT_FALSE(reply.accepted) << "at " << refused.transpose();
    EXPECT_NE(reply.message.find("crate would be inside hut"), std::string::npos) << reply.message;
  }
  EXPECT_EQ(world.scene().state(0).p_WB, Eigen::Vector3d(3, 0.2, 0.3));  // nothing lost
  state.p_WB = Eigen::Vector3d(1.5, 0, 0);
  EXPECT_TRUE(world.setState(0, state, 0).accepted);
}

TEST(ContactRegimes, ABoxTippingOverAnEdgePivotsAboutItAndLandsOnItsSide) {
  // A 0.05 × 0.15 × 0.2 m box standing on its end, leaning 0.35 rad (past its tipping angle atan(0.025/0.1)),
  // μ = 0.8 (far more than the pivot needs): the edge sticks while the box turns about it, so the edge stays
  // where it was to the step's second-order error (ω² R h² a step, ~1e-7 m at the turn rates of the first
  // 0.11 s, at h = 1 ms), and the side lands within the slop. A body whose free step turned it by ω = L/I₀
  // instead of its full inertia crept 1.5 mm in 0.11 s at every step size and landed 0.63 mm deep.
  const Eigen::Vector3d size(0.05, 0.15, 0.2);
  const Eigen::Vector3d pivot_B(0.025, 0.0, -0.1);  // the lowest edge, its middle
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()));
  for (const bool table : {false, true}) {
    for (const double h : {1e-3, 2.5e-4}) {
      ContactSetup setup;
      setup.settings.sleep = false;
      if (table) {
        CollisionShape box = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(1.0, 1.0, 0.2), 0.8, 0.0);
        box.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
        setup.environment = {box};
      } else {
        setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.8)};
      }
      setup.bodies = {reference::collisionShape(ShapeType::kBox, size, 0.8, 0.0)};
      const Eigen::Vector3d start(0.0, 0.0, 1e-6);
      Scene scene({reference::contactBody(MassProperties::box(1.0, size), start - q * pivot_B, q, Eigen::Vector3d::Zero(),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -9.81))},
                  IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      scene.step(static_cast<std::int64_t>(std::llround(0.11 / h)));
      const Eigen::Vector3d edge = scene.state(0).p_WB + scene.state(0).q_WB * pivot_B;
      EXPECT_LT((edge - start).head<2>().norm(), 1e-5) << "table " << table << ", h " << h;
      scene.step(static_cast<std::int64_t>(std::llround(0.9 / h)));
      EXPECT_NEAR(scene.state(0).p_WB.z(), 0.025, 2e-4) << "table " << table << ", h " << h;  // on its side
      EXPECT_LE(scene.contactStatistics().max_penetration, 1e-4) << "table " << table << ", h " << h;
    }
  }
}
