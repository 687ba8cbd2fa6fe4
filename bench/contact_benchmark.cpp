// Cost of contact per body and step (Google Benchmark): N boxes resting on the ground apart from each other,
// N boxes in stacks of 10 (every box touches two others or the ground), and N spheres in the air far apart
// (the broad phase alone: no pair overlaps), all awake (sleeping off); the stacks on two threads; a
// pyramid of 20 rows (one island) on one and on two threads; the stacks once asleep; and one box among
// 2 000 half-spaces. Not a
// test: run by scripts/benchmark.sh; numbers in docs/performance.md. One iteration is 10 steps of 1 ms (the
// node's default tick). Scenes without colliders are scene_benchmark's: their cost with contact compiled in is
// measured there.
#include <benchmark/benchmark.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/scene.hpp"

namespace {

using namespace rigid_body;

constexpr std::int64_t kStepsPerTick = 10;
const Eigen::Vector3d kBox(0.3, 0.3, 0.2);

CollisionShape ground() {
  CollisionShape shape;
  shape.type = ShapeType::kPlane;
  shape.name = "ground";
  return shape;
}

CollisionShape boxShape() {
  CollisionShape shape;
  shape.type = ShapeType::kBox;
  shape.size = kBox;
  return shape;
}

BodyDefinition bodyAt(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Vector3d& gravity) {
  BodyDefinition body;
  body.model.mass = mass;
  body.model.forces.gravity_W = gravity;
  body.initial.p_WB = p;
  body.takes_input = false;
  return body;
}

// columns × height boxes: height 1 is boxes resting on the ground apart; height 10 is stacks of 10.
// Awake unless `asleep`: then stepped until every island sleeps (what a settled scene costs then).
Scene boxes(std::size_t count, std::size_t height, IntegratorType type, bool asleep = false) {
  ContactSetup setup;
  setup.settings.sleep = asleep;
  setup.environment = {ground()};
  std::vector<BodyDefinition> bodies;
  const std::size_t columns = count / height;
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(columns))));
  for (std::size_t c = 0; c < columns; ++c) {
    for (std::size_t level = 0; level < height; ++level) {
      const Eigen::Vector3d p(0.5 * static_cast<double>(c % side), 0.5 * static_cast<double>(c / side),
                              0.1 + 0.2 * static_cast<double>(level));
      bodies.push_back(bodyAt(MassProperties::box(1.0, kBox), p, Eigen::Vector3d(0.0, 0.0, -9.81)));
      setup.bodies.push_back(boxShape());
    }
  }
  Scene scene(bodies, type, 0.001, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(100);  // warm: the contacts settled, the warm-start memory filled
  while (asleep && scene.contactStatistics().sleeping_bodies < static_cast<std::int64_t>(bodies.size())) {
    if (scene.integratedSteps(0) > 20000) throw std::runtime_error("the stacks did not fall asleep in 20 s");
    scene.step(100);
  }
  return scene;
}

// A pyramid of `rows` rows of the boxes in the x-z plane (row r has rows − r boxes, 1 mm apart, each on the
// two below it): one island, settled for 0.5 s, friction 0.5.
Scene pyramid(std::size_t rows, IntegratorType type) {
  ContactSetup setup;
  setup.settings.sleep = false;
  setup.environment = {ground()};
  std::vector<BodyDefinition> bodies;
  const double pitch = kBox.x() + 0.001;
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < rows - r; ++i) {
      const Eigen::Vector3d p(pitch * (static_cast<double>(i) + 0.5 * static_cast<double>(r)), 0.0,
                              0.5 * kBox.z() + kBox.z() * static_cast<double>(r));
      bodies.push_back(bodyAt(MassProperties::box(1.0, kBox), p, Eigen::Vector3d(0.0, 0.0, -9.81)));
      setup.bodies.push_back(boxShape());
      setup.bodies.back()->material.friction = 0.5;
    }
  }
  Scene scene(bodies, type, 0.001, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(500);
  return scene;
}

// Spheres 1 m apart in a cube lattice, zero g, slowly drifting: the broad phase finds no overlapping pair.
Scene apart(std::size_t count, IntegratorType type) {
  ContactSetup setup;
  std::vector<BodyDefinition> bodies;
  const auto side = static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(count))));
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d p(static_cast<double>(i % side), static_cast<double>((i / side) % side),
                            static_cast<double>(i / (side * side)));
    BodyDefinition body = bodyAt(MassProperties::sphere(1.0, 0.1), p, Eigen::Vector3d::Zero());
    body.initial.P_W = Eigen::Vector3d(0.01, 0.0, 0.0);
    bodies.push_back(body);
    CollisionShape sphere;
    sphere.type = ShapeType::kSphere;
    sphere.size.x() = 0.1;
    setup.bodies.push_back(sphere);
  }
  return Scene(bodies, type, 0.001, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

void run(benchmark::State& bench, Scene& scene) {
  for (auto _ : bench) {
    scene.step(kStepsPerTick);
    benchmark::DoNotOptimize(scene.state(scene.bodyCount() - 1));
  }
  bench.counters["per_body_step"] = benchmark::Counter(
      static_cast<double>(bench.iterations()) * static_cast<double>(scene.bodyCount() * kStepsPerTick),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  bench.counters["bodies"] = static_cast<double>(scene.bodyCount());
}

void resting(benchmark::State& bench, IntegratorType type) {
  Scene scene = boxes(static_cast<std::size_t>(bench.range(0)), 1, type);
  run(bench, scene);
}
void stacks(benchmark::State& bench, IntegratorType type) {
  Scene scene = boxes(static_cast<std::size_t>(bench.range(0)), 10, type);
  run(bench, scene);
}
// The stacks with their islands' solves spread over two threads (docs/contact.md, "Islands").
void stacks2Threads(benchmark::State& bench, IntegratorType type) {
  Scene scene = boxes(static_cast<std::size_t>(bench.range(0)), 10, type);
  scene.setThreads(2);
  run(bench, scene);
}
// One large island (docs/architecture.md): on one thread, and on two (its contacts filled and prepared over
// the pool, its sweeps on one thread).
void pyramidRows(benchmark::State& bench, std::size_t threads) {
  Scene scene = pyramid(static_cast<std::size_t>(bench.range(0)), IntegratorType::kRk4);
  scene.setThreads(threads);
  run(bench, scene);
}
void asleep(benchmark::State& bench, IntegratorType type) {
  Scene scene = boxes(static_cast<std::size_t>(bench.range(0)), 10, type, true);
  run(bench, scene);
}
// One box resting on the ground among range − 1 more half-spaces, walls 50 m away all around: what the
// half-spaces cost a body that touches only one of them (each is culled by the body's bounding sphere).
void manyPlanes(benchmark::State& bench) {
  ContactSetup setup;
  setup.settings.sleep = false;
  setup.environment = {ground()};
  const auto planes = static_cast<std::size_t>(bench.range(0));
  for (std::size_t k = 1; k < planes; ++k) {
    const double angle = 6.283185307179586 * static_cast<double>(k) / static_cast<double>(planes);
    CollisionShape wall = ground();
    wall.name = "wall_" + std::to_string(k);
    wall.normal = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
    wall.offset = -50.0;  // solid beyond 50 m, on the far side
    setup.environment.push_back(wall);
  }
  setup.bodies = {boxShape()};
  Scene scene({bodyAt(MassProperties::box(1.0, kBox), Eigen::Vector3d(0.0, 0.0, 0.1), Eigen::Vector3d(0.0, 0.0, -9.81))},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  run(bench, scene);
}
void broadPhaseOnly(benchmark::State& bench) {
  Scene scene = apart(static_cast<std::size_t>(bench.range(0)), IntegratorType::kSemiImplicitEuler);
  run(bench, scene);
}

}  // namespace

BENCHMARK_CAPTURE(resting, rk4, IntegratorType::kRk4)->Arg(1)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(resting, semi_implicit_euler, IntegratorType::kSemiImplicitEuler)
    ->Arg(1)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stacks, rk4, IntegratorType::kRk4)->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stacks, semi_implicit_euler, IntegratorType::kSemiImplicitEuler)
    ->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stacks2Threads, rk4, IntegratorType::kRk4)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(pyramidRows, one_thread, 1)->Arg(20)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(pyramidRows, two_threads, 2)->Arg(20)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(asleep, rk4, IntegratorType::kRk4)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(broadPhaseOnly)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(manyPlanes)->Arg(1)->Arg(2000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
