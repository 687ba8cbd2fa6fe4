// Edits of a scene's body list between steps (scene.hpp, "edits"): a body appended or removed while the
// others keep their arrays' entries. The free step reads nothing across bodies, so an edit changes no other
// free body's arithmetic; the contact step holds pairs by collider index, so it is rebuilt for the new list.
#include <stdexcept>
#include <string>
#include <utility>

#include "contact/contact_step.hpp"
#include "integrators/batch_stepper.hpp"
#include "rigid_body_sim/scene.hpp"

namespace rigid_body {

std::unique_ptr<contact::ContactStep> Scene::contactStepFor(const std::vector<std::optional<CollisionShape>>& shapes,
                                                            const std::vector<State>& states) const {
  std::vector<std::size_t> colliders;
  for (std::size_t body = 0; body < shapes.size(); ++body) {
    if (shapes[body]) colliders.push_back(body);
  }
  if (colliders.empty()) return nullptr;
  validateContactSettings(contact_setup_.settings);
  for (const CollisionShape& shape : contact_setup_.environment) validateShape(shape, true);
  for (std::size_t body : colliders) validateShape(*shapes[body], false);
  return std::make_unique<contact::ContactStep>(contact_setup_.environment, contact_setup_.settings, shapes, colliders,
                                                integrator_type_, states);
}

void Scene::adoptContactStep(std::unique_ptr<contact::ContactStep> step) {
  contact_ = std::move(step);
  collider_of_.assign(states_.size(), kNoCollider);
  if (!contact_) return;
  const std::vector<std::size_t>& colliders = contact_->colliders();
  for (std::size_t k = 0; k < colliders.size(); ++k) collider_of_[colliders[k]] = k;
  collider_running_.assign(colliders.size(), 1);
  collider_failed_.assign(colliders.size(), StepStatus::kOk);
  if (record_contacts_) contact_->setRecording(true);
  contact_->setWideLanes(wide_lanes_);
}

std::size_t Scene::addBody(const BodyDefinition& body, const std::optional<CollisionShape>& shape) {
  if (!isFinite(body.initial)) throw std::invalid_argument("the initial state must be finite");
  std::unique_ptr<contact::ContactStep> step;
  if (shape) {
    // Built on copies first: a refused body leaves the scene as it was.
    std::vector<std::optional<CollisionShape>> shapes = contact_setup_.bodies;
    shapes.push_back(shape);
    std::vector<State> states = states_;
    states.push_back(body.initial);
    step = contactStepFor(shapes, states);
    step->restart(states);
    const std::string conflict =
        step->placementConflict(step->colliders().size() - 1, body.initial, states, "would be inside");
    if (!conflict.empty()) throw std::invalid_argument(conflict);
  }
  const std::size_t index = states_.size();
  models_.push_back(body.model);
  states_.push_back(body.initial);
  records_.push_back(BodyRecord{body.initial, body.takes_input});
  inputs_.push_back(AppliedWrench());
  integrators_.push_back(Integrator(integrator_type_, settings_));
  terms_.emplace_back();
  contact_setup_.bodies.push_back(shape);
  if (step) {
    adoptContactStep(std::move(step));
  } else {
    collider_of_.push_back(kNoCollider);  // a free arrival leaves the contact step as it is
  }
  assemble(index);  // also marks the batches' kind order stale
  return index;
}

void Scene::removeBody(std::size_t body) {
  if (body >= states_.size()) throw std::invalid_argument("no body " + std::to_string(body) + " to remove");
  if (states_.size() == 1) throw std::invalid_argument("a scene needs at least one body: the last one stays");
  const bool was_collider = collides(body);
  const auto at = [body](auto& array) { array.erase(array.begin() + static_cast<std::ptrdiff_t>(body)); };
  at(models_);
  at(terms_);
  at(states_);
  at(inputs_);
  at(integrators_);
  at(records_);
  at(contact_setup_.bodies);
  if (batches_) batches_->markKindsStale();
  if (!was_collider) {
    // The contact step keeps its memory: only the scene indices of the colliders after the body move down.
    at(collider_of_);
    if (contact_) contact_->renumberAfterRemoval(body);
    return;
  }
  std::unique_ptr<contact::ContactStep> step = contactStepFor(contact_setup_.bodies, states_);
  if (step) step->restart(states_);
  adoptContactStep(std::move(step));
}

}  // namespace rigid_body
