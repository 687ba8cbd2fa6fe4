#include "rigid_body_sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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
                       std::int64_t max_substeps, const IntegratorSettings& settings, StepAssembly assembly)
    : Simulation(std::vector<BodyDefinition>{BodyDefinition{model, initial, true}}, integrator, dt, max_substeps,
                 settings, assembly) {}

Simulation::Simulation(const std::vector<BodyDefinition>& bodies, IntegratorType integrator, double dt,
                       std::int64_t max_substeps, const IntegratorSettings& settings, StepAssembly assembly)
    : assembly_(assembly), dt_(dt), max_substeps_(max_substeps) {
  if (!std::isfinite(dt) || dt <= 0.0) throw std::invalid_argument("dt must be a finite number > 0 [s]");
  if (max_substeps < 1) throw std::invalid_argument("max_substeps must be >= 1");
  if (bodies.empty()) throw std::invalid_argument("a scene needs at least one body");
  models_.reserve(bodies.size());
  states_.reserve(bodies.size());
  for (const BodyDefinition& body : bodies) {
    if (!isFinite(body.initial)) throw std::invalid_argument("the initial state must be finite");
    models_.push_back(body.model);
    states_.push_back(body.initial);
    bodies_.push_back(BodyRecord{body.initial, body.takes_input});
    assemble(bodies_.size() - 1);
  }
  inputs_.assign(bodies.size(), AppliedWrench());
  integrators_.assign(bodies.size(), Integrator(integrator, settings));
}

void Simulation::assemble(std::size_t body) {
  Model& model = models_[body];
  model.terms = assembly_ == StepAssembly::kGeneral
                    ? StepTerms::all()
                    : assembleTerms(model.mass, model.forces, states_[body], bodies_[body].takes_input);
}

void Simulation::setInput(std::size_t body, const AppliedWrench& input) {
  if (!bodies_[body].takes_input && !input.isZero()) {
    throw std::invalid_argument("body " + std::to_string(body) + " takes no wrench input");
  }
  inputs_[body] = input;
}

void Simulation::clearInput() { std::fill(inputs_.begin(), inputs_.end(), AppliedWrench()); }

bool Simulation::anyDiverged() const {
  return std::any_of(bodies_.begin(), bodies_.end(),
                     [](const BodyRecord& body) { return body.divergence != Divergence::kNone; });
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
  if (paused_) return result;  // the clock runs, the states hold
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
  if (steps <= 0) return AdvanceResult();
  return integrate(steps);
}

AdvanceResult Simulation::integrate(std::int64_t steps) {
  AdvanceResult result;
  for (std::size_t body = 0; body < states_.size(); ++body) {
    if (bodies_[body].divergence != Divergence::kNone) continue;  // it holds its last good state until reset
    StepStatus status = StepStatus::kOk;
    result.steps = std::max(result.steps, integrateBody(body, steps, status));
    if (status != StepStatus::kOk && result.status == StepStatus::kOk) result.status = status;
    result.diverged = result.diverged || bodies_[body].divergence != Divergence::kNone;
  }
  return result;
}

std::int64_t Simulation::integrateBody(std::size_t body, std::int64_t steps, StepStatus& status) {
  const Model& model = models_[body];
  State& state = states_[body];
  const AppliedWrench& input = inputs_[body];
  Integrator& integrator = integrators_[body];
  BodyRecord& record = bodies_[body];
  const State before = state;
  std::int64_t done = 0;
  for (; done < steps; ++done) {
    status = integrator.step(model, input, dt_, state);
    if (status != StepStatus::kOk) break;
  }
  record.integrated_steps += done;
  if (status == StepStatus::kNonFinite || status == StepStatus::kNotConverged) {
    record.divergence = status == StepStatus::kNonFinite ? Divergence::kNonFiniteState : Divergence::kStepFailure;
  } else if (std::isfinite(max_energy_growth_) && input.isZero()) {
    // With no commanded wrench the mechanical energy E = T + V cannot grow (damping only removes it). A
    // method's error may move it in proportion to the energy in play: E itself and the work of gravity
    // W = M g·Δx over the call (explicit Euler under gravity gains O(h) of W). A growth beyond
    // (max_energy_growth − 1) times that budget is a blow-up. All terms scale with the body: no absolute floor.
    const double kinetic_before = kineticEnergy(model.mass, before);
    const double gravity_work = model.mass.mass() * model.forces.gravity_W.dot(state.p_WB - before.p_WB);
    const double growth = kineticEnergy(model.mass, state) - gravity_work - kinetic_before;
    const double budget = (max_energy_growth_ - 1.0) * (kinetic_before + std::abs(gravity_work));
    if (!(growth <= budget * (1.0 + 1e-9))) record.divergence = Divergence::kEnergyGrowth;
  }
  if (record.divergence != Divergence::kNone) state = before;  // the last good state: before the call that diverged
  return done;
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
  for (std::size_t body = 0; body < states_.size(); ++body) {
    states_[body] = bodies_[body].initial;
    bodies_[body].divergence = Divergence::kNone;
    assemble(body);
  }
  clearInput();
}

bool Simulation::setState(std::size_t body, const State& state) {
  if (!isFinite(state)) return false;
  states_[body] = state;
  assemble(body);
  return true;
}

}  // namespace rigid_body
