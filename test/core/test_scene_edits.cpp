// Bodies added and removed between steps (Scene::addBody, removeBody; World's with inputs and waiting
// commands): the other bodies step on bit for bit, indices move down after a removal with everything a
// body owns, a colliding arrival meets the others, a refused edit changes nothing.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/world.hpp"

using namespace rigid_body;

namespace {

constexpr double kH = 1e-3;
const Eigen::Vector3d kDown(0.0, 0.0, -9.81);
const Eigen::Vector3d kBoxSize(0.2, 0.2, 0.2);

// Free body i: a box of its own mass, spin and velocity, under gravity and damping (every rk4 term).
BodyDefinition freeBody(int i) {
  Model model{MassProperties::box(1.0 + 0.3 * i, Eigen::Vector3d(0.4, 0.2 + 0.01 * i, 0.1)), ForceModel{}};
  model.forces.gravity_W = kDown;
  model.forces.linear_damping = 0.05 * (i % 3);
  model.forces.angular_damping = 0.01 * (i % 2);
  State initial = stateFromVelocities(model.mass, Eigen::Vector3d(i, -i, 2.0 * i), Eigen::Quaterniond::Identity(),
                                      Eigen::Vector3d(0.5, 0.1 * i, 3.0), Eigen::Vector3d(0.2 * i, 4.0, -0.3));
  return BodyDefinition{model, initial, true};
}

AppliedWrench force(const Eigen::Vector3d& f, const Eigen::Vector3d& torque_B = Eigen::Vector3d::Zero()) {
  AppliedWrench wrench;
  wrench.world.force = f;
  wrench.body.torque = torque_B;
  return wrench;
}

void expectSameBits(const State& a, const State& b, const std::string& what) {
  EXPECT_EQ(a.p_WB, b.p_WB) << what;
  EXPECT_EQ(a.q_WB.coeffs(), b.q_WB.coeffs()) << what;
  EXPECT_EQ(a.P_W, b.P_W) << what;
  EXPECT_EQ(a.L_W, b.L_W) << what;
}

// A 1 kg, 0.2 m box at rest at p, under gravity, with a wrench input.
BodyDefinition boxAt(const Eigen::Vector3d& p) {
  BodyDefinition box = reference::contactBody(MassProperties::box(1.0, kBoxSize), p, Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown);
  box.takes_input = true;
  return box;
}

CollisionShape boxShape(const std::string& name) {
  CollisionShape shape = reference::collisionShape(ShapeType::kBox, kBoxSize, 0.5, 0.0);
  shape.name = name;
  return shape;
}

ContactSetup groundOnly() {
  ContactSetup setup;
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
  return setup;
}

}  // namespace

// Nine free bodies cross the four-body batches and the lone tail; the edits shuffle which bodies share a
// batch. A wrong shift after the removal (states, inputs, integrator memory or terms left at the old index)
// or a lane whose arithmetic depended on its neighbours would show as a changed bit.
TEST(SceneEdits, FreeBodiesStepOnBitForBitWhileOthersAreAddedAndRemoved) {
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < 9; ++i) bodies.push_back(freeBody(i));
  Scene edited(bodies, IntegratorType::kRk4, kH);
  Scene reference(bodies, IntegratorType::kRk4, kH);
  for (Scene* scene : {&edited, &reference}) {
    scene->setInput(5, force(Eigen::Vector3d(1.0, -2.0, 3.0), Eigen::Vector3d(0.0, 0.1, 0.0)));
    scene->setInput(8, force(Eigen::Vector3d(0.0, 0.0, 9.0)));
    scene->step(300);
  }
  const std::size_t added = edited.addBody(freeBody(11));
  ASSERT_EQ(added, 9u);
  Scene alone({BodyDefinition{freeBody(11).model, freeBody(11).initial, true}}, IntegratorType::kRk4, kH);
  edited.step(300);
  reference.step(300);
  alone.step(300);
  edited.removeBody(2);
  ASSERT_EQ(edited.bodyCount(), 9u);
  edited.step(300);
  reference.step(300);
  alone.step(300);
  for (std::size_t body = 0; body < 9; ++body) {
    if (body == 2) continue;
    const std::size_t now = body < 2 ? body : body - 1;
    expectSameBits(edited.state(now), reference.state(body), "body " + std::to_string(body));
    EXPECT_EQ(edited.input(now), reference.input(body)) << "body " << body;
  }
  expectSameBits(edited.state(8), alone.state(0), "the added body");
  EXPECT_EQ(edited.integratedSteps(8), 600);
}

TEST(SceneEdits, ThreadedStepsOfAnEditedSceneGiveTheOneThreadBits) {
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < 13; ++i) bodies.push_back(freeBody(i));
  Scene one(bodies, IntegratorType::kRk4, kH);
  Scene two(bodies, IntegratorType::kRk4, kH);
  two.setThreads(2, 3);  // blocks of three bodies: the edits move bodies across blocks
  for (Scene* scene : {&one, &two}) {
    scene->removeBody(0);
    scene->addBody(freeBody(20));
    scene->removeBody(6);
    scene->step(200);
  }
  for (std::size_t body = 0; body < one.bodyCount(); ++body) {
    expectSameBits(two.state(body), one.state(body), "body " + std::to_string(body));
  }
}

TEST(SceneEdits, AnAddedColliderLandsOnTheGroundAndOnABoxAlreadyThere) {
  ContactSetup setup = groundOnly();
  setup.bodies = {boxShape("base")};
  Scene scene({boxAt(Eigen::Vector3d(0, 0, 0.1))}, IntegratorType::kRk4, kH, IntegratorSettings(),
              StepAssembly::kLeaveOut, setup);
  scene.step(100);
  // A free body first (the contact step keeps its memory), then a box dropped 0.3 m above the base.
  scene.addBody(freeBody(1));
  const std::size_t dropped = scene.addBody(boxAt(Eigen::Vector3d(0.05, 0.0, 0.5)), boxShape("dropped"));
  EXPECT_TRUE(scene.collides(dropped));
  EXPECT_FALSE(scene.collides(1));
  EXPECT_EQ(scene.collidingBodies(), 2u);
  scene.step(1500);
  // It rests on the base (top face at 0.2 m), not in it nor on the ground through it.
  EXPECT_NEAR(scene.state(dropped).p_WB.z(), 0.3, 2e-3);
  EXPECT_NEAR(scene.state(0).p_WB.z(), 0.1, 2e-3);
  EXPECT_LT(linearVelocity(scene.model(dropped).mass, scene.state(dropped)).norm(), 1e-2);
}

TEST(SceneEdits, AColliderInsideAnotherOrTheGroundIsRefusedNamingBothAndNothingChanges) {
  ContactSetup setup = groundOnly();
  setup.bodies = {boxShape("base"), std::nullopt};
  const std::vector<BodyDefinition> bodies = {boxAt(Eigen::Vector3d(0, 0, 0.1)), freeBody(3)};
  Scene scene(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  Scene reference(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(50);
  reference.step(50);
  struct Case {
    Eigen::Vector3d at;
    const char* other;
  };
  for (const Case& c : {Case{Eigen::Vector3d(0.1, 0.0, 0.15), "base"}, Case{Eigen::Vector3d(3.0, 0.0, 0.05), "ground"}}) {
    try {
      scene.addBody(boxAt(c.at), boxShape("intruder"));
      ADD_FAILURE() << "an intruder overlapping " << c.other << " was added";
    } catch (const std::invalid_argument& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("intruder"), std::string::npos) << message;
      EXPECT_NE(message.find(c.other), std::string::npos) << message;
    }
  }
  // Just clear of the base (1 mm gap) is accepted.
  EXPECT_EQ(scene.bodyCount(), 2u);
  EXPECT_EQ(scene.collidingBodies(), 1u);
  scene.step(200);
  reference.step(200);
  expectSameBits(scene.state(0), reference.state(0), "base");
  expectSameBits(scene.state(1), reference.state(1), "free body");
  EXPECT_NO_THROW(scene.addBody(boxAt(Eigen::Vector3d(0.0, 0.201, 0.1)), boxShape("neighbour")));
}

// The top box of a two-box stack falls to the ground when the bottom one goes: the contact step must
// forget the removed box and read the top one at its new index.
TEST(SceneEdits, RemovingTheBottomBoxOfAStackLetsTheTopOneFallToTheGround) {
  ContactSetup setup = groundOnly();
  setup.bodies = {std::nullopt, boxShape("bottom"), boxShape("top")};
  Scene scene({freeBody(0), boxAt(Eigen::Vector3d(0, 0, 0.1)), boxAt(Eigen::Vector3d(0, 0, 0.3))},
              IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(500);
  EXPECT_NEAR(scene.state(2).p_WB.z(), 0.3, 2e-3);
  scene.removeBody(1);
  ASSERT_EQ(scene.collidingBodies(), 1u);
  ASSERT_TRUE(scene.collides(1));
  // Free fall of 0.2 m takes √(2·0.2/g) = 0.2 s; after 1 s it rests on the ground.
  scene.step(100);
  EXPECT_LT(scene.state(1).p_WB.z(), 0.3 - 0.5 * 9.81 * 0.1 * 0.1 + 1e-3);
  scene.step(900);
  EXPECT_NEAR(scene.state(1).p_WB.z(), 0.1, 2e-3);
}

// A free body's removal keeps the contact step's memory (warm starts, touching pairs): the colliders after
// it read their new indices and step on as before, bit for bit.
TEST(SceneEdits, RemovingAFreeBodyLeavesTheCollidersTrajectoriesBitForBit) {
  ContactSetup setup = groundOnly();
  setup.bodies = {std::nullopt, boxShape("bottom"), std::nullopt, boxShape("top")};
  const std::vector<BodyDefinition> bodies = {freeBody(0), boxAt(Eigen::Vector3d(0, 0, 0.1)), freeBody(2),
                                              boxAt(Eigen::Vector3d(0.03, 0, 0.3))};
  Scene edited(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  Scene reference(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  for (Scene* scene : {&edited, &reference}) {
    scene->setInput(3, force(Eigen::Vector3d(2.0, 1.0, 0.0)));  // the top box slides on the bottom one
    scene->step(200);
  }
  edited.removeBody(0);
  edited.step(400);
  reference.step(400);
  expectSameBits(edited.state(0), reference.state(1), "bottom");
  expectSameBits(edited.state(1), reference.state(2), "free body");
  expectSameBits(edited.state(2), reference.state(3), "top");
  EXPECT_EQ(edited.contactCount(2), reference.contactCount(3));
}

TEST(SceneEdits, TheOnlyBodyAndABodyOutOfRangeAreNotRemoved) {
  Scene scene({freeBody(0)}, IntegratorType::kRk4, kH);
  EXPECT_THROW(scene.removeBody(0), std::invalid_argument);
  EXPECT_THROW(scene.removeBody(1), std::invalid_argument);
  BodyDefinition bad = freeBody(1);
  bad.initial.p_WB.x() = std::nan("");
  EXPECT_THROW(scene.addBody(bad), std::invalid_argument);
  EXPECT_EQ(scene.bodyCount(), 1u);
}

TEST(SceneEdits, ResetTakesAnAddedBodyBackToTheStateItWasAddedIn) {
  Scene scene({freeBody(0)}, IntegratorType::kRk4, kH);
  scene.step(10);
  const std::size_t added = scene.addBody(freeBody(4));
  scene.step(500);
  scene.reset();
  expectSameBits(scene.state(added), freeBody(4).initial, "added body");
  expectSameBits(scene.state(0), freeBody(0).initial, "first body");
}

// The World moves inputs and waiting commands down with their bodies: a timed wrench on the third body acts
// on it as the second after the first is removed; the removed body's own commands are dropped.
TEST(WorldEdits, TimedWrenchesAndWaitingCommandsFollowTheirBodiesAfterARemoval) {
  WorldSettings settings;
  settings.dt = kH;
  const std::vector<BodyDefinition> three = {freeBody(0), freeBody(1), freeBody(2)};
  const std::vector<BodyDefinition> two = {freeBody(1), freeBody(2)};
  World edited(three, IntegratorType::kRk4, IntegratorSettings(), settings);
  World reference(two, IntegratorType::kRk4, IntegratorSettings(), settings);
  edited.start(0);
  reference.start(0);
  ASSERT_TRUE(edited.applyWrench(2, force(Eigen::Vector3d(0, 3, 0)), 0, 0.5, 0).accepted);
  ASSERT_TRUE(reference.applyWrench(1, force(Eigen::Vector3d(0, 3, 0)), 0, 0.5, 0).accepted);
  // Waiting commands: at 0.2 s on the clock, for bodies 0 (dropped with it) and 1 (becomes 0).
  ASSERT_TRUE(edited.setWrench(0, force(Eigen::Vector3d(50, 0, 0)), toNanoseconds(0.2)).accepted);
  ASSERT_TRUE(edited.setWrench(1, force(Eigen::Vector3d(0, 0, 4)), toNanoseconds(0.2)).accepted);
  ASSERT_TRUE(reference.setWrench(0, force(Eigen::Vector3d(0, 0, 4)), toNanoseconds(0.2)).accepted);
  EXPECT_EQ(edited.pendingCommands(), 2u);
  ASSERT_TRUE(edited.removeBody(0).accepted);
  EXPECT_EQ(edited.pendingCommands(), 1u);
  edited.update(toNanoseconds(1.0));
  reference.update(toNanoseconds(1.0));
  ASSERT_EQ(edited.bodyCount(), 2u);
  for (std::size_t body = 0; body < 2; ++body) {
    expectSameBits(edited.scene().state(body), reference.scene().state(body), "body " + std::to_string(body));
  }
  EXPECT_FALSE(edited.removeBody(5).accepted);
}

TEST(WorldEdits, AnAddedBodyTakesWrenchesAndARefusedOneSaysWhy) {
  WorldSettings settings;
  settings.dt = kH;
  ContactSetup setup = groundOnly();
  setup.bodies = {boxShape("base")};
  World world({boxAt(Eigen::Vector3d(0, 0, 0.1))}, IntegratorType::kRk4, IntegratorSettings(), settings,
              StepAssembly::kLeaveOut, setup);
  world.start(0);
  world.update(toNanoseconds(0.1));
  std::size_t index = 0;
  const CommandReply refused = world.addBody(boxAt(Eigen::Vector3d(0, 0, 0.15)), boxShape("late"), &index);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.message.find("base"), std::string::npos) << refused.message;
  BodyDefinition pushed = freeBody(0);
  pushed.model.forces = ForceModel{};
  pushed.initial = State();
  ASSERT_TRUE(world.addBody(pushed, std::nullopt, &index).accepted);
  EXPECT_EQ(index, 1u);
  // 2 N for 0.5 s on 1 kg: 1 m/s, exact to one step of the window.
  ASSERT_TRUE(world.applyWrench(index, force(Eigen::Vector3d(2.0, 0, 0)), 0, 0.5, world.stamp()).accepted);
  world.update(toNanoseconds(1.0));
  EXPECT_NEAR(linearVelocity(world.scene().model(index).mass, world.scene().state(index)).x(), 1.0, 1e-9);
}
