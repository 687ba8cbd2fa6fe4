// A scene of bodies advanced in fixed steps against an external clock: the part of the node's timer loop
// that needs no ROS, so it is tested with explicit times.
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

/// What one call to Simulation::advanceTo did.
struct AdvanceResult {
  std::int64_t steps = 0;    ///< steps integrated (by the bodies still running)
  std::int64_t dropped = 0;  ///< steps due but skipped because of the max_substeps cap (time lost)
  StepStatus status = StepStatus::kOk;  ///< kNonFinite if a body's step failed; it then keeps its last good state
  bool diverged = false;     ///< this call latched some body's divergence state (see Simulation::divergence)
};

/// Why the simulation stopped integrating; kNone while it runs.
enum class Divergence {
  kNone,
  kNonFiniteState,  ///< a step produced NaN or Inf (e.g. a momentum that overflowed)
  kEnergyGrowth,    ///< the energy grew by more than max_energy_growth in one call with nothing to explain it
  kStepFailure,     ///< the integrator gave up (implicit solve or step-size control)
};

const char* divergenceName(Divergence divergence);

/// One body as a scene declares it.
struct BodyDefinition {
  Model model;               ///< mass properties and force models; the terms are assembled by the Simulation
  State initial;             ///< the state at start-up and after reset
  bool takes_input = true;   ///< the body has a wrench input (false: no input term, setInput refuses a wrench)
};

/// How a Simulation sets each body's StepTerms.
enum class StepAssembly {
  kLeaveOut,  ///< assembleTerms: only the terms the scene declares (the default, and the node's)
  kGeneral,   ///< every term (StepTerms::all()), the reference the specialised steps are tested against
};

/// Whole steps of length dt that fit into `elapsed` seconds: ⌊elapsed/dt⌋, with a relative guard so that
/// e.g. 0.03/0.001 = 29.999999999999996 counts as 30.
std::int64_t wholeStepsIn(double elapsed, double dt);

/// Bodies, one integrator method and the inputs, advanced on a fixed grid t_k = k·dt of an external clock.
/// The clock count k only grows (also across reset), so times derived from it strictly increase.
///
/// The bodies are independent (no contact, no joints): each steps with its own model, input and integrator
/// memory. They are kept as contiguous arrays, one per field (models, states, inputs, integrators), and the
/// step loop runs body by body over them: no allocation, no virtual call, a cost linear in the bodies.
/// A body whose step fails or whose energy grows latches its own divergence; the others go on.
/// Accessors without a body index mean body 0 (the one-body shorthand).
class Simulation {
 public:
  /// One body that takes input. dt > 0 [s]; max_substeps ≥ 1 bounds the steps one advanceTo integrates
  /// ("Fix your timestep").
  Simulation(const Model& model, const State& initial, IntegratorType integrator, double dt,
             std::int64_t max_substeps, const IntegratorSettings& settings = IntegratorSettings(),
             StepAssembly assembly = StepAssembly::kLeaveOut);
  /// A scene of one or more bodies sharing the integrator method, dt and the clock.
  Simulation(const std::vector<BodyDefinition>& bodies, IntegratorType integrator, double dt,
             std::int64_t max_substeps, const IntegratorSettings& settings = IntegratorSettings(),
             StepAssembly assembly = StepAssembly::kLeaveOut);

  /// The divergence guard: when no wrench is commanded, the mechanical energy E = T + V may not grow by more
  /// than this factor (> 1) within one advanceTo; physics allows no growth at all then (damping only
  /// removes energy), so a larger growth is a numerical blow-up. Infinity disables the check.
  void setMaxEnergyGrowth(double factor) { max_energy_growth_ = factor; }

  /// Integrates the whole steps between the last grid point reached and `elapsed` [s] since the start.
  /// If more than max_substeps are due, the rest is dropped (the body does not move for them) and counted.
  /// After a divergence the clock still advances but the state stays the last good one until reset().
  AdvanceResult advanceTo(double elapsed);

  /// The clock step that `elapsed` [s] since the start falls on (after the last reanchor).
  std::int64_t clockStepsAt(double elapsed) const;
  /// advanceTo expressed in clock steps: integrates up to clock step `target` (nothing if already there).
  AdvanceResult advanceToStep(std::int64_t target);

  /// Re-anchors the clock: the next advanceTo counts grid points from `elapsed` on (after ROS time jumped
  /// backwards). The state is kept; clockSteps() keeps counting up from where it is.
  void reanchor(double elapsed);

  /// While paused, advanceTo moves the clock but not the state (as after a divergence).
  void setPaused(bool paused) { paused_ = paused; }
  bool paused() const { return paused_; }

  /// Integrates `steps` steps now, paused or not, without moving the clock (a user's "step" request when
  /// the clock belongs to someone else). Stops at a failure, which latches the divergence as advanceTo does.
  AdvanceResult stepNow(std::int64_t steps);

  /// Sets the clock back to 0 (a deliberate rewind: reset_time in lockstep); the state is not touched.
  void rewindClock();

  std::size_t bodyCount() const { return states_.size(); }

  /// Replaces a body's input from the next step on. Throws std::invalid_argument for a non-zero wrench on a
  /// body without input (its step has no input term to carry it).
  void setInput(std::size_t body, const AppliedWrench& input);
  void setInput(const AppliedWrench& input) { setInput(0, input); }
  /// Every body's input to zero.
  void clearInput();
  const AppliedWrench& input(std::size_t body = 0) const { return inputs_[body]; }

  /// Every body back to its initial state (and its terms) with no input, divergences cleared; the clock keeps running.
  void reset();

  Divergence divergence(std::size_t body = 0) const { return bodies_[body].divergence; }
  /// True if any body has diverged.
  bool anyDiverged() const;
  /// Replaces a body's state (kept only if finite; returns whether it was). Its terms are assembled again:
  /// a state with spin gives a body rotation it did not need before.
  bool setState(std::size_t body, const State& state);
  bool setState(const State& state) { return setState(0, state); }

  const State& state(std::size_t body = 0) const { return states_[body]; }
  const Model& model(std::size_t body = 0) const { return models_[body]; }
  /// The terms a body's step evaluates: the assembled-terms query.
  const StepTerms& terms(std::size_t body = 0) const { return models_[body].terms; }
  bool takesInput(std::size_t body = 0) const { return bodies_[body].takes_input; }
  IntegratorType integratorType() const { return integrators_.front().type(); }
  const IntegratorStatistics& integratorStatistics(std::size_t body = 0) const { return integrators_[body].statistics(); }
  double dt() const { return dt_; }
  /// Grid points passed since the start, integrated or dropped: the state belongs to time clockSteps()·dt.
  std::int64_t clockSteps() const { return clock_steps_; }
  std::int64_t droppedSteps() const { return dropped_steps_; }
  /// Steps a body integrated since construction (not the clock: paused, dropped and diverged steps do not count).
  std::int64_t integratedSteps(std::size_t body = 0) const { return bodies_[body].integrated_steps; }
  /// A body's state at the last reset (or construction), for drift diagnostics.
  const State& initialState(std::size_t body = 0) const { return bodies_[body].initial; }

 private:
  // What the step loop does not read: kept apart so the hot arrays stay dense.
  struct BodyRecord {
    State initial;
    bool takes_input = true;
    Divergence divergence = Divergence::kNone;
    std::int64_t integrated_steps = 0;
  };

  // Integrates `steps` steps from the current states with the divergence checks; the clock is the caller's.
  AdvanceResult integrate(std::int64_t steps);
  // One body's `steps` steps and its divergence check; returns the steps done.
  std::int64_t integrateBody(std::size_t body, std::int64_t steps, StepStatus& status);
  void assemble(std::size_t body);

  // The hot arrays, one entry per body.
  std::vector<Model> models_;
  std::vector<State> states_;
  std::vector<AppliedWrench> inputs_;
  std::vector<Integrator> integrators_;
  std::vector<BodyRecord> bodies_;
  StepAssembly assembly_;
  double dt_;
  std::int64_t max_substeps_;
  std::int64_t clock_steps_ = 0;
  std::int64_t dropped_steps_ = 0;
  std::int64_t anchor_steps_ = 0;  // grid points counted before the last reanchor
  double anchor_elapsed_ = 0.0;    // elapsed time of the last reanchor [s]
  double max_energy_growth_ = std::numeric_limits<double>::infinity();
  bool paused_ = false;
};

}  // namespace rigid_body
