// Cost of one step per integrator (Google Benchmark). Not a test: run by scripts/benchmark.sh.
//
// The general body has everything the step can meet: a full (non-diagonal) inertia tensor, spin, gravity,
// linear and angular damping, and an input with world and body parts. The isotropic body is the same scene
// on a sphere; the torque-free body is the asymmetric scene of the tests; the gravity-only body falls without
// spin or input. Each case runs twice: "all_terms" evaluates every term of the step (StepTerms::all()), and
// "assembled" only those the scene declares (assembleTerms), so the ratio is what leaving out saves.
// Each iteration is one step of 1 ms. rk4 and the two Eulers run once more as ".../baseline_isa", with
// IntegratorSettings::wide_instructions off: the step in the build's own instruction set where the default
// picks AVX-512 at run time (the two compared: docs/performance.md).
#include <benchmark/benchmark.h>

#include "general_body.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace {

using namespace rigid_body;

using bench_bodies::generalInput;
using bench_bodies::generalModel;
using bench_bodies::spinningState;

enum class Terms { kAll, kAssembled, kAssembledBaselineIsa };

// Times one step of 1 ms per iteration and reports the f evaluations per step.
void timeSteps(benchmark::State& bench, IntegratorType type, Model model, const AppliedWrench& input, State state,
               Terms terms) {
  const StepTerms step_terms = terms == Terms::kAll ? StepTerms::all()
                                                   : assembleTerms(model.mass, model.forces, state, !input.isZero());
  IntegratorSettings settings;
  settings.wide_instructions = terms != Terms::kAssembledBaselineIsa;
  Integrator integrator(type, settings);
  for (auto _ : bench) {
    integrator.step(model, step_terms, input, 0.001, state);
    benchmark::DoNotOptimize(state);
  }
  bench.counters["rhs_per_step"] =
      static_cast<double>(integrator.statistics().rhs_evaluations) / static_cast<double>(integrator.statistics().steps);
}

void stepGeneralBody(benchmark::State& bench, IntegratorType type, Terms terms) {
  const Model model = generalModel();
  timeSteps(bench, type, model, generalInput(), spinningState(model.mass), terms);
}

// The general body's scene on an isotropic body (a sphere): ω = L/I₀ skips the world-inertia rotation.
void stepIsotropicBody(benchmark::State& bench, IntegratorType type, Terms terms) {
  Model model = generalModel();
  model.mass = MassProperties::sphere(1.5, 0.2);
  timeSteps(bench, type, model, generalInput(), spinningState(model.mass), terms);
}

// Zero g, no damping, no input, spinning: assembled, the step has rotation but no force term.
void stepTorqueFreeBody(benchmark::State& bench, IntegratorType type, Terms terms) {
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1, 2, 3).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  State state;
  state.L_W = Eigen::Vector3d(1.0, 0.5, 2.0);
  timeSteps(bench, type, model, AppliedWrench(), state, terms);
}

// A box falling without spin or input: assembled, the step is translation under gravity only.
void stepGravityOnlyBody(benchmark::State& bench, IntegratorType type, Terms terms) {
  Model model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  model.forces.gravity_W = Eigen::Vector3d(0.0, 0.0, -9.81);
  State state;
  state.p_WB = Eigen::Vector3d(0.0, 0.0, 10.0);
  state.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  timeSteps(bench, type, model, AppliedWrench(), state, terms);
}

int registerAll() {
  using Case = void (*)(benchmark::State&, IntegratorType, Terms);
  const std::pair<const char*, Case> cases[] = {{"general", stepGeneralBody},
                                                {"isotropic", stepIsotropicBody},
                                                {"torque_free", stepTorqueFreeBody},
                                                {"gravity_only", stepGravityOnlyBody}};
  for (const auto& [name, run] : cases) {
    for (IntegratorType type : allIntegrators()) {
      for (Terms terms : {Terms::kAll, Terms::kAssembled, Terms::kAssembledBaselineIsa}) {
        const bool wide = type == IntegratorType::kRk4 || type == IntegratorType::kSemiImplicitEuler ||
                          type == IntegratorType::kExplicitEuler;
        if (terms == Terms::kAssembledBaselineIsa && !wide) continue;
        const char* suffix = terms == Terms::kAll         ? "/all_terms"
                             : terms == Terms::kAssembled ? "/assembled"
                                                          : "/assembled/baseline_isa";
        const std::string label = std::string(name) + "/" + integratorName(type) + suffix;
        benchmark::RegisterBenchmark(label.c_str(), run, type, terms);
      }
    }
  }
  return 0;
}
const int registered = registerAll();

}  // namespace

BENCHMARK_MAIN();
