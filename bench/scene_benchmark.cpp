// Cost of a scene of N bodies per body and step (Google Benchmark), N = 1 … 10 000. Not a test: run by
// scripts/benchmark.sh. The per-body time must stay flat in N (a cost linear in the bodies): the Scene
// keeps each field of the bodies in one contiguous array and steps them body by body, with no allocation
// and no virtual call in the loop.
//
// The scene is the swarm's: bodies cycling through box, sphere and cylinder with spin, zero g, half of them
// pushed by a constant wrench. One iteration is one tick of the node's default timing: 10 steps of 1 ms.
// The threaded cases step the same scene on every core (Scene::setThreads(0)), timed by the wall clock. Batches
// run on AVX where the CPU has it (Scene::wideLanes); the portable cases turn that off.
#include <benchmark/benchmark.h>

#include <vector>

#include "general_body.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/world.hpp"

namespace {

using namespace rigid_body;

constexpr std::int64_t kStepsPerTick = 10;

std::vector<BodyDefinition> swarmBodies(std::size_t bodies) {
  const MassProperties shapes[] = {MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)),
                                   MassProperties::sphere(1.0, 0.15), MassProperties::cylinder(1.0, 0.1, 0.4)};
  std::vector<BodyDefinition> definitions;
  for (std::size_t i = 0; i < bodies; ++i) {
    const MassProperties& mass = shapes[i % 3];
    const State initial = stateFromVelocities(
        mass, Eigen::Vector3d(static_cast<double>(i % 100), static_cast<double>(i / 100), 0.0),
        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 0.01 * static_cast<double>(i % 7)),
        Eigen::Vector3d(0.1, 0.2, 0.1 * static_cast<double>(i % 5)));
    definitions.push_back({Model{mass, ForceModel{}}, initial, i % 2 == 0});
  }
  return definitions;
}

AppliedWrench push() {
  AppliedWrench wrench;
  wrench.world.force = Eigen::Vector3d(0.1, 0.0, 0.0);
  wrench.body.torque = Eigen::Vector3d(0.0, 0.0, 0.001);
  return wrench;
}

Scene swarm(std::size_t bodies, IntegratorType type) {
  Scene simulation(swarmBodies(bodies), type, 0.001);
  for (std::size_t i = 0; i < bodies; i += 2) simulation.setInput(i, push());
  return simulation;
}

enum class Vectors { kWide, kPortable };

void stepScene(benchmark::State& bench, IntegratorType type, std::size_t threads, Vectors vectors) {
  const auto bodies = static_cast<std::size_t>(bench.range(0));
  Scene simulation = swarm(bodies, type);
  simulation.setThreads(threads);
  simulation.setWideLanes(vectors == Vectors::kWide);
  for (auto _ : bench) {
    simulation.step(kStepsPerTick);
    benchmark::DoNotOptimize(simulation.state(bodies - 1));
  }
  // ns per body and step: the number that must stay flat in N.
  bench.counters["per_body_step"] = benchmark::Counter(
      static_cast<double>(bench.iterations()) * static_cast<double>(bodies * kStepsPerTick),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  bench.counters["bodies"] = static_cast<double>(bodies);
}

// The general body (general_body.hpp) alone in a Scene, a tick of 10 steps: a Scene's lone body runs the loop of its
// method's lone kernel, where Integrator::step runs one step a call. Reported per step.
void stepGeneralBody(benchmark::State& bench, IntegratorType type) {
  const Model model = bench_bodies::generalModel();
  Scene simulation({{model, bench_bodies::spinningState(model.mass), true}}, type, 0.001);
  simulation.setInput(0, bench_bodies::generalInput());
  for (auto _ : bench) {
    simulation.step(kStepsPerTick);
    benchmark::DoNotOptimize(simulation.state(0));
  }
  bench.counters["per_step"] =
      benchmark::Counter(static_cast<double>(bench.iterations() * kStepsPerTick),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The same tick through the World, as the node's timer runs it: update(now) 10 ms on, commands none. The
// difference to stepScene is the runner's overhead (clock, catch-up budget, input timeline).
void updateWorld(benchmark::State& bench, IntegratorType type) {
  const auto bodies = static_cast<std::size_t>(bench.range(0));
  WorldSettings settings;
  settings.dt = 0.001;
  World world(swarmBodies(bodies), type, IntegratorSettings(), settings);
  world.start(0);
  for (std::size_t i = 0; i < bodies; i += 2) world.setWrench(i, push(), 0);
  Nanoseconds now = 0;
  for (auto _ : bench) {
    now += kStepsPerTick * 1000000;
    world.update(now);
    benchmark::DoNotOptimize(world.scene().state(bodies - 1));
  }
  bench.counters["per_body_step"] = benchmark::Counter(
      static_cast<double>(bench.iterations()) * static_cast<double>(bodies * kStepsPerTick),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  bench.counters["bodies"] = static_cast<double>(bodies);
}

int registerAll() {
  for (IntegratorType type : {IntegratorType::kExplicitEuler, IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    benchmark::RegisterBenchmark(("scene/" + integratorName(type)).c_str(), stepScene, type, 1, Vectors::kWide)
        ->RangeMultiplier(10)
        ->Range(1, 10000)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("threaded/" + integratorName(type)).c_str(), stepScene, type, 0, Vectors::kWide)
        ->RangeMultiplier(10)
        ->Range(100, 10000)
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
    // The same without AVX (the build's baseline vectors), one core and all cores.
    benchmark::RegisterBenchmark(("portable/" + integratorName(type)).c_str(), stepScene, type, 1, Vectors::kPortable)
        ->Arg(1000)
        ->Arg(10000)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("portable_threaded/" + integratorName(type)).c_str(), stepScene, type, 0,
                                 Vectors::kPortable)
        ->Arg(1000)
        ->Arg(10000)
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("general_body/" + integratorName(type)).c_str(), stepGeneralBody, type);
    benchmark::RegisterBenchmark(("world/" + integratorName(type)).c_str(), updateWorld, type)
        ->RangeMultiplier(10)
        ->Range(1, 10000)
        ->Unit(benchmark::kMicrosecond);
  }
  return 0;
}
const int registered = registerAll();

}  // namespace

BENCHMARK_MAIN();
