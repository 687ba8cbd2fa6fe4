// Scenes of several bodies and the step assembled from the terms a scene declares.
#include <gtest/gtest.h>

#include <tuple>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/step_terms.hpp"

using namespace rigid_body;

namespace {

const MassProperties kBox = MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1));

ForceModel gravity(double g) {
  ForceModel forces;
  forces.gravity_W = Eigen::Vector3d(0.0, 0.0, -g);
  return forces;
}

// Gravity with both dampings: every force term of the step.
ForceModel dampedFall() {
  ForceModel forces = gravity(9.81);
  forces.linear_damping = 0.3;
  forces.angular_damping = 0.02;
  return forces;
}

const MassProperties kSphere = MassProperties::sphere(2.0, 0.3);

State spinning(const MassProperties& mass, const Eigen::Vector3d& w_B) {
  return stateFromVelocities(mass, Eigen::Vector3d(1.0, 2.0, 3.0),
                             Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -2, 0.5).normalized())),
                             Eigen::Vector3d(0.3, -0.2, 0.1), w_B);
}

}  // namespace

TEST(StepTerms, AZeroGBoxAtRestWithoutInputNeedsOnlyTranslation) {
  const StepTerms terms = assembleTerms(kBox, ForceModel{}, State{}, false);
  EXPECT_FALSE(terms.gravity);
  EXPECT_FALSE(terms.input);
  EXPECT_FALSE(terms.linear_damping);
  EXPECT_FALSE(terms.angular_damping);
  EXPECT_FALSE(terms.rotation);
  EXPECT_EQ(describeTerms(terms), "translation");
}

TEST(StepTerms, EachDeclaredForceModelAddsItsTerm) {
  ForceModel forces = gravity(9.81);
  forces.linear_damping = 0.5;
  forces.angular_damping = 0.1;
  const StepTerms terms = assembleTerms(kBox, forces, State{}, true);
  EXPECT_TRUE(terms.gravity);
  EXPECT_TRUE(terms.input);
  EXPECT_TRUE(terms.linear_damping);
  EXPECT_TRUE(terms.rotation);  // an input may carry a torque
  EXPECT_TRUE(terms.angular_damping);
  EXPECT_TRUE(terms.world_inertia);
  EXPECT_EQ(terms, StepTerms::all());
  // Without input and spin, ω stays 0 and so does the angular damping torque: both are left out.
  const StepTerms still = assembleTerms(kBox, forces, State{}, false);
  EXPECT_FALSE(still.rotation);
  EXPECT_FALSE(still.angular_damping);
  EXPECT_TRUE(still.linear_damping);
}

TEST(StepTerms, SpinNeedsRotationAndAnIsotropicBodySkipsTheWorldInertia) {
  const MassProperties sphere = MassProperties::sphere(2.0, 0.3);
  const StepTerms sphere_terms = assembleTerms(sphere, ForceModel{}, spinning(sphere, Eigen::Vector3d(1, 2, 3)), false);
  EXPECT_TRUE(sphere_terms.rotation);
  EXPECT_FALSE(sphere_terms.world_inertia);
  EXPECT_NE(describeTerms(sphere_terms).find("isotropic"), std::string::npos);
  const StepTerms box_terms = assembleTerms(kBox, ForceModel{}, spinning(kBox, Eigen::Vector3d(1, 2, 3)), false);
  EXPECT_TRUE(box_terms.rotation);
  EXPECT_TRUE(box_terms.world_inertia);
}

TEST(StepTerms, AColliderAtRestTurnsByItsFullInertiaAndAngularDamping) {
  // A contact off the centre of mass can make it spin at any step: a colliding box at rest, without input,
  // gets the rotation with its world inertia (not the isotropic shortcut ω = L/I₀) and its angular damping.
  ForceModel forces = gravity(9.81);
  forces.angular_damping = 0.1;
  const StepTerms collider = assembleTerms(kBox, forces, State{}, false, true);
  EXPECT_TRUE(collider.rotation);
  EXPECT_TRUE(collider.world_inertia);
  EXPECT_TRUE(collider.angular_damping);
  EXPECT_FALSE(collider.input);
  // And so in a scene, whatever its step assembly leaves out of the others.
  ContactSetup setup;
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
  setup.bodies = {reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(0.4, 0.2, 0.1), 0.5, 0.0), std::nullopt};
  State above;
  above.p_WB = Eigen::Vector3d(0, 0, 1);
  const Scene scene({{Model{kBox, forces}, above, false}, {Model{kBox, forces}, above, false}}, IntegratorType::kRk4,
                    0.001, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  EXPECT_TRUE(scene.terms(0).world_inertia && scene.terms(0).angular_damping);
  EXPECT_FALSE(scene.terms(1).rotation);
}

TEST(Scene, AZeroGSceneHasNoGravityTermAndAFallingOneHas) {
  const Scene space({{Model{kBox, ForceModel{}}, State{}, true}}, IntegratorType::kRk4, 0.001);
  EXPECT_FALSE(space.terms(0).gravity);
  const Scene falling({{Model{kBox, gravity(9.81)}, State{}, false}}, IntegratorType::kRk4, 0.001);
  EXPECT_TRUE(falling.terms(0).gravity);
  EXPECT_FALSE(falling.terms(0).rotation);
  // The general assembly keeps every term whatever the scene.
  const Scene general({{Model{kBox, ForceModel{}}, State{}, false}}, IntegratorType::kRk4, 0.001, IntegratorSettings(),
                      StepAssembly::kGeneral);
  EXPECT_EQ(general.terms(0), StepTerms::all());
}

TEST(Scene, EachBodyMovesOnlyUnderItsOwnWrench) {
  const std::vector<BodyDefinition> bodies = {
      {Model{kBox, gravity(9.81)}, spinning(kBox, Eigen::Vector3d(0.5, 2.0, 0.1)), true},
      {Model{MassProperties::sphere(3.0, 0.2), gravity(9.81)}, State{}, true},
      {Model{MassProperties::cylinder(0.5, 0.05, 0.6), gravity(9.81)}, spinning(kBox, Eigen::Vector3d(0, 0, 4)), true}};
  Scene scene(bodies, IntegratorType::kRk4, 0.001);
  AppliedWrench push;
  push.world.force = Eigen::Vector3d(3.0, 0.0, 0.0);
  push.body.torque = Eigen::Vector3d(0.0, 0.1, 0.0);
  scene.setInput(1, push);
  scene.step(500);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    // The same body alone, with the same input: the scene adds nothing between bodies.
    Scene alone({bodies[i]}, IntegratorType::kRk4, 0.001);
    if (i == 1) alone.setInput(0, push);
    alone.step(500);
    EXPECT_EQ(scene.state(i).p_WB, alone.state().p_WB) << "body " << i;
    EXPECT_EQ(scene.state(i).q_WB.coeffs(), alone.state().q_WB.coeffs()) << "body " << i;
    EXPECT_EQ(scene.state(i).L_W, alone.state().L_W) << "body " << i;
  }
  // Body 1 was pushed along x and turned about y; the others only fell.
  EXPECT_NEAR(scene.state(1).p_WB.x(), 0.5 * (3.0 / 3.0) * 0.25, 1e-12);
  EXPECT_GT(scene.state(1).L_W.norm(), 0.0);
  EXPECT_NEAR(scene.state(0).p_WB.x(), 1.0 + 0.3 * 0.5, 1e-12);
}

TEST(Scene, ABodyWithoutInputRefusesAWrenchAndSpinBringsRotationBack) {
  Scene scene({{Model{kBox, ForceModel{}}, State{}, false}}, IntegratorType::kRk4, 0.001);
  AppliedWrench push;
  push.world.force.x() = 1.0;
  EXPECT_THROW(scene.setInput(0, push), std::invalid_argument);
  EXPECT_NO_THROW(scene.setInput(0, AppliedWrench()));
  EXPECT_FALSE(scene.terms(0).rotation);
  ASSERT_TRUE(scene.setState(0, spinning(kBox, Eigen::Vector3d(0.0, 0.0, 2.0))));
  EXPECT_TRUE(scene.terms(0).rotation);  // set_state gave it spin: its step turns it again
  const Eigen::Quaterniond before = scene.state(0).q_WB;
  scene.step(100);
  EXPECT_NEAR(rotationAngleBetween(before, scene.state(0).q_WB), 0.2, 1e-9);
  scene.reset();
  EXPECT_FALSE(scene.terms(0).rotation);  // the initial state at rest again
}

TEST(Scene, ADivergingBodyStopsAloneWhileTheOthersGoOn) {
  State blowing;
  blowing.P_W = Eigen::Vector3d(1.79e308, 0.0, 0.0);  // overflows within a few steps of the push
  Scene scene({{Model{kBox, gravity(9.81)}, State{}, false}, {Model{kBox, gravity(9.81)}, State{}, true}},
                   IntegratorType::kExplicitEuler, 0.001);
  AppliedWrench huge;
  huge.world.force = Eigen::Vector3d(1e308, 0.0, 0.0);
  scene.setInput(1, huge);
  scene.setState(1, blowing);
  const SceneStepResult result = scene.step(10);
  EXPECT_TRUE(result.diverged);
  EXPECT_EQ(scene.divergence(0), Divergence::kNone);
  EXPECT_EQ(scene.divergence(1), Divergence::kNonFiniteState);
  EXPECT_EQ(scene.firstDiverged(), 1u);
  EXPECT_LT(scene.state(0).p_WB.z(), 0.0);  // body 0 fell
  EXPECT_EQ(scene.state(1).P_W.x(), 1.79e308);  // body 1 kept its last good state
  scene.reset();
  EXPECT_EQ(scene.firstDiverged(), scene.bodyCount());
}

// The specialised step (only the declared terms) against the general one (every term), 2000 steps of 1 ms,
// on the cases where both apply: the same trajectory to rounding.
class SpecialisedStep : public ::testing::TestWithParam<IntegratorType> {};

TEST_P(SpecialisedStep, GivesTheGeneralStepsTrajectoryToRounding) {
  const ForceModel damped = dampedFall();
  const MassProperties sphere = kSphere;
  const std::vector<BodyDefinition> cases = {
      {Model{kBox, ForceModel{}}, State{}, false},                                           // at rest in space
      {Model{kBox, gravity(9.81)}, spinning(kBox, Eigen::Vector3d::Zero()), false},          // falling, no spin
      {Model{kBox, damped}, spinning(kBox, Eigen::Vector3d::Zero()), false},                 // damped fall
      {Model{sphere, gravity(9.81)}, spinning(sphere, Eigen::Vector3d(1.0, 5.0, -2.0)), false},  // isotropic
      {Model{sphere, damped}, spinning(sphere, Eigen::Vector3d(1.0, 5.0, -2.0)), true},      // isotropic, input
      {Model{kBox, ForceModel{}}, spinning(kBox, Eigen::Vector3d(0.1, 3.0, 0.2)), false},    // torque-free
  };
  AppliedWrench input;
  input.world.force = Eigen::Vector3d(0.5, 0.0, 1.0);
  input.body.torque = Eigen::Vector3d(0.01, 0.0, -0.02);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    Scene specialised({cases[i]}, GetParam(), 0.001);
    Scene general({cases[i]}, GetParam(), 0.001, IntegratorSettings(), StepAssembly::kGeneral);
    if (cases[i].takes_input) {
      specialised.setInput(0, input);
      general.setInput(0, input);
    }
    specialised.step(2000);
    general.step(2000);
    const State& a = specialised.state();
    const State& b = general.state();
    const double scale = 1.0 + b.p_WB.norm();
    EXPECT_LE((a.p_WB - b.p_WB).norm(), 1e-12 * scale) << "case " << i;
    EXPECT_LE((a.P_W - b.P_W).norm(), 1e-12 * (1.0 + b.P_W.norm())) << "case " << i;
    EXPECT_LE((a.L_W - b.L_W).norm(), 1e-12 * (1.0 + b.L_W.norm())) << "case " << i;
    EXPECT_LE(rotationAngleBetween(a.q_WB, b.q_WB), 1e-11) << "case " << i;
    EXPECT_NE(specialised.terms(), StepTerms::all()) << "case " << i << " left nothing out";
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, SpecialisedStep, ::testing::ValuesIn(allIntegrators()),
                         [](const ::testing::TestParamInfo<IntegratorType>& info) { return integratorName(info.param); });

// Threads and blocks: every body's step is the same arithmetic on any thread and in any block, so the whole
// scene's trajectory is identical bit for bit for any thread count and block size, a diverging body included.
class ThreadedStep : public ::testing::TestWithParam<IntegratorType> {};

TEST_P(ThreadedStep, GivesTheOneThreadTrajectoryBitForBit) {
  const ForceModel damped = dampedFall();
  const MassProperties sphere = kSphere;
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < 150; ++i) {
    const MassProperties& mass = i % 2 ? kBox : sphere;
    State initial = spinning(mass, Eigen::Vector3d(0.1 * (i % 7), 3.0 - 0.05 * i, 0.2));
    initial.p_WB.x() += i;
    bodies.push_back({Model{mass, i % 3 ? damped : gravity(1.0 + 0.01 * i)}, initial, i % 4 != 0});
  }
  AppliedWrench huge;  // body 61 overflows under it: it diverges and keeps its last good state
  huge.world.force = Eigen::Vector3d(1e308, 0.0, 0.0);
  bodies[61].initial.P_W.x() = 1.79e308;
  const auto run = [&](std::size_t threads, std::size_t per_block, bool wide) {
    Scene scene(bodies, GetParam(), 0.001);
    scene.setThreads(threads, per_block);
    scene.setWideLanes(wide);
    std::vector<SceneStepResult> results;
    for (int call = 0; call < 3; ++call) {
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        if (!bodies[b].takes_input) continue;
        AppliedWrench input;
        input.world.force = Eigen::Vector3d(0.1 * call, -0.2, 0.05 * b);
        input.body.torque = Eigen::Vector3d(0.01, 0.002 * call, -0.02);
        scene.setInput(b, b == 61 ? huge : input);
      }
      results.push_back(scene.step(7));
    }
    return std::make_pair(std::move(scene), results);
  };
  const auto reference = run(1, Scene::kBodiesPerBlock, true);
  ASSERT_EQ(reference.first.divergence(61), Divergence::kNonFiniteState);
  ASSERT_TRUE(reference.second[0].diverged || reference.second[1].diverged || reference.second[2].diverged);
  // (threads, bodies per block, wide lanes where the CPU has them)
  for (const auto& [threads, per_block, wide] : std::vector<std::tuple<std::size_t, std::size_t, bool>>{
           {2, 64, true}, {3, 7, true}, {4, 1, true}, {2, 150, true}, {1, 64, false}, {2, 7, false}}) {
    const auto other = run(threads, per_block, wide);
    EXPECT_EQ(other.first.threads(), threads);
    for (std::size_t call = 0; call < 3; ++call) {
      EXPECT_EQ(other.second[call].steps, reference.second[call].steps);
      EXPECT_EQ(other.second[call].status, reference.second[call].status);
      EXPECT_EQ(other.second[call].diverged, reference.second[call].diverged);
    }
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const State& a = other.first.state(b);
      const State& r = reference.first.state(b);
      ASSERT_TRUE(a.p_WB == r.p_WB && a.q_WB.coeffs() == r.q_WB.coeffs() && a.P_W == r.P_W && a.L_W == r.L_W)
          << threads << " threads, blocks of " << per_block << (wide ? "" : ", portable lanes") << ": body " << b
          << " differs";
      EXPECT_EQ(other.first.divergence(b), reference.first.divergence(b));
      EXPECT_EQ(other.first.integratedSteps(b), reference.first.integratedSteps(b));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, ThreadedStep, ::testing::ValuesIn(allIntegrators()),
                         [](const ::testing::TestParamInfo<IntegratorType>& info) { return integratorName(info.param); });

// A scene steps explicit Euler, semi-implicit Euler and rk4 bodies four at a time (one per vector lane); each
// must still take the steps Integrator::step takes for it alone, bit for bit, whatever its neighbours in the
// batch, on 256-bit (AVX) lanes and on the portable ones alike, and whichever instruction set the lone step
// runs in.
class BatchedStep : public ::testing::TestWithParam<std::tuple<IntegratorType, bool>> {};

TEST_P(BatchedStep, GivesEachBodyItsOwnIntegratorStepsBitForBit) {
  const auto [type, wide] = GetParam();
  const ForceModel damped = dampedFall();
  const MassProperties sphere = kSphere;
  std::vector<BodyDefinition> bodies;
  const MassProperties cylinder = MassProperties::cylinder(1.5, 0.1, 0.4);  // a symmetric top
  for (int i = 0; i < 17; ++i) {  // kinds of terms and of bodies interleaved, batches left partly empty
    const MassProperties& mass = i % 3 == 0 ? sphere : (i % 3 == 1 ? kBox : cylinder);
    bodies.push_back({Model{mass, i % 2 ? damped : ForceModel{}},
                      spinning(mass, Eigen::Vector3d(0.3 * i, 2.0, -0.1 * i)), i % 2 == 1});
  }
  // Bodies whose principal axes are not their body axes, and more spheres and cylinders, one of each spinning
  // at 300 rad/s: semi-implicit Euler's 1/|q| (a general body's) and its sines and cosines (a sphere's, a
  // cylinder's) then take their series in some lanes of a batch and the library's functions in another.
  Eigen::Matrix3d full;
  full << 0.02, 0.001, -0.002, 0.001, 0.05, 0.003, -0.002, 0.003, 0.06;
  const MassProperties general = MassProperties::fromInertia(1.5, full);
  for (int i = 0; i < 10; ++i) {
    const MassProperties& mass = i < 5 ? general : (i < 7 ? sphere : cylinder);
    const double rate = i == 2 || i == 6 || i == 9 ? 300.0 : 2.0 + i;
    bodies.push_back({Model{mass, damped}, spinning(mass, Eigen::Vector3d(0.3, -0.2 * i, 1.0).normalized() * rate), true});
  }
  Scene scene(bodies, type, 0.001);
  if (scene.setWideLanes(wide) != wide) GTEST_SKIP() << "this CPU has no AVX";
  std::vector<AppliedWrench> inputs(bodies.size());
  for (std::size_t b = 1; b < bodies.size(); b += 2) {  // body parts in some lanes of a batch, not in others
    inputs[b].world.force = Eigen::Vector3d(0.2, -0.1 * b, 1.0);
    if (b % 3 != 0) inputs[b].body.torque = Eigen::Vector3d(0.01 * b, 0.0, -0.02);
    if (b % 4 == 1) inputs[b].body.force = Eigen::Vector3d(0.0, 0.5, 0.0);
    if (b % 5 == 0) inputs[b].world.torque = Eigen::Vector3d(0.0, -0.03, 0.01);
    scene.setInput(b, inputs[b]);
  }
  ASSERT_EQ(scene.step(50).steps, 50);
  // The lone step in both of its instruction sets (IntegratorSettings::wide_instructions: AVX-512 where the
  // CPU has it, the build's own where not or off).
  for (const bool wide_alone : {true, false}) {
    IntegratorSettings settings;
    settings.wide_instructions = wide_alone;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      Integrator alone(type, settings);
      State state = bodies[b].initial;
      for (int k = 0; k < 50; ++k) ASSERT_EQ(alone.step(bodies[b].model, scene.terms(b), inputs[b], 0.001, state), StepStatus::kOk);
      const State& batched = scene.state(b);
      EXPECT_TRUE(batched.p_WB == state.p_WB && batched.q_WB.coeffs() == state.q_WB.coeffs() && batched.P_W == state.P_W &&
                  batched.L_W == state.L_W && batched.t == state.t)
          << "body " << b << (wide_alone ? "" : ", alone in the baseline instruction set") << ": "
          << (batched.p_WB - state.p_WB).norm() << " m apart";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, BatchedStep, ::testing::Combine(::testing::ValuesIn(allIntegrators()), ::testing::Bool()),
                         [](const ::testing::TestParamInfo<std::tuple<IntegratorType, bool>>& info) {
                           return integratorName(std::get<0>(info.param)) + (std::get<1>(info.param) ? "_wide" : "_portable");
                         });
