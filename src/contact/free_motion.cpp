// Step 1 of the contact step (docs/contact.md): the colliding bodies' free motion, each body by its own
// integrator as if nothing touched it, spread over the pool; in the scene's four-body batches where its
// integrator has a lane kernel (a body's step is the same bits alone or in a batch, as for the free bodies).
#include <limits>

#include "contact_step.hpp"
#include "integrators/batch_stepper.hpp"
#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

namespace {

// A colliding body's free step is one step, where a free body's block covers a whole tick of them: so many
// of the scene's blocks of bodies make one block of free steps, enough work to be worth a hand-out.
constexpr std::size_t kFreeStepBlocks = 8;

constexpr std::size_t kNoCollider = std::numeric_limits<std::size_t>::max();

}  // namespace

void ContactStep::stepFreeMotion(SceneBodies& bodies, const std::vector<char>& running, double h,
                                 std::vector<StepStatus>& failed) {
  if (bodies.batches != nullptr) return stepFreeMotionInBatches(bodies, running, h, failed);
  const std::size_t per_block = scaledBlock(bodies_per_block_, kFreeStepBlocks);
  forEachRange(pool_, colliders_.size(), per_block, [&](std::size_t, std::size_t first, std::size_t end) {
    for (std::size_t k = first; k < end; ++k) {
      const std::size_t body = colliders_[k];
      start_[k] = bodies.states[body];
      if (!running[k]) continue;
      const StepStatus status = bodies.integrators[body].step(bodies.models[body], bodies.terms[body],
                                                              bodies.inputs[body], h, bodies.states[body]);
      if (status != StepStatus::kOk) {
        failed[k] = status;
        bodies.states[body] = start_[k];
      }
    }
    placeRange(bodies.states, first, end);  // each object is its own body's: placed in the same block
  });
}

// The batches take the scene's bodies in their kind order (so that one kind's bodies share a batch), not in
// the colliders' order: the blocks are ranges of that order, each admitting the running colliders in it.
void ContactStep::stepFreeMotionInBatches(SceneBodies& bodies, const std::vector<char>& running, double h,
                                          std::vector<StepStatus>& failed) {
  const std::size_t n = colliders_.size();
  batched_steps_.resize(n, 0);  // zero between ticks (countBatchedSteps), so a scene edit shifts none
  collider_of_.assign(bodies.states.size(), kNoCollider);
  for (std::size_t k = 0; k < n; ++k) {
    collider_of_[colliders_[k]] = k;
    if (running[k]) continue;
    start_[k] = bodies.states[colliders_[k]];
    placeRange(bodies.states, k, k + 1);
  }
  const integrators::BatchStepper::Bodies arrays{bodies.models, bodies.terms, bodies.inputs, bodies.states};
  const auto admit = [&](std::size_t body) {
    const std::size_t k = collider_of_[body];
    return k != kNoCollider && running[k] != 0;
  };
  // A refused step's lane holds what the step gave (non-finite): the body goes back to its state before the
  // step, as Integrator::step leaves it. Left there, the step's finiteness check refused the whole contact
  // step and every pair lost its warm start.
  const auto finish = [&](std::size_t body, const State& before, std::int64_t done, StepStatus status) {
    const std::size_t k = collider_of_[body];
    start_[k] = before;
    batched_steps_[k] += static_cast<std::uint64_t>(done);
    if (status != StepStatus::kOk) {
      failed[k] = status;
      bodies.states[body] = before;
    }
    placeRange(bodies.states, k, k + 1);
  };
  const std::size_t per_block = scaledBlock(bodies_per_block_, kFreeStepBlocks);
  forEachRange(pool_, bodies.states.size(), per_block, [&](std::size_t, std::size_t first, std::size_t end) {
    bodies.batches->step(arrays, first, end, h, 1, admit, finish);
  });
}

void ContactStep::countBatchedSteps(std::vector<Integrator>& integrators) {
  for (std::size_t k = 0; k < batched_steps_.size() && k < colliders_.size(); ++k) {
    if (batched_steps_[k] != 0) integrators[colliders_[k]].countSteps(batched_steps_[k]);
  }
  batched_steps_.assign(batched_steps_.size(), 0);
}

}  // namespace contact
}  // namespace rigid_body
