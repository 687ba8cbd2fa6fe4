#include "rigid_body_sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rigid_body_sim/kinematics.hpp"

namespace rigid_body {

namespace {
// elapsed/dt is rounded up to the next integer when it is within this relative distance of it: a ratio
// computed as 29.999999999999996 is the grid point 30, not 29.
constexpr double kGridTolerance = 1e-9;
}  // namespace

std::int64_t wholeStepsIn(double elapsed, double dt) {
  if (!(elapsed > 0.0)) return 0;
  const double ratio = elapsed / dt;
  return static_cast<std::int64_t>(std::floor(ratio * (1.0 + kGridTolerance)));
}

Simulation::Simulation(const Model& model, const State& initial, IntegratorType integrator, double dt,
                       std::int64_t max_substeps, const IntegratorSettings& settings)
    : model_(model), initial_(initial), state_(initial), integrator_(integrator, settings), dt_(dt),
      max_substeps_(max_substeps) {
  if (!std::isfinite(dt) || dt <= 0.0) throw std::invalid_argument("dt must be a finite number > 0 [s]");
  if (max_substeps < 1) throw std::invalid_argument("max_substeps must be >= 1");
  if (!isFinite(initial)) throw std::invalid_argument("the initial state must be finite");
}

const char* divergenceName(Divergence divergence) {
  switch (divergence) {
    case Divergence::kNone:
      return "none";
    case Divergence::kNonFiniteState:
      return "non-finite state";
    case Divergence::kEnergyGrowth:
      return "energy growth beyond max_energy_growth";
    case Divergence::kStepFailure:
      return "integrator step failure";
  }
  return "unknown";
}

std::int64_t Simulation::clockStepsAt(double elapsed) const {
  return anchor_steps_ + wholeStepsIn(elapsed - anchor_elapsed_, dt_);
}

AdvanceResult Simulation::advanceTo(double elapsed) { return advanceToStep(clockStepsAt(elapsed)); }

AdvanceResult Simulation::advanceToStep(std::int64_t target) {
  AdvanceResult result;
  const std::int64_t due = target - clock_steps_;
  if (due <= 0) return result;
  clock_steps_ += due;
  if (divergence_ != Divergence::kNone || paused_) return result;  // the clock runs, the state holds
  const std::int64_t steps = std::min(due, max_substeps_);
  result.dropped = due - steps;
  dropped_steps_ += result.dropped;
  const AdvanceResult integrated = integrate(steps);
  result.steps = integrated.steps;
  result.status = integrated.status;
  result.diverged = integrated.diverged;
  return result;
}

AdvanceResult Simulation::stepNow(std::int64_t steps) {
  if (divergence_ != Divergence::kNone || steps <= 0) return AdvanceResult();
  return integrate(steps);
}

AdvanceResult Simulation::integrate(std::int64_t steps) {
  AdvanceResult result;
  const State before = state_;
  for (std::int64_t k = 0; k < steps; ++k) {
    result.status = integrator_.step(model_, input_, dt_, state_);
    if (result.status != StepStatus::kOk) break;
    ++result.steps;
  }
  integrated_steps_ += result.steps;
  if (result.status == StepStatus::kNonFinite || result.status == StepStatus::kNotConverged) {
    divergence_ = result.status == StepStatus::kNonFinite ? Divergence::kNonFiniteState : Divergence::kStepFailure;
  } else if (std::isfinite(max_energy_growth_) && input_.isZero()) {
    // With no commanded wrench the mechanical energy E = T + V cannot grow (damping only removes it). A
    // method's error may move it in proportion to the energy in play: E itself and the work of gravity
    // W = M g·Δx over the call (explicit Euler under gravity gains O(h) of W). A growth beyond
    // (max_energy_growth − 1) times that budget is a blow-up. All terms scale with the body: no absolute floor.
    const double kinetic_before = kineticEnergy(model_.mass, before);
    const double gravity_work = model_.mass.mass() * model_.forces.gravity_W.dot(state_.p_WB - before.p_WB);
    const double growth = kineticEnergy(model_.mass, state_) - gravity_work - kinetic_before;
    const double budget = (max_energy_growth_ - 1.0) * (kinetic_before + std::abs(gravity_work));
    if (!(growth <= budget * (1.0 + 1e-9))) divergence_ = Divergence::kEnergyGrowth;
  }
  if (divergence_ != Divergence::kNone) {
    state_ = before;  // the last good state: the one before the call that diverged
    result.diverged = true;
  }
  return result;
}

void Simulation::rewindClock() {
  clock_steps_ = 0;
  anchor_steps_ = 0;
  anchor_elapsed_ = 0.0;
}

void Simulation::reanchor(double elapsed) {
  anchor_steps_ = clock_steps_;
  anchor_elapsed_ = elapsed;
}

void Simulation::reset() {
  state_ = initial_;
  clearInput();
  divergence_ = Divergence::kNone;
}

bool Simulation::setState(const State& state) {
  if (!isFinite(state)) return false;
  state_ = state;
  return true;
}

}  // namespace rigid_body
