// Islands of the resting solve (docs/contact.md, "Islands"): bodies are grouped by the contacts between them
// and never through the environment; each island's solve is its own (its convergence, its results whatever
// else the lists hold); and a scene with contact steps to the same bits on any number of threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <vector>

#include "../../src/contact/solver_islands.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/thread_pool.hpp"

using namespace rigid_body;
using namespace rigid_body::contact;

namespace {

constexpr double kG = 9.81;
constexpr double kH = 1e-3;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
const Eigen::Vector3d kBox(0.3, 0.3, 0.2);

TEST(ContactIslands, PointsAreGroupedByTheBodiesTheyLinkNeverThroughTheEnvironment) {
  // Bodies 0–5, environment objects 6 and 7. Body 0 touches only the environment: an island of its own.
  const std::vector<std::pair<std::size_t, std::size_t>> links{{3, 6}, {1, 2}, {4, 5}, {0, 7},
                                                                {2, 6}, {5, 3}, {6, 1}};
  SolverIslands islands;
  islands.group(links, 6);
  ASSERT_EQ(islands.islands(), 3u);
  // Numbered by their smallest body ({0}, {1, 2}, {3, 4, 5}), each island's points in their given order.
  EXPECT_EQ(islands.order(), (std::vector<std::size_t>{3, 1, 4, 6, 0, 2, 5}));
  EXPECT_EQ(islands.islandStart(0), 0u);
  EXPECT_EQ(islands.islandStart(1), 1u);
  EXPECT_EQ(islands.islandStart(2), 4u);
  EXPECT_EQ(islands.islandStart(3), 7u);
  // The same links in another order make the same islands, numbered the same.
  const std::vector<std::pair<std::size_t, std::size_t>> reversed(links.rbegin(), links.rend());
  islands.group(reversed, 6);
  ASSERT_EQ(islands.islands(), 3u);
  EXPECT_EQ(islands.order(), (std::vector<std::size_t>{3, 0, 2, 5, 1, 4, 6}));
}

// A box of mass m at solver index `self` on `below` (the environment or another box under it), its four
// lower corners touching, everything moving down at one step of gravity's speed.
void boxOn(std::size_t self, std::size_t below, double m, std::vector<SolverBody>& bodies,
           std::vector<SolverContact>& contacts) {
  SolverBody body;
  body.inverse_mass = 1.0 / m;
  const MassProperties mass = MassProperties::box(m, kBox);
  body.inverse_inertia_W = mass.inverseInertia();
  body.v = Eigen::Vector3d(0.01, -0.02, -kG * kH);
  body.w = Eigen::Vector3d(0.001, 0.0, 0.002);
  bodies.push_back(body);
  for (const double x : {-0.15, 0.15}) {
    for (const double y : {-0.15, 0.15}) {
      SolverContact c;
      c.a = self, c.b = below;
      c.r_a = Eigen::Vector3d(x, y, -0.1);
      if (below != kEnvironment) c.r_b = Eigen::Vector3d(x, y, 0.1);
      c.n = Eigen::Vector3d::UnitZ(), c.t1 = Eigen::Vector3d::UnitX(), c.t2 = Eigen::Vector3d::UnitY();
      c.separation = -2e-5;
      c.friction = 0.5;
      c.sustained = true;
      contacts.push_back(c);
    }
  }
}

// A 0.1 m ball at solver index `self` on the ground, sliding and sinking.
void ballOn(std::size_t self, std::vector<SolverBody>& bodies, std::vector<SolverContact>& contacts) {
  SolverBody body;
  body.inverse_mass = 1.0 / 0.5;
  body.inverse_inertia_W = MassProperties::sphere(0.5, 0.1).inverseInertia();
  body.v = Eigen::Vector3d(0.3, -0.1, -kG * kH);
  body.w = Eigen::Vector3d(0.0, 1.0, 0.0);
  bodies.push_back(body);
  SolverContact c;
  c.a = self, c.b = kEnvironment;
  c.r_a = Eigen::Vector3d(0.0, 0.0, -0.1);
  c.n = Eigen::Vector3d::UnitZ(), c.t1 = Eigen::Vector3d::UnitX(), c.t2 = Eigen::Vector3d::UnitY();
  c.separation = -2e-5;
  c.friction = 0.5;
  c.sustained = true;
  contacts.push_back(c);
}

RestingSolveSettings fewSweeps() {
  RestingSolveSettings settings;
  settings.options.iterations = 5;
  settings.options.sweep_budget_contacts = 1;  // 5 sweeps, no more
  settings.options.dt = kH;
  settings.move_weight = 0.5 * kH;
  return settings;
}

bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}

// Pose and momenta to the bit.
bool sameBits(const State& a, const State& b) {
  return sameBits(a.p_WB, b.p_WB) && sameBits(a.P_W, b.P_W) && sameBits(a.L_W, b.L_W) &&
         std::memcmp(a.q_WB.coeffs().data(), b.q_WB.coeffs().data(), 4 * sizeof(double)) == 0;
}

// An island whose solve at once is refused step after step (a box on the ground that sticking would hold
// only with 25 times its friction: a new contact, so not counted as sliding) waits 1, 3, 7, ... 63 of its
// unconverged steps between tries, and gets the same bits whether it waits or tries: a refused solve leaves
// the sweeps' result. Catches a back-off that never lets the island be tried again, one island's refusals
// holding back another, or a refused solve that changes anything.
TEST(ContactIslands, AnIslandRefusedAgainAndAgainIsTriedAfterDoublingWaits) {
  std::vector<SolverBody> start_bodies{environmentBody()};
  std::vector<SolverContact> start_contacts;
  boxOn(1, kEnvironment, 1.0, start_bodies, start_contacts);
  start_bodies[1].v = Eigen::Vector3d(2.5, 0.0, -kG * kH);
  for (SolverContact& c : start_contacts) c.friction = 0.1, c.sustained = false;
  std::vector<std::pair<std::size_t, std::size_t>> links;
  for (const SolverContact& c : start_contacts) links.emplace_back(0, 10);
  SolverIslands islands;
  std::vector<std::size_t> tries;
  std::vector<SolverBody> first;
  for (std::size_t step = 0; step < 64; ++step) {
    std::vector<SolverBody> bodies = start_bodies;
    std::vector<SolverContact> contacts = start_contacts;
    islands.group(links, 2);  // object 1 touches nothing yet
    islands.solve(contacts, bodies, {1, 2}, fewSweeps(), nullptr);
    ASSERT_FALSE(islands.converged(0)) << step;
    if (islands.triedAtOnce() > 0) tries.push_back(step);
    if (step == 0) first = bodies;
    EXPECT_TRUE(sameBits(bodies[1].dP, first[1].dP) && sameBits(bodies[1].dL, first[1].dL)) << step;
  }
  EXPECT_EQ(tries, (std::vector<std::size_t>{0, 2, 6, 14, 30, 62}));
  // A second such box beside it, an island of its own, is tried at once: the first's refusals hold back
  // only the first (waiting its 63).
  std::vector<SolverBody> bodies = start_bodies;
  std::vector<SolverContact> contacts = start_contacts;
  boxOn(2, kEnvironment, 1.0, bodies, contacts);
  bodies[2].v = bodies[1].v;
  for (std::size_t k = 4; k < 8; ++k) contacts[k].friction = 0.1, contacts[k].sustained = false;
  links.clear();
  for (const SolverContact& c : contacts) links.emplace_back(c.a - 1, 10);
  islands.group(links, 2);
  islands.solve(contacts, bodies, {1, 2, 3}, fewSweeps(), nullptr);
  EXPECT_EQ(islands.triedAtOnce(), 1u);
}

TEST(ContactIslands, EachIslandConvergesOnItsOwnAndGetsWhatItWouldAlone) {
  // Island 0: a ball sliding on the ground (object 0, solver body 1; one point, which two sweeps settle);
  // island 1: a 1 000 kg box (object 2, body 3) on a 1 kg one (object 1, body 2) on the ground, which five
  // sweeps cannot settle (the impulse crosses the mass ratio a little at each).
  std::vector<SolverBody> bodies{environmentBody()};
  std::vector<SolverContact> contacts;
  ballOn(1, bodies, contacts);
  boxOn(2, kEnvironment, 1.0, bodies, contacts);
  boxOn(3, 2, 1000.0, bodies, contacts);
  std::vector<std::pair<std::size_t, std::size_t>> links;
  for (const SolverContact& c : contacts) links.emplace_back(c.a - 1, c.b == kEnvironment ? 10 : c.b - 1);
  SolverIslands islands;
  islands.group(links, 3);
  ASSERT_EQ(islands.islands(), 2u);
  ASSERT_EQ(islands.order(), (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  const std::vector<SolverBody> bodies_before = bodies;
  const std::vector<SolverContact> contacts_before = contacts;
  ThreadPool pool(2);
  islands.solve(contacts, bodies, {1, 2, 4}, fewSweeps(), &pool);
  EXPECT_TRUE(islands.converged(0));
  for (std::size_t k = 1; k < 9; ++k) EXPECT_FALSE(islands.converged(k)) << k;

  // The ball solved in lists of its own, with the same sweep budget, gets the same bits.
  std::vector<SolverBody> alone_bodies{bodies_before[0], bodies_before[1]};
  std::vector<SolverContact> alone(contacts_before.begin(), contacts_before.begin() + 1);
  RestingSolveSettings settings = fewSweeps();
  settings.options.budget_contacts = contacts.size();
  std::vector<double> lift(2);
  EXPECT_TRUE(solveRestingContacts(alone, alone_bodies, settings, SolveRange::all(1, 2), lift));
  for (Eigen::Vector3d SolverBody::*field :
       {&SolverBody::dP, &SolverBody::dL, &SolverBody::dx, &SolverBody::dtheta, &SolverBody::v}) {
    EXPECT_TRUE(sameBits(bodies[1].*field, alone_bodies[1].*field));
  }
  EXPECT_EQ(contacts[0].normal_impulse, alone[0].normal_impulse);
  EXPECT_EQ(contacts[0].friction_impulse, alone[0].friction_impulse);
  EXPECT_GT(contacts[0].normal_impulse, 0.0);
  // The environment's entry is left as it was (islands on other threads share it).
  EXPECT_TRUE(sameBits(bodies[0].v, Eigen::Vector3d::Zero()) && sameBits(bodies[0].dx, Eigen::Vector3d::Zero()));
}

// Stacks of 1 to 6 boxes and one of 40 (an island of more contacts than a thread's block), a ball dropped
// onto the gap between two stacks (it joins their islands when it lands), a box thrown along the ground
// into a stack, and a sphere rolling at the friction limit down a tilted block: contact of every kind.
// With `sleep`, islands also fall asleep and are woken (by the landing ball, by the thrown box).
Scene mixedScene(bool sleep = false) {
  ContactSetup setup;
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
  setup.settings.sleep = sleep;
  setup.settings.sleep_time = 0.2;
  std::vector<BodyDefinition> bodies;
  const auto add = [&](const BodyDefinition& body, const CollisionShape& shape) {
    bodies.push_back(body);
    setup.bodies.push_back(shape);
  };
  const CollisionShape box = reference::collisionShape(ShapeType::kBox, kBox, 0.5, 0.0);
  const auto boxAt = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& v) {
    return reference::contactBody(MassProperties::box(1.0, kBox), p, Eigen::Quaterniond::Identity(), v,
                                  Eigen::Vector3d::Zero(), kDown);
  };
  for (int s = 0; s < 6; ++s) {
    for (int i = 0; i <= s; ++i) add(boxAt(Eigen::Vector3d(0.31 * s, 0.0, 0.1 + 0.2 * i), Eigen::Vector3d::Zero()), box);
  }
  for (int i = 0; i < 40; ++i) add(boxAt(Eigen::Vector3d(-2.0, 0.0, 0.1 + 0.2 * i), Eigen::Vector3d::Zero()), box);
  const CollisionShape ball = reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.3, 0.5);
  add(reference::contactBody(MassProperties::sphere(0.5, 0.1), Eigen::Vector3d(0.465, 0.0, 0.8),
                             Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0.2, 0), kDown),
      ball);
  add(boxAt(Eigen::Vector3d(0.8, -1.5, 0.1), Eigen::Vector3d(0.3, 4.0, 0.0)), box);
  return Scene(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

// The same bits on 1 to 4 threads (blocks of three bodies, so the colliders' free steps are split too), awake
// throughout and with islands falling asleep and being woken.
void expectSameBitsOnAnyNumberOfThreads(bool sleep) {
  std::int64_t most_asleep = 0;
  const auto run = [&](std::size_t threads) {
    Scene scene = mixedScene(sleep);
    scene.setThreads(threads, 3);
    scene.setRecordContacts(true);
    for (int i = 0; i < 70; ++i) {
      scene.step(10);
      most_asleep = std::max(most_asleep, scene.contactStatistics().sleeping_bodies);
    }
    return scene;
  };
  const Scene reference = run(1);
  const std::size_t ball = reference.bodyCount() - 2;
  // The ball landed on the stacks beside it and the thrown box reached the stacks' row (not a scene at rest).
  ASSERT_LT(reference.state(ball).p_WB.z(), 0.7);
  ASSERT_GT(reference.state(ball + 1).p_WB.y(), -1.0);
  if (sleep) {  // islands slept, and some were woken
    ASSERT_GT(most_asleep, 0);
    ASSERT_GT(reference.contactStatistics().wakes, 0);
  }
  // More threads than cores, several times: a step whose result depends on how the blocks interleave (as
  // when sleeping bodies' bounding boxes went into Bullet's broad phase from the pool, in the order the
  // blocks ran, and the pairs' order with it) differs in some of the runs.
  for (const std::size_t threads : {2, 3, 4, 4, 4, 4, 4, 4}) {
    const Scene other = run(threads);
    for (std::size_t b = 0; b < reference.bodyCount(); ++b) {
      EXPECT_TRUE(sameBits(reference.state(b), other.state(b))) << threads << " threads, body " << b;
      ASSERT_EQ(reference.contacts(b).size(), other.contacts(b).size()) << threads << " threads, body " << b;
      for (std::size_t c = 0; c < reference.contacts(b).size(); ++c) {
        EXPECT_EQ(reference.contacts(b)[c].normal_impulse, other.contacts(b)[c].normal_impulse);
        EXPECT_TRUE(sameBits(reference.contacts(b)[c].friction_impulse_W, other.contacts(b)[c].friction_impulse_W));
      }
    }
  }
}

TEST(ContactIslands, AContactSceneStepsToTheSameBitsOnAnyNumberOfThreads) { expectSameBitsOnAnyNumberOfThreads(false); }

// Blocks of one body, of sizes whose multiple for the free steps would wrap around, and of the largest size:
// the same bits as one thread, and no division by a wrapped block size.
TEST(ContactIslands, AContactSceneStepsToTheSameBitsWithAnyBlockSize) {
  const auto run = [](std::size_t threads, std::size_t per_block) {
    Scene scene = mixedScene();
    scene.setThreads(threads, per_block);
    scene.step(200);
    return scene;
  };
  const Scene reference = run(1, Scene::kBodiesPerBlock);
  const std::size_t most = std::numeric_limits<std::size_t>::max();
  for (const std::size_t per_block : {std::size_t{1}, most / 8 + 1, most / 4, most}) {
    const Scene other = run(2, per_block);
    for (std::size_t b = 0; b < reference.bodyCount(); ++b) {
      EXPECT_TRUE(sameBits(reference.state(b).p_WB, other.state(b).p_WB) &&
                  sameBits(reference.state(b).L_W, other.state(b).L_W))
          << "blocks of " << per_block << ", body " << b;
    }
  }
}

TEST(ContactIslands, AContactSceneWithSleepingIslandsStepsToTheSameBitsOnAnyNumberOfThreads) {
  expectSameBitsOnAnyNumberOfThreads(true);
}

// A mixed pile dropped onto a ring of triangles on the ground: boxes, balls, cylinders, capsules and hulls
// (icospheres), so that every kind of narrow phase the detection runs is in it: Bullet's box–box and
// sphere algorithms and the one GJK/EPA query with face clipping on the pool, a body on an environment mesh
// (whose algorithm allocates per triangle) on the caller, the half-space's features in blocks. Blocks of
// three bodies: pairs in blocks of 3, manifolds of 6, bodies on the half-space of 48.
Scene mixedPile() {
  ContactSetup setup;
  CollisionShape ring;
  ring.type = ShapeType::kMesh;
  ring.mesh = primitives::ring(0.6, 1.0, 0.3, 24);
  ring.pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.15);
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5), ring};
  setup.settings.sleep = false;
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < 48; ++i) {
    const Eigen::Vector3d p(-0.525 + 0.35 * (i % 4), -0.525 + 0.35 * ((i / 4) % 4), 0.5 + 0.35 * (i / 16));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.05 * (i % 7), Eigen::Vector3d(1, 2, 3).normalized()));
    CollisionShape shape;
    MassProperties mass = MassProperties::sphere(0.5, 0.1);  // the balls', and the hulls' (icospheres of it)
    switch (i % 5) {
      case 0: shape = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d::Constant(0.2), 0.5, 0.0);
              mass = MassProperties::box(0.5, Eigen::Vector3d::Constant(0.2)); break;
      case 1: shape = reference::collisionShape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.5, 0.2); break;
      case 2: shape = reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.08, 0.2, 0), 0.5, 0.0);
              mass = MassProperties::cylinder(0.5, 0.08, 0.2); break;
      case 3: shape = reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(0.07, 0.12, 0), 0.5, 0.0);
              mass = MassProperties::cylinder(0.5, 0.07, 0.26); break;  // near enough for a test of bits
      default: shape = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0.0);
               shape.mesh = primitives::icosphere(0.1, 1); break;
    }
    bodies.push_back(reference::contactBody(mass, p, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
    setup.bodies.push_back(shape);
  }
  return Scene(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

TEST(ContactIslands, AMixedPileOnAMeshStepsToTheSameBitsOnAnyNumberOfThreads) {
  bool on_ring = false, faced_pair = false;  // the reference met the mesh, and pairs of faced shapes
  const auto run = [&](std::size_t threads) {
    Scene scene = mixedPile();
    scene.setThreads(threads, 3);
    scene.setRecordContacts(true);
    for (int i = 0; i < 80; ++i) {
      scene.step(10);
      for (std::size_t b = 0; b < scene.bodyCount(); ++b) {
        for (const Contact& c : scene.contacts(b)) {
          on_ring = on_ring || (!c.other.is_body && c.other.index == 1);
          faced_pair = faced_pair || (c.other.is_body && b % 5 >= 2 && c.other.index % 5 >= 2);
        }
      }
    }
    return scene;
  };
  const Scene reference = run(1);
  ASSERT_TRUE(on_ring);
  ASSERT_TRUE(faced_pair);
  for (const std::size_t threads : {2, 3}) {
    const Scene other = run(threads);
    for (std::size_t b = 0; b < reference.bodyCount(); ++b) {
      EXPECT_TRUE(sameBits(reference.state(b), other.state(b))) << threads << " threads, body " << b;
    }
  }
}

TEST(ContactIslands, AContactSceneStepsToTheSameBitsWithAndWithoutWideInstructions) {
  // The resting solve's four lanes as AVX operations or as the build's baseline ones (where the CPU has AVX;
  // elsewhere both runs take the baseline and the test holds trivially).
  const auto run = [](bool wide) {
    Scene scene = mixedScene();
    scene.setWideLanes(wide);
    scene.setThreads(2, 3);
    scene.step(700);
    return scene;
  };
  const Scene wide = run(true), narrow = run(false);
  for (std::size_t b = 0; b < wide.bodyCount(); ++b) EXPECT_TRUE(sameBits(wide.state(b), narrow.state(b))) << "body " << b;
}

}  // namespace
