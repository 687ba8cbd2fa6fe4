// The package's contact step and Bullet's own rigid-body world on the same scenes, back to back on one
// thread (not a test; numbers in docs/performance.md): stacks of ten 0.2 m cubes on a plane, a 20-row
// pyramid of such cubes, and a pile of mixed shapes dropped into a bin; at h = 1 ms, with the same solver
// sweeps, friction (μ = 0.5 between any two surfaces), no restitution and sleeping off in both. Prints the
// wall time per body-step; the sag (the largest distance of a body from where it started, after settling)
// and the creep (the largest distance a body moved over the timed run: the drift of a resting stack); the
// deepest penetration in a state either engine handed out after a step (the pile's, during its drop), both
// found by Bullet's collision detection (the package's bodies in a collision world of their own, outside the
// timing), and the package's own deepest contact at the end of a free step, before its solve moves it out.
//
// Bullet: btDiscreteDynamicsWorld with btSequentialImpulseConstraintSolver (Debian's libbullet, double
// precision), one stepSimulation(h, 0) per step (no interpolation substeps), deactivation disabled, the same
// masses and principal moments as the package's solids. It combines friction by product, so each surface
// gets √0.5; the package takes the geometric mean of 0.5 and 0.5. Its penetration is read from its contact
// manifolds after each step, outside the timing: detected at the start of a step, they are those of the state
// its last step handed out.
//
// Usage: bullet_side_by_side [STACK_BODIES...=100 1000]; env SETTLE_SECONDS (0.5) and SIM_SECONDS (3) for the
// stacks and the pyramid: untimed settling, then the timed run over which creep is measured; PILE_BODIES
// (1000) and PILE_SECONDS (2) for the pile, timed from the drop.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "rigid_body_sim/scene.hpp"

namespace {

using namespace rigid_body;

constexpr double kH = 0.001;
constexpr double kSide = 0.2;      // the cubes' edge [m]
constexpr double kFriction = 0.5;  // between any two surfaces
const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

// A body of a scene: its shape (a cube unless said) and where it starts.
struct Piece {
  Eigen::Vector3d p;
  ShapeType shape = ShapeType::kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Constant(kSide);  // as CollisionShape::size has it
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};
using Placement = std::vector<Piece>;
// The static shapes around them: a plane through the origin and, for the pile, a bin's walls.
struct Walls {
  std::vector<Eigen::Vector3d> centres, sizes;
};

// Each solid's mass properties, the same in both engines (Bullet gets the principal moments).
MassProperties massOf(const Piece& piece) {
  switch (piece.shape) {
    case ShapeType::kSphere:
      return MassProperties::sphere(0.5, piece.size.x());
    case ShapeType::kCylinder:
      return MassProperties::cylinder(0.5, piece.size.x(), piece.size.y());
    case ShapeType::kCapsule:  // as the cylinder that holds it
      return MassProperties::cylinder(0.5, piece.size.x(), piece.size.y() + 2.0 * piece.size.x());
    default:
      return MassProperties::box(piece.shape == ShapeType::kBox && piece.size == Eigen::Vector3d::Constant(kSide) ? 1.0 : 0.5,
                                 piece.size);
  }
}

// `count` boxes in stacks of ten, the stacks 0.5 m apart on a square grid, each box touching the one below.
Placement stacks(std::size_t count) {
  Placement boxes;
  const std::size_t columns = count / 10;
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(columns))));
  for (std::size_t c = 0; c < columns; ++c) {
    for (int level = 0; level < 10; ++level) {
      boxes.push_back({Eigen::Vector3d(0.5 * static_cast<double>(c % side), 0.5 * static_cast<double>(c / side),
                                       0.5 * kSide + kSide * level)});
    }
  }
  return boxes;
}

// A pyramid of `rows` rows in the x-z plane: row r has rows − r boxes, 1 mm apart, each resting on the two
// below it (offset by half a box and its gap).
Placement pyramid(int rows) {
  Placement boxes;
  const double pitch = kSide + 0.001;
  for (int r = 0; r < rows; ++r) {
    for (int i = 0; i < rows - r; ++i) boxes.push_back({Eigen::Vector3d(pitch * (i + 0.5 * r), 0.0, 0.5 * kSide + kSide * r)});
  }
  return boxes;
}

// `count` mixed bodies (boxes, spheres, cylinders, capsules in turn, 0.5 kg, a small tilt each) on a grid
// 0.3 m apart above a 3 m square bin of 0.5 m walls, dropped together.
Placement pile(std::size_t count, Walls& walls) {
  Placement bodies;
  const std::size_t per_layer = 100;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t layer = i / per_layer, cell = i % per_layer;
    Piece piece;
    piece.p = Eigen::Vector3d(-1.35 + 0.3 * static_cast<double>(cell % 10), -1.35 + 0.3 * static_cast<double>(cell / 10),
                              0.6 + 0.3 * static_cast<double>(layer));
    piece.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * static_cast<double>(i % 7), Eigen::Vector3d(1, 2, 3).normalized()));
    switch (i % 4) {
      case 0: piece.shape = ShapeType::kBox, piece.size = Eigen::Vector3d(0.2, 0.15, 0.1); break;
      case 1: piece.shape = ShapeType::kSphere, piece.size = Eigen::Vector3d(0.08, 0, 0); break;
      case 2: piece.shape = ShapeType::kCylinder, piece.size = Eigen::Vector3d(0.06, 0.16, 0); break;
      default: piece.shape = ShapeType::kCapsule, piece.size = Eigen::Vector3d(0.05, 0.1, 0); break;
    }
    bodies.push_back(piece);
  }
  for (int side = 0; side < 4; ++side) {
    const double sign = side % 2 ? -1.0 : 1.0;
    const bool along_x = side < 2;
    walls.centres.emplace_back(along_x ? sign * 1.55 : 0.0, along_x ? 0.0 : sign * 1.55, 0.25);
    walls.sizes.emplace_back(along_x ? 0.1 : 3.2, along_x ? 3.2 : 0.1, 0.5);
  }
  return bodies;
}

// A run: `settle` steps untimed, then `steps` timed ones.
struct Run {
  std::int64_t settle = 0;
  std::int64_t steps = 0;
};

struct Outcome {
  double microseconds_per_body_step = 0.0;  // over the timed steps
  double sag = 0.0;          // [m] the largest distance of a body from its start when the timed steps begin
  double creep = 0.0;        // [m] the largest distance a body moved over the timed steps
  double penetration = 0.0;  // [m] the deepest contact in a state handed out after a step
  // [m] as each engine detects it: the package at the end of a free step, before its solve moves the bodies
  // out; Bullet at the start of a step (its manifolds), on the state its last step handed out
  double detected = 0.0;
};

double largestDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double distance = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) distance = std::max(distance, (a[i] - b[i]).norm());
  return distance;
}

std::vector<Eigen::Vector3d> starts(const Placement& pieces) {
  std::vector<Eigen::Vector3d> p;
  for (const Piece& piece : pieces) p.push_back(piece.p);
  return p;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::unique_ptr<btCollisionShape> bulletShape(const Piece& piece) {
  switch (piece.shape) {
    case ShapeType::kSphere:
      return std::make_unique<btSphereShape>(piece.size.x());
    case ShapeType::kCylinder:
      return std::make_unique<btCylinderShapeZ>(btVector3(piece.size.x(), piece.size.x(), 0.5 * piece.size.y()));
    case ShapeType::kCapsule:
      return std::make_unique<btCapsuleShapeZ>(piece.size.x(), piece.size.y());
    default:
      return std::make_unique<btBoxShape>(btVector3(0.5 * piece.size.x(), 0.5 * piece.size.y(), 0.5 * piece.size.z()));
  }
}

// The deepest penetration among the world's contact manifolds (as detected in the last step) [m].
double deepestContact(btCollisionWorld& world) {
  double deepest = 0.0;
  btDispatcher& dispatcher = *world.getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    for (int c = 0; c < manifold.getNumContacts(); ++c) {
      deepest = std::max(deepest, -static_cast<double>(manifold.getContactPoint(c).getDistance()));
    }
  }
  return deepest;
}


// The static shapes in Bullet's terms, each handed to add(shape, pose): the plane through the origin, then
// the walls.
template <class Add>
void addEnvironment(const Walls& walls, Add add) {
  add(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0), btTransform::getIdentity());
  for (std::size_t i = 0; i < walls.centres.size(); ++i) {
    const Eigen::Vector3d& c = walls.centres[i];
    const Eigen::Vector3d half = 0.5 * walls.sizes[i];
    add(std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), half.z())),
        btTransform(btQuaternion::getIdentity(), btVector3(c.x(), c.y(), c.z())));
  }
}

// Bullet's collision detection alone over the package's bodies: the penetration in the states the package
// hands out after a step, found as Bullet's world finds its own (which detects at the start of a step, on
// the state its last step handed out), so that both engines' deepest contacts are the same quantity.
class PublishedDepth {
 public:
  PublishedDepth(const Placement& pieces, const Walls& walls)
      : dispatcher_(&configuration_), world_(&dispatcher_, &broadphase_, &configuration_) {
    addEnvironment(walls, [&](std::unique_ptr<btCollisionShape> shape, const btTransform& pose) {
      add(std::move(shape), pose, true);
    });
    first_ = objects_.size();
    for (const Piece& piece : pieces) add(bulletShape(piece), btTransform::getIdentity(), false);
  }
  ~PublishedDepth() {
    for (const auto& object : objects_) world_.removeCollisionObject(object.get());
  }

  // The deepest penetration among the bodies and the environment, body i at pose(i) [m].
  template <class Pose>
  double deepest(Pose pose) {
    for (std::size_t i = first_; i < objects_.size(); ++i) objects_[i]->setWorldTransform(pose(i - first_));
    world_.performDiscreteCollisionDetection();
    return deepestContact(world_);
  }
  double deepest(const Scene& scene) {
    return deepest([&](std::size_t i) {
      const State& s = scene.state(i);
      return btTransform(btQuaternion(s.q_WB.x(), s.q_WB.y(), s.q_WB.z(), s.q_WB.w()),
                         btVector3(s.p_WB.x(), s.p_WB.y(), s.p_WB.z()));
    });
  }

 private:
  // The environment's shapes are static, as in Bullet's own world: not tested against each other.
  void add(std::unique_ptr<btCollisionShape> shape, const btTransform& pose, bool environment) {
    objects_.push_back(std::make_unique<btCollisionObject>());
    objects_.back()->setCollisionShape(shape.get());
    objects_.back()->setWorldTransform(pose);
    shapes_.push_back(std::move(shape));
    if (environment) {
      objects_.back()->setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT);
      world_.addCollisionObject(objects_.back().get(), btBroadphaseProxy::StaticFilter,
                                btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
    } else {
      world_.addCollisionObject(objects_.back().get());
    }
  }

  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btCollisionWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> objects_;
  std::size_t first_ = 0;
};

// The package's run; with `depth`, the penetration of every step's outcome is measured (outside the timing).
Outcome runPackage(const Placement& pieces, const Walls& walls, const Run& run, int iterations, std::size_t threads,
                   PublishedDepth* depth) {
  ContactSetup setup;
  setup.settings.sleep = false;
  setup.settings.iterations = iterations;
  CollisionShape ground;
  ground.type = ShapeType::kPlane;
  ground.name = "ground";
  ground.material.friction = kFriction;
  setup.environment = {ground};
  for (std::size_t i = 0; i < walls.centres.size(); ++i) {
    CollisionShape wall;
    wall.type = ShapeType::kBox;
    wall.name = "wall " + std::to_string(i);
    wall.size = walls.sizes[i];
    wall.pose.translation() = walls.centres[i];
    wall.material.friction = kFriction;
    setup.environment.push_back(wall);
  }
  std::vector<BodyDefinition> bodies;
  for (const Piece& piece : pieces) {
    BodyDefinition body;
    body.model.mass = massOf(piece);
    body.model.forces.gravity_W = kGravity;
    body.initial.p_WB = piece.p;
    body.initial.q_WB = piece.q;
    body.takes_input = false;
    bodies.push_back(body);
    CollisionShape shape;
    shape.type = piece.shape;
    shape.size = piece.size;
    shape.material.friction = kFriction;
    setup.bodies.push_back(shape);
  }
  Scene scene(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setThreads(threads);
  const auto positions = [&] {
    std::vector<Eigen::Vector3d> p;
    for (std::size_t i = 0; i < pieces.size(); ++i) p.push_back(scene.state(i).p_WB);
    return p;
  };
  double penetration = 0.0, seconds_stepping = 0.0;
  const auto stepAndMeasure = [&](std::int64_t steps) {
    if (depth == nullptr) {
      scene.step(steps);
      return;
    }
    for (std::int64_t k = 0; k < steps; ++k) {
      const auto start = std::chrono::steady_clock::now();
      scene.step(1);
      seconds_stepping += secondsSince(start);
      penetration = std::max(penetration, depth->deepest(scene));
    }
  };
  stepAndMeasure(run.settle);
  const std::vector<Eigen::Vector3d> settled = positions();
  seconds_stepping = 0.0;
  const auto start = std::chrono::steady_clock::now();
  stepAndMeasure(run.steps);
  const double seconds = depth == nullptr ? secondsSince(start) : seconds_stepping;
  return {seconds * 1e6 / (static_cast<double>(run.steps) * static_cast<double>(pieces.size())),
          largestDistance(starts(pieces), settled), largestDistance(settled, positions()), penetration,
          scene.contactStatistics().max_penetration};
}

// Bullet's run; with `depth`, the penetration of every step's outcome is measured (outside the timing, which
// such a run does not report: the probe's detection between steps would leave the caches cold).
Outcome runBullet(const Placement& pieces, const Walls& walls, const Run& run, int iterations, PublishedDepth* depth) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(kGravity.x(), kGravity.y(), kGravity.z()));
  world.getSolverInfo().m_numIterations = iterations;
  const double surface_friction = std::sqrt(kFriction);  // Bullet multiplies the two surfaces' values
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  const auto add = [&](std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& inertia,
                       const btTransform& pose) {
    motions.push_back(std::make_unique<btDefaultMotionState>(pose));
    bodies.push_back(std::make_unique<btRigidBody>(
        btRigidBody::btRigidBodyConstructionInfo(mass, motions.back().get(), shape.get(), inertia)));
    shapes.push_back(std::move(shape));
    bodies.back()->setFriction(surface_friction);
    bodies.back()->setRestitution(0.0);
    if (mass > 0.0) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
  };
  addEnvironment(walls, [&](std::unique_ptr<btCollisionShape> shape, const btTransform& pose) {
    add(std::move(shape), 0.0, btVector3(0, 0, 0), pose);
  });
  const std::size_t first = bodies.size();
  for (const Piece& piece : pieces) {
    const MassProperties mass = massOf(piece);
    const Eigen::Vector3d I = mass.inertia().diagonal();  // axis-aligned solids: principal in the body frame
    add(bulletShape(piece), mass.mass(), btVector3(I.x(), I.y(), I.z()),
        btTransform(btQuaternion(piece.q.x(), piece.q.y(), piece.q.z(), piece.q.w()),
                    btVector3(piece.p.x(), piece.p.y(), piece.p.z())));
  }
  const auto positions = [&] {
    std::vector<Eigen::Vector3d> p;
    for (std::size_t i = first; i < bodies.size(); ++i) {
      const btVector3& o = bodies[i]->getWorldTransform().getOrigin();
      p.emplace_back(o.x(), o.y(), o.z());
    }
    return p;
  };
  double seconds = 0.0, penetration = 0.0, manifold_penetration = 0.0;
  std::vector<Eigen::Vector3d> settled;
  for (std::int64_t k = 0; k < run.settle + run.steps; ++k) {
    if (k == run.settle) settled = positions();
    const auto start = std::chrono::steady_clock::now();
    world.stepSimulation(kH, 0);
    if (k >= run.settle) seconds += secondsSince(start);
    // Outside the timing: its state as handed out, measured as the package's is.
    if (depth == nullptr) continue;
    penetration = std::max(penetration, depth->deepest([&](std::size_t i) { return bodies[first + i]->getWorldTransform(); }));
    manifold_penetration = std::max(manifold_penetration, deepestContact(world));
  }
  const Outcome outcome{seconds * 1e6 / (static_cast<double>(run.steps) * static_cast<double>(pieces.size())),
                        largestDistance(starts(pieces), settled), largestDistance(settled, positions()), penetration,
                        manifold_penetration};
  for (const auto& body : bodies) world.removeRigidBody(body.get());
  return outcome;
}

void compare(const std::string& name, const Placement& pieces, const Walls& walls, const Run& run, int iterations) {
  // One thread, timed in one call; then again step by step, with the penetration of every step's outcome
  // (likewise for Bullet).
  Outcome ours = runPackage(pieces, walls, run, iterations, 1, nullptr);
  PublishedDepth depth(pieces, walls);
  const Outcome measured = runPackage(pieces, walls, run, iterations, 1, &depth);
  ours.penetration = measured.penetration;
  // Two threads: the same trajectory to the bit (the islands' solves spread over the pool), so only its time.
  const Outcome ours_two = runPackage(pieces, walls, run, iterations, 2, nullptr);
  Outcome bullet = runBullet(pieces, walls, run, iterations, nullptr);
  const Outcome bullet_measured = runBullet(pieces, walls, run, iterations, &depth);
  bullet.penetration = bullet_measured.penetration;
  bullet.detected = bullet_measured.detected;
  char motion[96] = "- | -";  // a drop has no resting pose to sag from or creep away from
  if (run.settle > 0) {
    std::snprintf(motion, sizeof motion, "%.3f / %.3f | %.4f / %.4f", ours.sag * 1e3, bullet.sag * 1e3,
                  ours.creep * 1e3, bullet.creep * 1e3);
  }
  std::printf("| %s | %zu | %.3f | %.3f | %.3f | %.2f | %.2f | %s | %.2f / %.2f | %.2f / %.2f |\n", name.c_str(), pieces.size(),
              ours.microseconds_per_body_step, ours_two.microseconds_per_body_step, bullet.microseconds_per_body_step,
              ours.microseconds_per_body_step / bullet.microseconds_per_body_step,
              ours_two.microseconds_per_body_step / bullet.microseconds_per_body_step, motion,
              ours.penetration * 1e3, bullet.penetration * 1e3, ours.detected * 1e3, bullet.detected * 1e3);
  if (ours_two.creep != ours.creep || ours_two.detected != ours.detected || measured.creep != ours.creep) {
    std::printf("(the two-thread run moved otherwise: creep %.17g against %.17g m)\n", ours_two.creep, ours.creep);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const auto steps = [](const char* name, double fallback) {
    const char* value = std::getenv(name);
    return static_cast<std::int64_t>(std::llround((value ? std::atof(value) : fallback) / kH));
  };
  const Run resting{steps("SETTLE_SECONDS", 0.5), steps("SIM_SECONDS", 3.0)};
  const Run drop{0, steps("PILE_SECONDS", 2.0)};
  const char* pile_env = std::getenv("PILE_BODIES");
  const std::size_t pile_bodies = pile_env ? static_cast<std::size_t>(std::atol(pile_env)) : 1000;
  const int iterations = ContactSettings().iterations;  // the package's default sweeps, in both
  std::printf("h = 1 ms, %d solver sweeps in both, mu = 0.5, e = 0, sleeping off, Bullet on one thread; stacks and pyramid: "
              "%.1f s to settle, then %.1f s timed; pile: %.1f s from the drop, timed\n\n",
              iterations, resting.settle * kH, resting.steps * kH, drop.steps * kH);
  std::printf("| scene | bodies | package µs/body-step, 1 thread | 2 threads | Bullet µs/body-step | package/Bullet, "
              "1 thread | 2 threads | sag mm (package / Bullet) | creep mm (package / Bullet) | deepest mm (package / "
              "Bullet) | deepest as detected, mm (package before its solve / Bullet's manifolds) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<std::size_t> counts;
  for (int i = 1; i < argc; ++i) counts.push_back(static_cast<std::size_t>(std::atol(argv[i])));
  if (counts.empty()) counts = {100, 1000};
  const Walls none;
  for (std::size_t count : counts) compare("stacks of 10", stacks(count), none, resting, iterations);
  compare("pyramid of 20 rows", pyramid(20), none, resting, iterations);
  Walls bin;
  const Placement mixed = pile(pile_bodies, bin);
  compare("mixed pile dropped into a bin", mixed, bin, drop, iterations);
  return 0;
}
