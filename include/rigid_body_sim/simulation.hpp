// One body advanced in fixed steps against an external clock: the part of the node's timer loop that
// needs no ROS, so it is tested with explicit times.
#pragma once

#include <cstdint>
#include <limits>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// What one call to Simulation::advanceTo did.
struct AdvanceResult {
  std::int64_t steps = 0;    ///< steps integrated
  std::int64_t dropped = 0;  ///< steps due but skipped because of the max_substeps cap (time lost)
  StepStatus status = StepStatus::kOk;  ///< kNonFinite if a step failed; the state is then the last good one
  bool diverged = false;     ///< this call latched the divergence state (see Simulation::divergence)
};

/// Why the simulation stopped integrating; kNone while it runs.
enum class Divergence {
  kNone,
  kNonFiniteState,  ///< a step produced NaN or Inf (e.g. a momentum that overflowed)
  kEnergyGrowth,    ///< the energy grew by more than max_energy_growth in one call with nothing to explain it
  kStepFailure,     ///< the integrator gave up (implicit solve or step-size control)
};

const char* divergenceName(Divergence divergence);

/// Whole steps of length dt that fit into `elapsed` seconds: ⌊elapsed/dt⌋, with a relative guard so that
/// e.g. 0.03/0.001 = 29.999999999999996 counts as 30.
std::int64_t wholeStepsIn(double elapsed, double dt);

/// A body, its integrator and the input, advanced on a fixed grid t_k = k·dt of an external clock.
/// The clock count k only grows (also across reset), so times derived from it strictly increase.
class Simulation {
 public:
  /// dt > 0 [s]; max_substeps ≥ 1 bounds the steps one advanceTo integrates ("Fix your timestep").
  Simulation(const Model& model, const State& initial, IntegratorType integrator, double dt,
             std::int64_t max_substeps, const IntegratorSettings& settings = IntegratorSettings());

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

  /// Replaces the input from the next step on.
  void setInput(const AppliedWrench& input) { input_ = input; }
  void clearInput() { input_ = AppliedWrench(); }
  const AppliedWrench& input() const { return input_; }

  /// Back to the initial state with no input, the divergence cleared; the clock count keeps running.
  void reset();

  Divergence divergence() const { return divergence_; }
  /// Replaces the state (kept only if finite; returns whether it was).
  bool setState(const State& state);

  const State& state() const { return state_; }
  const Model& model() const { return model_; }
  IntegratorType integratorType() const { return integrator_.type(); }
  const IntegratorStatistics& integratorStatistics() const { return integrator_.statistics(); }
  double dt() const { return dt_; }
  /// Grid points passed since the start, integrated or dropped: the state belongs to time clockSteps()·dt.
  std::int64_t clockSteps() const { return clock_steps_; }
  std::int64_t droppedSteps() const { return dropped_steps_; }
  /// Steps integrated since construction (not the clock: paused, dropped and diverged steps do not count).
  std::int64_t integratedSteps() const { return integrated_steps_; }
  /// The state and energy at the last reset (or construction), for drift diagnostics.
  const State& initialState() const { return initial_; }

 private:
  // Integrates `steps` steps from the current state with the divergence checks; the clock is the caller's.
  AdvanceResult integrate(std::int64_t steps);

  Model model_;
  State initial_;
  State state_;
  Integrator integrator_;
  AppliedWrench input_;
  double dt_;
  std::int64_t max_substeps_;
  std::int64_t clock_steps_ = 0;
  std::int64_t dropped_steps_ = 0;
  std::int64_t anchor_steps_ = 0;  // grid points counted before the last reanchor
  double anchor_elapsed_ = 0.0;    // elapsed time of the last reanchor [s]
  double max_energy_growth_ = std::numeric_limits<double>::infinity();
  bool paused_ = false;
  std::int64_t integrated_steps_ = 0;
  Divergence divergence_ = Divergence::kNone;
};

}  // namespace rigid_body
