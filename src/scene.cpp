#include "rigid_body_sim/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "contact/contact_step.hpp"
#include "integrators/batch_stepper.hpp"
#include "rigid_body_sim/kinematics.hpp"

namespace rigid_body {

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

Scene::Scene(const std::vector<BodyDefinition>& bodies, IntegratorType integrator, double dt,
             const IntegratorSettings& settings, StepAssembly assembly, const ContactSetup& contact)
    : integrator_type_(integrator),
      settings_(settings),
      assembly_(assembly),
      dt_(dt),
      wide_lanes_(integrators::BatchStepper::wideInstructionsAvailable()) {
  if (!std::isfinite(dt) || dt <= 0.0) throw std::invalid_argument("dt must be a finite number > 0 [s]");
  if (bodies.empty()) throw std::invalid_argument("a scene needs at least one body");
  for (const BodyDefinition& body : bodies) {
    if (!isFinite(body.initial)) throw std::invalid_argument("the initial state must be finite");
    models_.push_back(body.model);
    states_.push_back(body.initial);
    records_.push_back(BodyRecord{body.initial, body.takes_input});
  }
  contact_setup_ = contact;  // kept for edits of the body list (scene_edits.cpp)
  if (contact.active()) {
    if (contact.bodies.size() != bodies.size()) throw std::invalid_argument("contact: one entry per body is needed");
    adoptContactStep(contactStepFor(contact.bodies, states_));
    // The start-up check of every body against every other and the environment (contactStepFor leaves it out).
    contact_->start(states_);
  } else {
    contact_setup_.bodies.assign(bodies.size(), std::nullopt);
    collider_of_.assign(bodies.size(), kNoCollider);
  }
  terms_.resize(bodies.size());
  for (std::size_t body = 0; body < bodies.size(); ++body) assemble(body);
  inputs_.assign(bodies.size(), AppliedWrench());
  integrators_.assign(bodies.size(), Integrator(integrator, settings));
  pool_ = std::make_unique<ThreadPool>(1);
  if (integrators::BatchStepper::handles(integrator)) batches_ = std::make_unique<integrators::BatchStepper>(integrator);
}

void Scene::setThreads(std::size_t threads, std::size_t bodies_per_block) {
  bodies_per_block_ = std::max<std::size_t>(1, bodies_per_block);
  const std::size_t resolved = ThreadPool::resolve(threads);
  if (resolved != pool_->threads()) pool_ = std::make_unique<ThreadPool>(resolved);
}

bool Scene::setWideLanes(bool on) {
  wide_lanes_ = on && integrators::BatchStepper::wideInstructionsAvailable();
  if (batches_) batches_->setWideInstructions(wide_lanes_);
  if (contact_) contact_->setWideLanes(wide_lanes_);
  return wide_lanes_;
}

Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

void Scene::assemble(std::size_t body) {
  if (batches_) batches_->markKindsStale();
  if (assembly_ == StepAssembly::kGeneral) {
    terms_[body] = StepTerms::all();
    return;
  }
  // A contact off the centre of mass makes a torque: a colliding body can always come to spin, and then
  // turns by its full inertia and angular damping (turning on `rotation` alone after the assembly left a
  // body at rest with ω = L/I₀ and no angular damping: a box tipping over an edge crept 1.5 mm along the
  // ground in 0.11 s, at any step size).
  terms_[body] = assembleTerms(models_[body].mass, models_[body].forces, states_[body], records_[body].takes_input,
                               collides(body));
}

void Scene::setRecordContacts(bool record) {
  record_contacts_ = record;
  if (contact_) contact_->setRecording(record);
}

const std::vector<Contact>& Scene::contacts(std::size_t body) const {
  static const std::vector<Contact> kNone;
  return collides(body) ? contact_->contacts(collider_of_[body]) : kNone;
}

ContactStatistics Scene::contactStatistics() const {
  return contact_ ? contact_->statistics() : ContactStatistics();
}

const std::vector<ImpactEvent>& Scene::impacts() const {
  static const std::vector<ImpactEvent> kNone;
  return contact_ ? contact_->impacts() : kNone;
}

void Scene::setInput(std::size_t body, const AppliedWrench& input) {
  if (!records_[body].takes_input && !input.isZero()) {
    throw std::invalid_argument("body " + std::to_string(body) + " takes no wrench input");
  }
  // A sleeping body under a new wrench wakes with its island (docs/contact.md, "Sleeping").
  if (collides(body) && !(input == inputs_[body])) contact_->wake(collider_of_[body]);
  inputs_[body] = input;
}

std::size_t Scene::firstDiverged() const {
  std::size_t body = 0;
  while (body < records_.size() && records_[body].divergence == Divergence::kNone) ++body;
  return body;
}

std::size_t Scene::runningBodies() const {
  return static_cast<std::size_t>(std::count_if(records_.begin(), records_.end(), [](const BodyRecord& record) {
    return record.divergence == Divergence::kNone;
  }));
}

std::size_t Scene::collidingBodies() const { return contact_ ? contact_->colliders().size() : 0; }

SceneStepResult Scene::step(std::int64_t steps) {
  SceneStepResult result;
  if (steps <= 0) return result;
  const std::size_t bodies = states_.size();
  const std::size_t per_block = bodies_per_block_;
  const std::size_t blocks = (bodies + per_block - 1) / per_block;
  if (batches_) batches_->prepare(models_, terms_);
  if (pool_->threads() > 1 && blocks > 1) {
    // Every block reports into its own slot; merged in block order, the result is the one-thread result.
    block_results_.assign(blocks, SceneStepResult());
    pool_->parallelFor(blocks, [&](std::size_t block) {
      stepBodies(block * per_block, std::min(bodies, (block + 1) * per_block), steps, block_results_[block]);
    });
    for (const SceneStepResult& block : block_results_) merge(block, result);
  } else {
    stepBodies(0, bodies, steps, result);
  }
  if (contact_) stepColliders(steps, result);
  return result;
}

void Scene::stepBodies(std::size_t begin, std::size_t end, std::int64_t steps, SceneStepResult& result) {
  if (batches_) {
    stepBodiesInBatches(begin, end, steps, result);
    return;
  }
  for (std::size_t body = begin; body < end; ++body) {
    if (records_[body].divergence != Divergence::kNone) continue;  // it holds its last good state until reset
    if (collides(body)) continue;                                   // stepped with the contact below
    StepStatus status = StepStatus::kOk;
    const std::int64_t done = stepBody(body, steps, status);
    mergeBody(body, done, status, result);
  }
}

void Scene::merge(const SceneStepResult& part, SceneStepResult& result) {
  result.steps = std::max(result.steps, part.steps);
  if (result.status == StepStatus::kOk) result.status = part.status;  // the first failure stays
  result.diverged = result.diverged || part.diverged;
}

void Scene::mergeBody(std::size_t body, std::int64_t done, StepStatus status, SceneStepResult& result) const {
  merge({done, status, records_[body].divergence != Divergence::kNone}, result);
}

void Scene::stepBodiesInBatches(std::size_t begin, std::size_t end, std::int64_t steps, SceneStepResult& result) {
  const integrators::BatchStepper::Bodies bodies{models_, terms_, inputs_, states_};
  batches_->step(
      bodies, begin, end, dt_, steps,
      [&](std::size_t body) { return records_[body].divergence == Divergence::kNone && !collides(body); },
      [&](std::size_t body, const State& before, std::int64_t done, StepStatus status) {
        integrators_[body].countSteps(static_cast<std::uint64_t>(done));
        finishBody(body, before, done, status);
        mergeBody(body, done, status, result);
      });
}

void Scene::stepColliders(std::int64_t steps, SceneStepResult& result) {
  const std::vector<std::size_t>& colliders = contact_->colliders();
  contact::SceneBodies arrays{models_, terms_, states_, inputs_, integrators_, batches_.get()};
  std::int64_t done = 0;
  for (; done < steps; ++done) {
    bool any = false;
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      collider_running_[k] = records_[colliders[k]].divergence == Divergence::kNone;
      any = any || collider_running_[k];
    }
    if (!any) break;
    std::fill(collider_failed_.begin(), collider_failed_.end(), StepStatus::kOk);
    contact_->step(arrays, collider_running_, dt_, collider_failed_, pool_.get(), bodies_per_block_);
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      BodyRecord& record = records_[colliders[k]];
      if (!collider_running_[k]) continue;
      const StepStatus status = collider_failed_[k];
      if (status == StepStatus::kOk) {
        ++record.integrated_steps;
        continue;
      }
      if (result.status == StepStatus::kOk) result.status = status;
      if (status == StepStatus::kNonFinite || status == StepStatus::kNotConverged) {
        record.divergence = status == StepStatus::kNonFinite ? Divergence::kNonFiniteState : Divergence::kStepFailure;
        result.diverged = true;
      }
    }
  }
  contact_->countBatchedSteps(integrators_);
  result.steps = std::max(result.steps, done);
}

std::int64_t Scene::stepBody(std::size_t body, std::int64_t steps, StepStatus& status) {
  const Model& model = models_[body];
  const StepTerms& terms = terms_[body];
  State& state = states_[body];
  const AppliedWrench& input = inputs_[body];
  Integrator& integrator = integrators_[body];
  const State before = state;
  std::int64_t done = 0;
  for (; done < steps; ++done) {
    status = integrator.step(model, terms, input, dt_, state);
    if (status != StepStatus::kOk) break;
  }
  finishBody(body, before, done, status);
  return done;
}

void Scene::finishBody(std::size_t body, const State& before, std::int64_t done, StepStatus status) {
  const Model& model = models_[body];
  const AppliedWrench& input = inputs_[body];
  State& state = states_[body];
  BodyRecord& record = records_[body];
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
}

void Scene::reset() {
  for (std::size_t body = 0; body < states_.size(); ++body) {
    states_[body] = records_[body].initial;
    records_[body].divergence = Divergence::kNone;
    assemble(body);
  }
  std::fill(inputs_.begin(), inputs_.end(), AppliedWrench());
  // dopri5's memory restarts by itself from a state it did not return; a fresh integrator says so plainly.
  integrators_.assign(states_.size(), Integrator(integrator_type_, settings_));
  if (contact_) contact_->restart(states_);
}

void Scene::setForceModel(std::size_t body, const ForceModel& forces) {
  models_[body].forces = forces;
  assemble(body);
  if (collides(body)) contact_->wake(collider_of_[body]);
}

std::string Scene::placementConflict(std::size_t body, const State& state) {
  if (!collides(body)) return "";
  return contact_->placementConflict(collider_of_[body], state, states_, "would be inside");
}

bool Scene::setState(std::size_t body, const State& state) {
  if (!isFinite(state)) return false;
  states_[body] = state;
  assemble(body);
  if (collides(body)) contact_->restart(states_);
  return true;
}

}  // namespace rigid_body
