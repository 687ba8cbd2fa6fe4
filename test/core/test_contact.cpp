// Contact against closed forms (docs/references.md, "Contact"): a bouncing ball, a block sliding to a stop,
// a block on an incline that sticks or slides, a sphere rolling down an incline, an elastic head-on
// collision, a rod's impact against the impulse formula, resting boxes and a stack, a fast sphere and a thin
// plate; and the scene without colliders unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

using reference::collisionShape;
using reference::groundPlane;

CollisionShape plane(const Eigen::Vector3d& normal, double offset, double friction, double restitution = 0.0) {
  return groundPlane(normal, friction, restitution, offset);
}

CollisionShape shapeOf(ShapeType type, const Eigen::Vector3d& size, double friction, double restitution) {
  return collisionShape(type, size, friction, restitution);
}

BodyDefinition body(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                    const Eigen::Vector3d& v, const Eigen::Vector3d& gravity) {
  return reference::contactBody(mass, p, q, v, Eigen::Vector3d::Zero(), gravity);
}

const Eigen::Vector3d kDown(0.0, 0.0, -kG);

// A body on a plane through the origin tilted by theta about y (down-slope is −x' along the plane).
struct Incline {
  double theta;
  Eigen::Quaterniond q() const { return Eigen::Quaterniond(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY())); }
  Eigen::Vector3d normal() const { return q() * Eigen::Vector3d::UnitZ(); }
  Eigen::Vector3d downSlope() const { return q() * Eigen::Vector3d::UnitX(); }
};

// `height` boxes (0.3 × 0.3 × 0.2 m, 1 kg, μ = 0.5) stacked on the ground, touching, at h = 1 ms.
Scene boxStack(int height, IntegratorType type) {
  const Eigen::Vector3d size(0.3, 0.3, 0.2);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  std::vector<BodyDefinition> boxes;
  for (int i = 0; i < height; ++i) {
    boxes.push_back(body(MassProperties::box(1.0, size), Eigen::Vector3d(0, 0, 0.1 + 0.2 * i),
                         Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), kDown));
    setup.bodies.push_back(shapeOf(ShapeType::kBox, size, 0.5, 0.0));
  }
  return Scene(boxes, type, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

}  // namespace

TEST(Contact, BouncingBallMeetsTheGroundAtSqrt2hOverGAndReboundsToE2nH) {
  const double radius = 0.1, h0 = 1.0, e = 0.5;
  const MassProperties ball = MassProperties::sphere(1.0, radius);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  setup.bodies = {shapeOf(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, e)};
  Scene scene({body(ball, Eigen::Vector3d(0, 0, radius + h0), Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                    kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  std::vector<double> apexes;
  double previous_vz = 0.0;
  for (int i = 0; i < 4000 && apexes.size() < 5; ++i) {
    scene.step(1);
    const State& s = scene.state();
    const double vz = s.P_W.z();
    // In free flight z + v²/(2g) is the apex height of the arc the ball is on; read it as v_z turns negative.
    if (previous_vz > 0.0 && vz <= 0.0) apexes.push_back(s.p_WB.z() - radius + vz * vz / (2.0 * kG));
    previous_vz = vz;
  }
  ASSERT_EQ(apexes.size(), 5u);
  for (std::size_t n = 1; n <= 5; ++n) {
    const double expected = std::pow(e, 2.0 * n) * h0;
    EXPECT_NEAR(apexes[n - 1], expected, 1e-6 * expected) << "after bounce " << n;
  }
  ASSERT_GE(scene.impacts().size(), 5u);
  const double t1 = std::sqrt(2.0 * h0 / kG);
  EXPECT_NEAR(scene.impacts()[0].time, t1, 1e-6 * t1);
  // Bounce n + 1 follows bounce n after a flight of 2 eⁿ v₁/g.
  const double v1 = kG * t1;
  double expected_time = t1;
  for (std::size_t n = 1; n < 5; ++n) {
    expected_time += 2.0 * std::pow(e, n) * v1 / kG;
    EXPECT_NEAR(scene.impacts()[n].time, expected_time, 1e-6 * expected_time) << "impact " << n + 1;
  }
}

TEST(Contact, ABlockSlidingWithFrictionStopsAfterV0SquaredOver2MuG) {
  const double mu = 0.4, v0 = 2.0;
  const Eigen::Vector3d size(0.2, 0.2, 0.1);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, mu)};
  setup.bodies = {shapeOf(ShapeType::kBox, size, mu, 0.0)};
  Scene scene({body(MassProperties::box(2.0, size), Eigen::Vector3d(0, 0, 0.05), Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d(v0, 0, 0), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  const double stop_time = v0 / (mu * kG), stop_distance = v0 * v0 / (2.0 * mu * kG);
  double stopped_at = -1.0;
  for (int i = 1; i <= 2000; ++i) {
    scene.step(1);
    if (stopped_at < 0.0 && scene.state().P_W.x() <= 1e-9) stopped_at = i * 1e-3;
  }
  EXPECT_NEAR(stopped_at, stop_time, 5e-3 * stop_time);
  EXPECT_NEAR(scene.state().p_WB.x(), stop_distance, 5e-3 * stop_distance);
  EXPECT_NEAR(scene.state().p_WB.z(), 0.05, 1e-3);  // on the ground, neither sunk nor lifted
}

TEST(Contact, ABlockOnAnInclineSticksBelowTheFrictionAngleAndSlidesAboveIt) {
  const Incline incline{20.0 * kPi / 180.0};
  const Eigen::Vector3d size(0.2, 0.2, 0.1);
  for (double mu : {0.5, 0.2}) {
    ContactSetup setup;
    setup.environment = {plane(incline.normal(), 0.0, mu)};
    setup.bodies = {shapeOf(ShapeType::kBox, size, mu, 0.0)};
    const Eigen::Vector3d start = 0.05 * incline.normal();
    Scene scene({body(MassProperties::box(1.0, size), start, incline.q(), Eigen::Vector3d::Zero(), kDown)},
                IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    const double duration = mu > std::tan(incline.theta) ? 5.0 : 1.0;
    scene.step(static_cast<std::int64_t>(std::llround(duration / 1e-3)));
    const double travelled = (scene.state().p_WB - start).dot(incline.downSlope());
    if (mu > std::tan(incline.theta)) {
      EXPECT_LT((scene.state().p_WB - start).norm(), 1e-3) << "mu " << mu << ": it should stick";
    } else {
      const double a = kG * (std::sin(incline.theta) - mu * std::cos(incline.theta));
      EXPECT_NEAR(travelled, 0.5 * a * duration * duration, 0.01 * 0.5 * a * duration * duration) << "mu " << mu;
    }
  }
}

TEST(Contact, ASphereRollsDownAnInclineWithoutSlippingAtFiveSeventhsGSinTheta) {
  const Incline incline{25.0 * kPi / 180.0};
  const double radius = 0.1, mu = 0.6;
  ContactSetup setup;
  setup.environment = {plane(incline.normal(), 0.0, mu)};
  setup.bodies = {shapeOf(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), mu, 0.0)};
  const Eigen::Vector3d start = radius * incline.normal();
  Scene scene({body(MassProperties::sphere(1.0, radius), start, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                    kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(1000);
  const double a = 5.0 / 7.0 * kG * std::sin(incline.theta);
  const double travelled = (scene.state().p_WB - start).dot(incline.downSlope());
  EXPECT_NEAR(travelled, 0.5 * a, 0.01 * 0.5 * a);  // a sliding sphere would travel 7/5 as far
  // Rolling: the contact point is at rest, v = ω × (r n).
  const Eigen::Vector3d v = linearVelocity(scene.model().mass, scene.state());
  const Eigen::Vector3d w = angularVelocity(scene.model().mass, scene.state());
  EXPECT_LT((v + w.cross(-radius * incline.normal())).norm(), 1e-6 * v.norm());
}

TEST(Contact, EqualSpheresHeadOnWithRestitutionOneExchangeVelocities) {
  const double radius = 0.1;
  const MassProperties ball = MassProperties::sphere(1.0, radius);
  ContactSetup setup;
  setup.bodies = {shapeOf(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0),
                  shapeOf(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0)};
  const Eigen::Vector3d va(1.5, 0, 0), vb(-0.5, 0, 0);
  Scene scene({body(ball, Eigen::Vector3d(-0.5, 0, 0), Eigen::Quaterniond::Identity(), va, Eigen::Vector3d::Zero()),
               body(ball, Eigen::Vector3d(0.5, 0, 0), Eigen::Quaterniond::Identity(), vb, Eigen::Vector3d::Zero())},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  const double energy = kineticEnergy(ball, scene.state(0)) + kineticEnergy(ball, scene.state(1));
  const Eigen::Vector3d momentum = scene.state(0).P_W + scene.state(1).P_W;
  scene.step(1000);
  ASSERT_EQ(scene.impacts().size(), 1u);
  EXPECT_NEAR(scene.impacts()[0].time, 0.8 / 2.0, 1e-9);  // the gap of 0.8 m closes at 2 m/s
  EXPECT_LT((scene.state(0).P_W - vb).norm(), 1e-9);
  EXPECT_LT((scene.state(1).P_W - va).norm(), 1e-9);
  EXPECT_LT((scene.state(0).P_W + scene.state(1).P_W - momentum).norm(), 1e-9);
  EXPECT_NEAR(kineticEnergy(ball, scene.state(0)) + kineticEnergy(ball, scene.state(1)), energy, 1e-9 * energy);
}

TEST(Contact, ATiltedRodLandsWithTheImpulseOfTheFormula) {
  // A capsule rod (radius r, straight part l along its z axis) tilted by 30° about y, dropped from rest: it
  // meets the ground with its lower end's hemisphere, at one point.
  const double r = 0.02, l = 1.0, m = 2.0, e = 0.5, tilt = 30.0 * kPi / 180.0, drop = 0.2;
  const MassProperties rod = MassProperties::cylinder(m, r, l + 2.0 * r);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d centre(0.0, 0.0, 0.5 * l * axis.z() + r + drop);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.0)};
  setup.bodies = {shapeOf(ShapeType::kCapsule, Eigen::Vector3d(r, l, 0), 0.0, e)};
  Scene scene({body(rod, centre, q, Eigen::Vector3d::Zero(), kDown)}, IntegratorType::kRk4, 1e-3,
              IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  const double impact_time = std::sqrt(2.0 * drop / kG);
  const std::int64_t impact_step = static_cast<std::int64_t>(std::ceil(impact_time / 1e-3));
  scene.step(impact_step);
  ASSERT_EQ(scene.impacts().size(), 1u);
  EXPECT_NEAR(scene.impacts()[0].time, impact_time, 1e-9);
  // Baraff & Witkin's impulse: j = −(1+e) v⁻·n / (1/M + n·(I⁻¹(r×n))×r), then Δv = j n/M, ΔL = r × j n.
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d lever = -0.5 * l * axis - r * n;  // lowest point of the lower hemisphere
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d I_inv = R * rod.inverseInertia() * R.transpose();
  const Eigen::Vector3d v_minus(0.0, 0.0, -kG * impact_time);
  const double j = -(1.0 + e) * v_minus.dot(n) / (1.0 / m + n.dot((I_inv * lever.cross(n)).cross(lever)));
  // After the impact, free flight for the rest of the step: v grows by g Δt; L about the centre is constant.
  const double rest = impact_step * 1e-3 - impact_time;
  const Eigen::Vector3d P_expected = m * (v_minus + j * n / m) + m * kDown * rest;
  const Eigen::Vector3d L_expected = lever.cross(j * n);
  EXPECT_LT((scene.state().P_W - P_expected).norm(), 1e-9 * P_expected.norm());
  EXPECT_LT((scene.state().L_W - L_expected).norm(), 1e-9 * L_expected.norm());
}

TEST(Contact, ABoxRestsOnTheGroundWithoutSinkingDriftingOrGainingEnergy) {
  const Eigen::Vector3d size(0.4, 0.2, 0.1);
  const MassProperties box = MassProperties::box(1.0, size);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  setup.bodies = {shapeOf(ShapeType::kBox, size, 0.5, 0.0)};
  const Eigen::Vector3d start(0.3, -0.2, 0.05);
  Scene scene({body(box, start, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), kDown)}, IntegratorType::kRk4,
              1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  const double energy = potentialEnergy(box, scene.model().forces, scene.state());
  scene.setRecordContacts(true);
  scene.step(10000);
  EXPECT_EQ(scene.contacts(0).size(), 4u);  // its four bottom corners
  EXPECT_LE(scene.contactStatistics().max_penetration, 1e-3);
  EXPECT_LT((scene.state().p_WB - start).head<2>().norm(), 1e-6);
  EXPECT_NEAR(scene.state().p_WB.z(), 0.05, 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(scene.state().q_WB).angle(), 1e-6);
  EXPECT_LE(kineticEnergy(box, scene.state()) + potentialEnergy(box, scene.model().forces, scene.state()),
            energy + 1e-6);
  for (const Contact& contact : scene.contacts(0)) {
    EXPECT_FALSE(contact.other.is_body);
    EXPECT_LT((contact.normal_W - Eigen::Vector3d::UnitZ()).norm(), 1e-9);
  }
}

TEST(Contact, AStackOfTenBoxesStandsForTenSeconds) {
  Scene scene = boxStack(10, IntegratorType::kRk4);
  scene.step(10000);
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_LT((scene.state(i).p_WB - scene.initialState(i).p_WB).norm(), 2e-3) << "box " << i;
  }
  EXPECT_LE(scene.contactStatistics().max_penetration, 1e-3);
}

// Static friction holds a point where it began to stick. A velocity-level solve leaves a little slip at
// each interface of a tall stack every step, and without a memory of where the points stuck those slips add
// up (the stack of 20 walks its top box ~1 cm in 10 s); the friction anchors take them back. Each
// interface's slip is the horizontal offset of a box's bottom-face centre from the top-face centre of the box
// below (the ground's point under the bottom box for the first), which the boxes' tilts move only to second
// order; it must stay within the penetration slop, the tolerance the normal direction has.
TEST(Contact, TheBoxesOfAStackOfTwentyDoNotSlipOnEachOther) {
  const Eigen::Vector3d half_height(0.0, 0.0, 0.1);
  const double slop = ContactSettings().penetration_slop;
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    Scene scene = boxStack(20, type);
    double slip = 0.0;
    for (int second = 0; second < 10; ++second) {
      scene.step(1000);
      Eigen::Vector3d below = Eigen::Vector3d::Zero();  // the top-face centre of what is below (the ground's origin)
      for (std::size_t i = 0; i < 20; ++i) {
        const State& box = scene.state(i);
        const Eigen::Vector3d bottom = box.p_WB - box.q_WB * half_height;
        slip = std::max(slip, (bottom - below).head<2>().norm());
        below = box.p_WB + box.q_WB * half_height;
      }
    }
    EXPECT_LT(slip, slop) << integratorName(type);
  }
}

TEST(Contact, AFastSphereDoesNotTunnelThroughAThinPlate) {
  const double radius = 0.05;
  CollisionShape plate = shapeOf(ShapeType::kBox, Eigen::Vector3d(1.0, 1.0, 0.01), 0.5, 0.0);
  plate.name = "plate";
  ContactSetup setup;
  setup.environment = {plate};
  setup.bodies = {shapeOf(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, 0.0)};
  Scene scene({body(MassProperties::sphere(0.5, radius), Eigen::Vector3d(0, 0, 1.0), Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d(0, 0, -100.0), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(200);
  EXPECT_GT(scene.state().p_WB.z(), 0.005 + radius - 1e-3);  // on the plate's top face, not below it
  EXPECT_LT(scene.state().P_W.norm(), 0.5 * 0.1);             // and stopped there
  EXPECT_GE(scene.contactStatistics().swept_impacts + scene.contactStatistics().located_impacts, 1);
}

TEST(Contact, ABodyStartingInsideAnotherIsRefusedNamingBoth) {
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  CollisionShape crate = shapeOf(ShapeType::kBox, Eigen::Vector3d(0.2, 0.2, 0.2), 0.5, 0.0);
  crate.name = "crate";
  setup.bodies = {crate};
  try {
    Scene scene({body(MassProperties::box(1.0, Eigen::Vector3d(0.2, 0.2, 0.2)), Eigen::Vector3d(0, 0, 0.05),
                      Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), kDown)},
                IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    FAIL() << "a crate half in the ground was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("crate"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("ground"), std::string::npos) << error.what();
  }
}

TEST(Contact, ABodyWithoutCollisionStepsExactlyAsInAScenewithoutContact) {
  const MassProperties box = MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1));
  BodyDefinition free = body(box, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0), kDown);
  free.initial.L_W = Eigen::Vector3d(0.01, 0.2, 0.01);
  BodyDefinition ball = body(MassProperties::sphere(1.0, 0.1), Eigen::Vector3d(3, 0, 0.5), Eigen::Quaterniond::Identity(),
                             Eigen::Vector3d::Zero(), kDown);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  setup.bodies = {std::nullopt, shapeOf(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.5, 0.0)};
  Scene with_contact({free, ball}, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  Scene without({free}, IntegratorType::kRk4, 1e-3);
  EXPECT_FALSE(without.hasContact());
  EXPECT_TRUE(with_contact.hasContact());
  EXPECT_FALSE(with_contact.collides(0));
  for (int i = 0; i < 2000; ++i) {
    with_contact.step(1);
    without.step(1);
  }
  // Bit for bit: the body without a shape never enters the contact step (it falls through the ground).
  EXPECT_EQ(with_contact.state(0).p_WB, without.state(0).p_WB);
  EXPECT_EQ(with_contact.state(0).q_WB.coeffs(), without.state(0).q_WB.coeffs());
  EXPECT_EQ(with_contact.state(0).L_W, without.state(0).L_W);
  EXPECT_LT(with_contact.state(0).p_WB.z(), -5.0);
  EXPECT_NEAR(with_contact.state(1).p_WB.z(), 0.1, 1e-3);  // the ball with a shape lands and stays
}

TEST(Contact, ACollidingBodyWhoseStepIsRefusedStopsAloneWhileTheBodiesSteppedBesideItGoOn) {
  // Four boxes of one kind resting apart (their free steps run side by side, in one batch of lanes where
  // the integrator has them); the second is driven to overflow. It keeps its last good state and stops; the
  // others' trajectories are those of a scene without the push, to the bit (the continuous test off: the
  // pushed body's speed would split the steps of the whole scene, docs/contact.md "No tunnelling").
  const IntegratorType types[] = {IntegratorType::kRk4, IntegratorType::kSemiImplicitEuler, IntegratorType::kDopri5};
  for (const IntegratorType type : types) {
    const auto scene = [type](bool push) {
      ContactSetup setup;
      setup.settings.continuous = false;
      setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
      std::vector<BodyDefinition> bodies;
      for (int i = 0; i < 4; ++i) {
        BodyDefinition b = body(MassProperties::box(1.0, Eigen::Vector3d(0.2, 0.2, 0.2)),
                                Eigen::Vector3d(0.5 * i, 0, 0.1), Eigen::Quaterniond::Identity(),
                                Eigen::Vector3d(0.1 * i, 0, 0), kDown);
        b.takes_input = true;
        bodies.push_back(b);
        setup.bodies.push_back(shapeOf(ShapeType::kBox, Eigen::Vector3d(0.2, 0.2, 0.2), 0.5, 0.0));
      }
      auto made = std::make_unique<Scene>(bodies, type, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
      if (push) {
        State blowing = made->state(1);
        blowing.P_W = Eigen::Vector3d(0.0, 1.79e308, 0.0);  // overflows within a few steps of the push
        AppliedWrench huge;
        huge.world.force = Eigen::Vector3d(0.0, 1e308, 0.0);
        made->setInput(1, huge);
        made->setState(1, blowing);
      }
      return made;
    };
    const auto pushed = scene(true), calm = scene(false);
    const SceneStepResult result = pushed->step(20);
    calm->step(20);
    EXPECT_TRUE(result.diverged) << integratorName(type);
    EXPECT_EQ(pushed->divergence(1), Divergence::kNonFiniteState) << integratorName(type);
    EXPECT_TRUE(pushed->state(1).P_W.allFinite() && pushed->state(1).p_WB.allFinite()) << integratorName(type);
    EXPECT_LT(pushed->integratedSteps(1), 20) << integratorName(type);
    for (const std::size_t i : {0u, 2u, 3u}) {
      EXPECT_EQ(pushed->divergence(i), Divergence::kNone) << integratorName(type) << ", body " << i;
      EXPECT_EQ(pushed->integratedSteps(i), 20) << integratorName(type) << ", body " << i;
      EXPECT_EQ(pushed->state(i).p_WB, calm->state(i).p_WB) << integratorName(type) << ", body " << i;
      EXPECT_EQ(pushed->state(i).P_W, calm->state(i).P_W) << integratorName(type) << ", body " << i;
      EXPECT_EQ(pushed->state(i).L_W, calm->state(i).L_W) << integratorName(type) << ", body " << i;
    }
  }
}

TEST(Contact, ExtremeStatesAndWrenchesNeverGiveANonFiniteStateOrACrash) {
  // A pile of shapes on the ground and in a thin-walled bin, driven by wrenches and states from 1e-300 to
  // 1e300 and hurled beyond the contact range: every state stays finite, the scene keeps stepping.
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.5)};
  CollisionShape wall = shapeOf(ShapeType::kBox, Eigen::Vector3d(0.01, 2.0, 1.0), 0.5, 0.0);
  wall.pose.translation() = Eigen::Vector3d(1.0, 0.0, 0.5);
  setup.environment.push_back(wall);
  std::vector<BodyDefinition> bodies;
  const std::vector<ShapeType> types = {ShapeType::kBox, ShapeType::kSphere, ShapeType::kCylinder, ShapeType::kCapsule};
  for (int i = 0; i < 8; ++i) {
    BodyDefinition b = body(MassProperties::box(1.0, Eigen::Vector3d(0.2, 0.2, 0.2)), Eigen::Vector3d(0.25 * i - 1.0, 0, 0.15),
                            Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), kDown);
    b.takes_input = true;
    bodies.push_back(b);
    setup.bodies.push_back(shapeOf(types[i % 4], Eigen::Vector3d(0.1, 0.1, 0.1), 0.5, i % 2 ? 1.0 : 0.0));
  }
  Scene scene(bodies, IntegratorType::kSemiImplicitEuler, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  std::uint64_t seed = 12345;
  auto uniform = [&seed]() {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * (1.0 / 9007199254740992.0);
  };
  auto extreme = [&]() {
    const double magnitude = std::pow(10.0, -300.0 + 600.0 * uniform());
    return (uniform() < 0.5 ? -1.0 : 1.0) * (uniform() < 0.2 ? 0.0 : magnitude);
  };
  for (int round = 0; round < 300; ++round) {
    const std::size_t k = static_cast<std::size_t>(uniform() * 8) % 8;
    if (uniform() < 0.5) {
      AppliedWrench input;
      input.world.force = Eigen::Vector3d(extreme(), extreme(), extreme());
      input.world.torque = Eigen::Vector3d(extreme(), extreme(), extreme());
      scene.setInput(k, input);
    } else if (uniform() < 0.3) {
      State state = scene.state(k);
      state.p_WB = Eigen::Vector3d(extreme(), extreme(), std::abs(extreme()));
      state.P_W = Eigen::Vector3d(extreme(), extreme(), extreme());
      state.L_W = Eigen::Vector3d(extreme(), extreme(), extreme());
      scene.setState(k, state);
    } else {
      scene.setInput(k, AppliedWrench());
    }
    scene.step(1 + static_cast<std::int64_t>(uniform() * 20));
    for (std::size_t b = 0; b < scene.bodyCount(); ++b) {
      ASSERT_TRUE(isFinite(scene.state(b))) << "body " << b << " in round " << round;
      for (const Contact& contact : scene.contacts(b)) {
        ASSERT_TRUE(contact.position_W.allFinite() && contact.normal_W.allFinite() &&
                    std::isfinite(contact.normal_impulse) && contact.friction_impulse_W.allFinite());
      }
    }
    if (round % 50 == 49) scene.reset();
  }
}

TEST(Contact, EveryIntegratorRestsABoxAndStopsASlidingOne) {
  // The contact step takes every integrator's free motion; the position update matches the method's own
  // response to a constant force, so each rests exactly and stops a sliding box where physics says.
  const double mu = 0.4, v0 = 2.0;
  const Eigen::Vector3d size(0.2, 0.2, 0.1);
  for (IntegratorType type : allIntegrators()) {
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, mu)};
    setup.bodies = {shapeOf(ShapeType::kBox, size, mu, 0.0), shapeOf(ShapeType::kBox, size, mu, 0.0)};
    Scene scene({body(MassProperties::box(2.0, size), Eigen::Vector3d(0, 0, 0.05), Eigen::Quaterniond::Identity(),
                      Eigen::Vector3d::Zero(), kDown),
                 body(MassProperties::box(2.0, size), Eigen::Vector3d(0, 1, 0.05), Eigen::Quaterniond::Identity(),
                      Eigen::Vector3d(v0, 0, 0), kDown)},
                type, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
    scene.step(2000);
    const std::string name = integratorName(type);
    EXPECT_LT((scene.state(0).p_WB - Eigen::Vector3d(0, 0, 0.05)).norm(), 1e-9) << name << ": the resting box moved";
    const double stop_distance = v0 * v0 / (2.0 * mu * kG);
    EXPECT_NEAR(scene.state(1).p_WB.x(), stop_distance, 5e-3 * stop_distance) << name;
    EXPECT_NEAR(scene.state(1).p_WB.z(), 0.05, 1e-6) << name;
  }
}

namespace {

// A ball and a spinning box thrown about inside four walls 1 m from the origin, with or without 1 996 more
// half-spaces 50 m away all around: each body tests only the half-spaces in its reach at its last scan
// until it has moved as far as the nearest other one was beyond its reach then (collision_world.cpp,
// addPlanePoints). The walls start out of reach and come into it as the bodies fly at them.
Scene thrownBetweenWalls(bool far_walls) {
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0, 0.3)};
  for (const Eigen::Vector3d& n : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                   Eigen::Vector3d(0, -1, 0)}) {
    setup.environment.push_back(plane(n, -1.0, 0.3, 0.8));  // solid beyond 1 m
  }
  for (int k = 0; far_walls && k < 1996; ++k) {
    const double angle = 2.0 * kPi * k / 1996.0;
    setup.environment.push_back(plane(Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0), -50.0, 0.3));
  }
  setup.settings.sleep = false;
  setup.bodies = {shapeOf(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.3, 0.8),
                  shapeOf(ShapeType::kBox, Eigen::Vector3d(0.2, 0.15, 0.1), 0.3, 0.8)};
  Scene scene({body(MassProperties::sphere(1.0, 0.1), Eigen::Vector3d(0.0, 0.0, 0.3), Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d(4.0, 2.5, 0.0), kDown),
               reference::contactBody(MassProperties::box(1.0, Eigen::Vector3d(0.2, 0.15, 0.1)), Eigen::Vector3d(0.3, -0.4, 0.2),
                                      Eigen::Quaterniond::Identity(), Eigen::Vector3d(-3.0, 1.7, 1.0),
                                      Eigen::Vector3d(2.0, -5.0, 8.0), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(2000);
  return scene;
}

}  // namespace

TEST(Contact, HalfSpacesFarAwayChangeNothingAndTheNearOnesStillStopBodies) {
  const Scene walls = thrownBetweenWalls(false), among_many = thrownBetweenWalls(true);
  for (std::size_t b = 0; b < 2; ++b) {
    const State& r = walls.state(b);
    const State& o = among_many.state(b);
    // Kept between the walls (4 and 3.5 m/s for 2 s would have carried either far beyond them).
    EXPECT_LT(r.p_WB.head<2>().cwiseAbs().maxCoeff(), 1.0) << "body " << b;
    EXPECT_EQ(r.p_WB, o.p_WB) << "body " << b;
    EXPECT_EQ(r.P_W, o.P_W) << "body " << b;
    EXPECT_EQ(r.L_W, o.L_W) << "body " << b;
    EXPECT_EQ(r.q_WB.coeffs(), o.q_WB.coeffs()) << "body " << b;
  }
}
