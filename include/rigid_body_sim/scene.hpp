// The bodies of a scene and their step: constant models, mutable states, inputs and integrators, kept as
// contiguous arrays one per field, stepped together. No clock here: World owns time (world.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

/// Why a body stopped integrating; kNone while it runs.
enum class Divergence {
  kNone,
  kNonFiniteState,  ///< a step produced NaN or Inf (e.g. a momentum that overflowed)
  kEnergyGrowth,    ///< the energy grew by more than max_energy_growth in one call with nothing to explain it
  kStepFailure,     ///< the integrator gave up (implicit solve or step-size control)
};

const char* divergenceName(Divergence divergence);

/// One body as a scene declares it.
struct BodyDefinition {
  Model model;               ///< mass properties and force models, constant for the scene's life
  State initial;             ///< the state at start-up and after reset
  bool takes_input = true;   ///< the body has a wrench input (false: no input term, setInput refuses a wrench)
};

/// How a Scene sets each body's StepTerms.
enum class StepAssembly {
  kLeaveOut,  ///< assembleTerms: only the terms the scene declares (the default, and the node's)
  kGeneral,   ///< every term (StepTerms::all()), the reference the specialised steps are tested against
};

/// What one Scene::step did.
struct SceneStepResult {
  std::int64_t steps = 0;               ///< steps integrated (by the bodies still running)
  StepStatus status = StepStatus::kOk;  ///< kNonFinite if a body's step failed; it keeps its last good state
  bool diverged = false;                ///< this call latched some body's divergence
};

/// Bodies sharing one integrator method and dt. The bodies are independent (no contact, no joints): each
/// steps with its own model, terms, input and integrator memory, body by body over contiguous arrays: no
/// allocation, no virtual call, a cost linear in the bodies. A body whose step fails or whose energy grows
/// beyond the guard latches its own divergence and holds its last good state; the others go on.
/// Accessors without a body index mean body 0 (the one-body shorthand).
class Scene {
 public:
  /// Throws std::invalid_argument for no bodies, a non-finite initial state or a dt that is not > 0.
  Scene(const std::vector<BodyDefinition>& bodies, IntegratorType integrator, double dt,
        const IntegratorSettings& settings = IntegratorSettings(), StepAssembly assembly = StepAssembly::kLeaveOut);

  /// The divergence guard: when no wrench is commanded, the mechanical energy E = T + V may not grow by more
  /// than this factor (> 1) within one step() call; physics allows no growth at all then (damping only
  /// removes energy), so a larger growth is a numerical blow-up. Infinity disables the check.
  void setMaxEnergyGrowth(double factor) { max_energy_growth_ = factor; }

  /// Integrates `steps` ≥ 0 steps of dt for every running body, under the inputs as they stand.
  SceneStepResult step(std::int64_t steps);

  std::size_t bodyCount() const { return states_.size(); }
  double dt() const { return dt_; }
  IntegratorType integratorType() const { return integrators_.front().type(); }

  /// Replaces a body's input from the next step on. Throws std::invalid_argument for a non-zero wrench on a
  /// body without input (its step has no input term to carry it).
  void setInput(std::size_t body, const AppliedWrench& input);
  const AppliedWrench& input(std::size_t body = 0) const { return inputs_[body]; }
  bool takesInput(std::size_t body = 0) const { return records_[body].takes_input; }

  /// Every body back to its initial state (and terms) with no input, divergences cleared, integrator memory
  /// dropped.
  void reset();
  /// Replaces a body's state if it is finite (returns whether it was). Its terms are assembled again: a
  /// state with spin gives a body rotation it did not need before.
  bool setState(std::size_t body, const State& state);

  const State& state(std::size_t body = 0) const { return states_[body]; }
  const Model& model(std::size_t body = 0) const { return models_[body]; }
  /// The terms a body's step evaluates: the assembled-terms query.
  const StepTerms& terms(std::size_t body = 0) const { return terms_[body]; }
  Divergence divergence(std::size_t body = 0) const { return records_[body].divergence; }
  /// The first body that has diverged, or bodyCount() when none has.
  std::size_t firstDiverged() const;
  /// Bodies still integrating (not diverged).
  std::size_t runningBodies() const;
  /// Steps a body integrated since construction (paused, dropped and diverged steps do not count).
  std::int64_t integratedSteps(std::size_t body = 0) const { return records_[body].integrated_steps; }
  /// A body's state at construction (and after every reset), for drift diagnostics.
  const State& initialState(std::size_t body = 0) const { return records_[body].initial; }

 private:
  // What the step loop does not read: kept apart so the hot arrays stay dense.
  struct BodyRecord {
    State initial;
    bool takes_input = true;
    Divergence divergence = Divergence::kNone;
    std::int64_t integrated_steps = 0;
  };

  // One body's `steps` steps and its divergence check; returns the steps done.
  std::int64_t stepBody(std::size_t body, std::int64_t steps, StepStatus& status);
  void assemble(std::size_t body);

  // The hot arrays, one entry per body. models_ never changes after construction.
  std::vector<Model> models_;
  std::vector<StepTerms> terms_;
  std::vector<State> states_;
  std::vector<AppliedWrench> inputs_;
  std::vector<Integrator> integrators_;
  std::vector<BodyRecord> records_;
  IntegratorType integrator_type_;
  IntegratorSettings settings_;
  StepAssembly assembly_;
  double dt_;
  double max_energy_growth_ = std::numeric_limits<double>::infinity();
};

}  // namespace rigid_body
