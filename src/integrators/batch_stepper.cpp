// A scene's batches: the bodies sorted by kind, loaded into lanes, stepped by the lane loop and stored back.
#include "batch_stepper.hpp"

#include <algorithm>
#include <numeric>

#include "lane_dispatch.hpp"

namespace rigid_body {
namespace integrators {

static_assert(BatchStepper::kBatchSize == kLanes, "a batch is one body per lane");

namespace {
// `count` bodies into the lanes of T (double: one body), stepped, and back.
template <class T>
void stepInLanes(bool wide, IntegratorType type, const BatchStepper::Bodies& bodies, const std::size_t* members,
                 std::size_t count, double h, std::int64_t steps, std::int64_t* done, bool* running) {
  constexpr std::size_t lanes = kLaneCount<T>;
  LaneBody<T> constants;
  LaneState<T> y;
  const StepTerms& terms = bodies.terms[members[0]];
  for (std::size_t i = 0; i < lanes; ++i) {  // unused lanes repeat the last body; their results are dropped
    const std::size_t body = members[std::min(i, count - 1)];
    loadBody(constants, i, type, terms, bodies.models[body], bodies.inputs[body]);
    loadState(y, i, bodies.states[body]);
  }
  for (std::size_t i = count; i < lanes; ++i) constants.mass[i] = nullptr;
  if constexpr (lanes == 1) {
    stepLone(wide, type, constants, terms, h, steps, y, done, running);
  } else {
    stepBatch(wide, type, constants, terms, h, steps, count, y, done, running);
  }
  for (std::size_t i = 0; i < count; ++i) storeState(y, i, bodies.states[members[i]]);
}
}  // namespace

BatchStepper::BatchStepper(IntegratorType type) : type_(type), wide_(wideLanesAvailable()) {}

bool BatchStepper::wideInstructionsAvailable() { return wideLanesAvailable(); }

bool BatchStepper::setWideInstructions(bool on) {
  wide_ = on && wideLanesAvailable();
  return wide_;
}

void BatchStepper::prepare(const std::vector<Model>& models, const std::vector<StepTerms>& terms) {
  if (!kinds_stale_ && order_.size() == models.size()) return;
  // The key orders only; step() compares the terms themselves, so a key that missed a term would cost
  // batches, never mix kinds in one.
  std::vector<unsigned> key(models.size());
  turn_kind_.resize(models.size());
  for (std::size_t body = 0; body < key.size(); ++body) {
    const StepTerms& t = terms[body];
    const SemiImplicitTurn turn = semiImplicitTurnKind(type_, models[body].mass);
    turn_kind_[body] = static_cast<unsigned char>(turn);
    unsigned k = static_cast<unsigned>(turn);
    for (const bool term : {t.input, t.gravity, t.linear_damping, t.angular_damping, t.rotation, t.world_inertia}) {
      k = 2 * k + (term ? 1 : 0);
    }
    key[body] = k;
  }
  order_.resize(models.size());
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  kinds_stale_ = false;
}

void BatchStepper::stepBatch(const Bodies& bodies, const std::size_t* members, std::size_t count, double h,
                             std::int64_t steps, std::int64_t* done, bool* running) const {
  if (count == 1) {
    stepInLanes<double>(wide_, type_, bodies, members, 1, h, steps, done, running);
  } else {
    stepInLanes<Lanes>(wide_, type_, bodies, members, count, h, steps, done, running);
  }
}

}  // namespace integrators
}  // namespace rigid_body
