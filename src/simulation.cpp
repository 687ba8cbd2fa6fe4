#include "rigid_body_sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

AdvanceResult Simulation::advanceTo(double elapsed) {
  AdvanceResult result;
  const std::int64_t due = wholeStepsIn(elapsed, dt_) - clock_steps_;
  if (due <= 0) return result;
  const std::int64_t steps = std::min(due, max_substeps_);
  result.dropped = due - steps;
  dropped_steps_ += result.dropped;
  clock_steps_ += due;
  for (std::int64_t k = 0; k < steps; ++k) {
    result.status = integrator_.step(model_, input_, dt_, state_);
    if (result.status != StepStatus::kOk) break;
    ++result.steps;
  }
  return result;
}

void Simulation::reset() {
  state_ = initial_;
  clearInput();
}

bool Simulation::setState(const State& state) {
  if (!isFinite(state)) return false;
  state_ = state;
  return true;
}

}  // namespace rigid_body
