// What a lone step's time is made of (Google Benchmark; not a test, run by hand, docs/performance.md):
//   - latency/*: this core's latency of a dependent double addition, multiplication, division and square
//     root (64 dependent operations per iteration; the counter ns_per_op);
//   - kernel/*: the lane kernel of src/integrators/lane_dispatch.hpp on one general body (the scene of
//     integrators_benchmark's general case), 100 steps per iteration (the counter ns_per_step), without the
//     State it is loaded from and stored to and without the acceptability test: what Integrator::step costs
//     beyond it is the call around it.
#include <benchmark/benchmark.h>

#include <cmath>

#include "general_body.hpp"
#include "integrators/lane_dispatch.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace {

using namespace rigid_body;
using namespace rigid_body::integrators;

constexpr int kChain = 64;

template <class Op>
void dependentChain(benchmark::State& bench, Op op) {
  double x = 1.0;
  benchmark::DoNotOptimize(x);
  for (auto _ : bench) {
    for (int i = 0; i < kChain; ++i) x = op(x);  // each operation waits for the last one's result
    benchmark::DoNotOptimize(x);
  }
  bench.counters["ns_per_op"] = benchmark::Counter(static_cast<double>(bench.iterations()) * kChain,
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void latencyAdd(benchmark::State& bench) {
  volatile double tiny = 1e-300;  // read once: the compiler cannot fold x + tiny
  const double b = tiny;
  dependentChain(bench, [b](double x) { return x + b; });
}
void latencyMul(benchmark::State& bench) {
  volatile double one = 1.0;
  const double b = one;
  dependentChain(bench, [b](double x) { return x * b; });
}
void latencyDiv(benchmark::State& bench) {
  dependentChain(bench, [](double x) { return 1.0 / x; });
}
void latencySqrt(benchmark::State& bench) {
  dependentChain(bench, [](double x) { return std::sqrt(x); });
}

struct GeneralBody {
  LaneBody<double> b;
  LaneState<double> y;
  StepTerms terms;
  GeneralBody(IntegratorType type) {
    const Model model = bench_bodies::generalModel();
    const State state = bench_bodies::spinningState(model.mass);
    const AppliedWrench input = bench_bodies::generalInput();
    terms = assembleTerms(model.mass, model.forces, state, true);
    loadBody(b, 0, type, terms, model, input);
    loadState(y, 0, state);
  }
};

template <IntegratorType kType>
void kernel(benchmark::State& bench) {
  GeneralBody body(kType);
  constexpr int kSteps = 100;  // the state stays in registers between these steps, as in a batch's loop
  for (auto _ : bench) {
    for (int i = 0; i < kSteps; ++i) body.y = laneKernelStep(kType, body.b, body.terms, 0.001, body.y);
    benchmark::DoNotOptimize(body.y);
  }
  bench.counters["ns_per_step"] = benchmark::Counter(static_cast<double>(bench.iterations()) * kSteps,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(latencyAdd)->Name("latency/add");
BENCHMARK(latencyMul)->Name("latency/mul");
BENCHMARK(latencyDiv)->Name("latency/div");
BENCHMARK(latencySqrt)->Name("latency/sqrt");
BENCHMARK(kernel<IntegratorType::kExplicitEuler>)->Name("kernel/general/explicit_euler");
BENCHMARK(kernel<IntegratorType::kSemiImplicitEuler>)->Name("kernel/general/semi_implicit_euler");
BENCHMARK(kernel<IntegratorType::kRk4>)->Name("kernel/general/rk4");

BENCHMARK_MAIN();
