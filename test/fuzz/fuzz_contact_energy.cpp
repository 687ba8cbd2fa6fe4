// Seeded random heaps for the contact step (not a test of the suite; docs/reliability.md, "Contact"): each
// iteration drops 1 to 12 bodies (boxes, spheres, cylinders, capsules 0.02 to 1 m across, aspect ratios to
// 30, 0.001 to 100 kg: mass ratios to 10⁵), turned at random, stacked one above the other with random
// velocities (up to 100 m/s for a third of them) and spins (up to 30 rad/s), random friction and restitution,
// onto the ground at a random step (1 to 20 ms, rk4), and follows them for 2 s. A contact never creates
// energy, so the heap's mechanical energy (kinetic, rotational, potential) must never exceed what it started
// with by more than what the position projection may lift the bodies by (the slop and one step's fall, g h²,
// at each body's weight). Must not happen (exit 1): that gain, or a non-finite state. Printed for each
// iteration: the largest gain over the start, in millimetres of the heap's weight, and the deepest any body's
// lowest point went below the ground.
//
// The integrator is rk4 (the node's default) unless named: a rise that is the free flight's own error (rk4
// turning a thin body that an impact spun to tens of radians a step) shows as no finding with
// implicit_midpoint, which keeps a free body's energy to rounding.
//
// Usage: fuzz_contact_energy ITERATIONS SEED [INTEGRATOR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <random>
#include <vector>

#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

namespace {

using namespace rigid_body;
using reference::mechanicalEnergy;

constexpr double kG = 9.81;

struct Heap {
  std::vector<BodyDefinition> bodies;
  ContactSetup setup;
  double h = 1e-3;
};

Heap randomHeap(std::mt19937& random) {
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(random); };
  const auto logUniform = [&](double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); };
  const auto direction = [&](double z_low, double z_high) {
    return Eigen::Vector3d(uniform(-1, 1), uniform(-1, 1), uniform(z_low, z_high)).normalized();
  };
  Heap heap;
  const double steps[] = {0.001, 0.002, 0.005, 0.01, 0.02};
  heap.h = steps[random() % 5];
  heap.setup.settings.sleep = false;
  CollisionShape ground;
  ground.type = ShapeType::kPlane;
  ground.name = "ground";
  ground.material.friction = uniform(0, 1.2);
  ground.material.restitution = uniform(0, 1) < 0.5 ? 0.0 : uniform(0, 1);
  heap.setup.environment = {ground};
  const int count = 1 + static_cast<int>(random() % 12);
  double top = 0.0;
  for (int i = 0; i < count; ++i) {
    BodyDefinition body;
    CollisionShape shape;
    const double scale = logUniform(0.02, 1.0), mass = logUniform(0.001, 100.0);
    double reach = 0.0;  // the farthest point from the centre
    switch (random() % 4) {
      case 0:
        shape.type = ShapeType::kBox;
        shape.size = scale * Eigen::Vector3d(uniform(0.03, 1), uniform(0.03, 1), uniform(0.03, 1));
        body.model.mass = MassProperties::box(mass, shape.size);
        reach = 0.5 * shape.size.norm();
        break;
      case 1:
        shape.type = ShapeType::kSphere;
        shape.size = Eigen::Vector3d(0.5 * scale, 0, 0);
        body.model.mass = MassProperties::sphere(mass, shape.size.x());
        reach = shape.size.x();
        break;
      case 2:
        shape.type = ShapeType::kCylinder;
        shape.size = scale * Eigen::Vector3d(uniform(0.1, 0.5), uniform(0.03, 1), 0);
        body.model.mass = MassProperties::cylinder(mass, shape.size.x(), shape.size.y());
        reach = std::hypot(shape.size.x(), 0.5 * shape.size.y());
        break;
      default:
        shape.type = ShapeType::kCapsule;
        shape.size = scale * Eigen::Vector3d(uniform(0.1, 0.5), uniform(0.03, 1), 0);
        body.model.mass = MassProperties::cylinder(mass, shape.size.x(), shape.size.y() + 2 * shape.size.x());
        reach = shape.size.x() + 0.5 * shape.size.y();
        break;
    }
    shape.material.friction = uniform(0, 1.2);
    shape.material.restitution = uniform(0, 1) < 0.5 ? 0.0 : uniform(0, 1);
    body.model.forces.gravity_W = Eigen::Vector3d(0, 0, -kG);
    body.initial.p_WB = Eigen::Vector3d(uniform(-0.3, 0.3), uniform(-0.3, 0.3), top + reach + 0.01);
    top += 2.0 * reach + 0.01;
    const Eigen::Vector4d turn(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    body.initial.q_WB = Eigen::Quaterniond(turn.normalized());
    const double speed = uniform(0, 1) < 0.3 ? uniform(0, 100) : uniform(0, 3);
    body.initial.P_W = mass * speed * direction(-1, 0.3);
    const Eigen::Matrix3d R = body.initial.q_WB.toRotationMatrix();
    body.initial.L_W = R * body.model.mass.inertia() * R.transpose() * (uniform(0, 30) * direction(-1, 1));
    body.takes_input = false;
    heap.bodies.push_back(body);
    heap.setup.bodies.push_back(shape);
  }
  return heap;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: fuzz_contact_energy ITERATIONS SEED [INTEGRATOR]\n");
    return 2;
  }
  const int iterations = std::atoi(argv[1]);
  const unsigned seed = static_cast<unsigned>(std::atoi(argv[2]));
  IntegratorType integrator = IntegratorType::kRk4;
  try {
    if (argc == 4) integrator = integratorFromName(argv[3]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "fuzz_contact_energy: %s\n", error.what());
    return 2;
  }
  const double slop = ContactSettings().penetration_slop;
  int findings = 0;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    std::mt19937 random(seed * 1000003u + static_cast<unsigned>(iteration));
    Heap heap = randomHeap(random);
    Scene scene(heap.bodies, integrator, heap.h, IntegratorSettings(), StepAssembly::kLeaveOut, heap.setup);
    double weight = 0.0;
    for (const BodyDefinition& body : heap.bodies) weight += body.model.mass.mass() * kG;
    const double start = mechanicalEnergy(scene), allowance = weight * (slop + kG * heap.h * heap.h);
    double most = start, deepest = 0.0;
    bool finite = true;
    for (int step = 0; step < static_cast<int>(2.0 / heap.h) && finite; ++step) {
      scene.step(1);
      const double energy = mechanicalEnergy(scene);
      finite = std::isfinite(energy);
      most = std::max(most, energy);
      for (std::size_t b = 0; b < heap.bodies.size(); ++b) {
        deepest = std::max(deepest, reference::depthBelowGround(scene.state(b), *heap.setup.bodies[b]));
      }
    }
    const bool found = !finite || most - start > allowance;
    findings += found ? 1 : 0;
    std::printf("%s seed %u iteration %d: %zu bodies, h %.3f s, gained %.3g mm of its weight (allowed %.3g), "
                "deepest below the ground %.3g mm\n",
                found ? "FINDING" : "ok", seed, iteration, heap.bodies.size(), heap.h,
                finite ? 1e3 * (most - start) / weight : INFINITY, 1e3 * allowance / weight, 1e3 * deepest);
  }
  std::printf("%d iterations, %d findings\n", iterations, findings);
  return findings == 0 ? 0 : 1;
}
