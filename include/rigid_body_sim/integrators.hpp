// Time integrators for the state-space form Y = (x, q, P, L), behind one interface.
//
// Every method keeps the momentum form: with no torque, world L is unchanged by any step, so the errors
// of a torque-free body live in the orientation (and, through it, in the energy).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

/// The available methods. A new method goes here, in the registry table of integrators.cpp (one row: what
/// the node, the report, the contact step and the tests ask of a method) and in Integrator::doStep's switch;
/// the typed tests (test_integrator_suite.cpp) run every registered method.
enum class IntegratorType {
  kExplicitEuler,        ///< Y ← Y + h f(Y), then q normalised. Order 1.
  kSemiImplicitEuler,    ///< momenta first, then x with the new v and q ← exp(ω h) ⊗ q. Order 1.
  kRk4,                  ///< classic Runge–Kutta on the whole Y, q normalised after the step. Order 4.
  kRkmk4,                ///< Runge–Kutta–Munthe-Kaas: RK4 with q on the rotation group (exp, dexp⁻¹). Order 4.
  kBuss,                 ///< Buss's augmented second-order rotation update (2000). Order 2.
  kSymplecticSplitting,  ///< Strang splitting: exact damping, kicks, drift and split free rotations. Order 2.
  kImplicitMidpoint,     ///< midpoint rule on body momentum, Cayley rotation (Lie–Poisson). Order 2.
  kDopri5,               ///< Dormand–Prince 5(4), error control and dense output. Order 5.
};

/// One row of the registry: everything the node, the report, the contact step and the documentation ask of
/// a method, so that none of them tests a method by name.
/// A method's step written plainly (Eigen, the equations as they read): Y_{n+1} from Y_n.
using ReferenceStep = State (*)(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                const State& y);

struct IntegratorInfo {
  IntegratorType type;
  std::string name;  ///< the parameter value, e.g. "rk4"
  int order;         ///< nominal order of accuracy: the global error is O(h^order)
  /// Evaluations of f(Y) (or their equivalent in the split methods) per step; dopri5: per internal step
  /// after the first, which takes one more (first same as last).
  int rhs_evaluations;
  bool adaptive;  ///< chooses its own internal steps against abs/rel tolerances (the step h is an interval)
  /// Integrates linear damping by its exact exponential flow (the Strang splittings): a stiff damping
  /// decays monotonically at any h.
  bool exact_damping;
  /// c in Δx = c h² a: how far one step moves a body from rest under a constant acceleration a. Exact motion
  /// and every method of order ≥ 2 give ½ (Σ bᵢcᵢ = ½ for a Runge–Kutta method); explicit Euler moves x
  /// with the old velocity (0), semi-implicit Euler with the new one (1). The contact step uses it to undo a
  /// resting body's fall exactly (docs/contact.md).
  double constant_force_weight;
  /// Steps by a lane kernel: one body, or four at a time in vector lanes (src/integrators/lane_dispatch.hpp,
  /// docs/architecture.md).
  bool lane_kernel;
  const char* summary;  ///< one line for tables and logs
  /// With a lane kernel: the plain scalar version of the method, which the kernel is tested against
  /// (src/integrators/reference_steps.hpp). Null for a method whose step is already written plainly.
  ReferenceStep reference_step = nullptr;
};

/// The registry, in the order of the documentation.
const std::vector<IntegratorInfo>& integratorRegistry();

/// The row of `type`.
const IntegratorInfo& integratorInfo(IntegratorType type);

/// Every method, in the order of the documentation.
const std::vector<IntegratorType>& allIntegrators();

/// The parameter name of a method, e.g. "rk4".
const std::string& integratorName(IntegratorType type);

/// The method called `name`; throws std::invalid_argument listing the valid names otherwise.
IntegratorType integratorFromName(const std::string& name);

/// "explicit_euler, semi_implicit_euler, rk4, ...": the valid names, for messages.
std::string integratorNameList();

/// The nominal order of accuracy of a method (the global error is O(h^order)).
int nominalOrder(IntegratorType type);

/// Outcome of one step.
enum class StepStatus {
  kOk,            ///< the state was advanced
  kInvalidStep,   ///< h was negative or not finite: the state is unchanged
  kNonFinite,     ///< the step produced a non-finite state or a non-unit q: the state is unchanged
  kNotConverged,  ///< an implicit solve or the step-size control failed: the state is unchanged
};

/// Settings of the methods that have them. Defaults are the node's.
struct IntegratorSettings {
  double abs_tolerance = 1e-9;   ///< dopri5: absolute error per step, per state component
  double rel_tolerance = 1e-9;   ///< dopri5: relative error per step, per state component
  /// implicit_midpoint: the Newton iteration stops when the update is below this, relative to |m|.
  double newton_tolerance = 1e-15;
  int newton_max_iterations = 20;  ///< implicit_midpoint: the cap, beyond which the step fails
  /// rk4 and the two Eulers: step in AVX-512's instructions where the CPU has them, in the build's own
  /// (x86-64: SSE2) where it has not or this is false. The same results bit for bit either way.
  bool wide_instructions = true;
};

/// Work counters since construction: the machine-independent cost of the method.
struct IntegratorStatistics {
  std::uint64_t steps = 0;              ///< calls of step() with h > 0 that succeeded
  std::uint64_t rhs_evaluations = 0;    ///< evaluations of f(Y) (or its equivalent in the split methods)
  std::uint64_t accepted_steps = 0;     ///< dopri5: internal steps accepted
  std::uint64_t rejected_steps = 0;     ///< dopri5: internal steps rejected by the error control
  std::uint64_t newton_iterations = 0;  ///< implicit_midpoint
};

/// One integrator. `step` is the public entry: it checks h, runs the method on a copy, checks the result
/// and commits it only if it is finite, so on failure the state is unchanged (Drake's contract).
/// dopri5 keeps its step-size controller and its last internal step (for dense output) between calls;
/// the other methods are stateless.
class Integrator {
 public:
  explicit Integrator(IntegratorType type, const IntegratorSettings& settings = IntegratorSettings());

  IntegratorType type() const { return type_; }
  const IntegratorSettings& settings() const { return settings_; }
  const IntegratorStatistics& statistics() const { return statistics_; }

  /// Advances `state` by h ≥ 0 [s] under `input`, held constant over the step, evaluating the assembled
  /// `terms` only. h = 0 leaves it as it is.
  StepStatus step(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, State& state);
  /// Whether a step's result may be committed: finite, with a unit quaternion (what step() checks).
  static bool acceptable(const State& next);
  /// How far |q| of a step's result may be from 1. Every method ends a step with |q| = 1 to rounding (≤ 1e-15
  /// measured); off by more, the step failed even if every number is finite: normalising a q whose
  /// components overflowed divides by infinity and gives the zero quaternion, which is no rotation at all.
  static constexpr double kUnitQuaternionTolerance = 1e-6;
  /// Counts `steps` successful steps taken for this integrator by its Scene, which steps explicit Euler,
  /// semi-implicit Euler and rk4 bodies several at a time with the same arithmetic as step() (rhs evaluations
  /// counted per method).
  void countSteps(std::uint64_t steps);

  /// The general step: every term (StepTerms::all()).
  StepStatus step(const Model& model, const AppliedWrench& input, double h, State& state) {
    return step(model, StepTerms::all(), input, h, state);
  }

 private:
  StepStatus doStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, State& state);
  StepStatus dopri5Step(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, State& state);

  IntegratorType type_;
  const IntegratorInfo* info_;  // its registry row
  IntegratorSettings settings_;
  bool wide_;  // settings_.wide_instructions and the CPU has them
  IntegratorStatistics statistics_;

  // dopri5: the last accepted internal step [t0, t0 + h] with what dense output needs, and the size the
  // controller proposes next. The internal solution runs ahead of the published one; it is reused only
  // while the caller's state is the one this integrator last returned and the input has not changed.
  struct DopriMemory {
    bool valid = false;
    double next_h = 0.0;
    State last_output;
    AppliedWrench input;
    Eigen::Matrix<double, 13, 5> coefficients;  // rcont1..rcont5 of Hairer's DOPRI5, per component
    double t0 = 0.0;
    double h = 0.0;
  } dopri_;
};

}  // namespace rigid_body
