// The step of a scene's independent bodies under a method with a lane kernel (explicit Euler, semi-implicit
// Euler, rk4: IntegratorInfo::lane_kernel): bodies of one kind go four at a time into a batch, one body per
// lane; a body without a batch to share steps alone by the same kernel. Which bodies share a batch changes
// nothing in any body's arithmetic (the lanes round as one body alone does), so the scene's results do not
// depend on the grouping, the order of the body list or the thread count. The words (lane, batch, lone,
// wide, kind): docs/architecture.md. Internal to the core: Scene holds one and includes no lane code.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <vector>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {
namespace integrators {

class BatchStepper {
 public:
  /// The bodies a batch holds at most: one per lane.
  static constexpr std::size_t kBatchSize = 4;

  /// The scene's arrays, one entry per body, as the batches read and write them.
  struct Bodies {
    const std::vector<Model>& models;
    const std::vector<StepTerms>& terms;
    const std::vector<AppliedWrench>& inputs;
    std::vector<State>& states;
  };

  /// For a method with a lane kernel (handles(type)); wide instructions on where the CPU has AVX.
  explicit BatchStepper(IntegratorType type);
  static bool handles(IntegratorType type) { return integratorInfo(type).lane_kernel; }

  /// Whether batches run as 256-bit (AVX) operations and a lone body in AVX-512's instructions, where the
  /// CPU has them; off, both run in the build's baseline instructions. The same bits either way. Returns the
  /// setting taken.
  bool setWideInstructions(bool on);
  /// Whether this CPU runs the wide instructions (AVX): checked once.
  static bool wideInstructionsAvailable();
  bool wideInstructions() const { return wide_; }

  /// A body's terms or model changed: the kinds are taken again by the next prepare().
  void markKindsStale() { kinds_stale_ = true; }
  /// Sorts the bodies by kind if a kind may have changed. From one thread, before step().
  void prepare(const std::vector<Model>& models, const std::vector<StepTerms>& terms);

  /// `steps` steps of h for the bodies at positions [begin, end) of the kind order that admit(body) lets
  /// in, in batches of one kind; then finish(body, state before, steps done, status) for each, where a body
  /// whose step was refused (Integrator::step's rule) holds the state before that step and reports
  /// kNonFinite. Positions, not indices: the blocks of a threaded step split the kind order.
  template <class Admit, class Finish>
  void step(const Bodies& bodies, std::size_t begin, std::size_t end, double h, std::int64_t steps, Admit&& admit,
            Finish&& finish) const;

 private:
  // `count` ≤ kBatchSize bodies of one kind, `steps` steps each: done[i] steps taken, running[i] false if a
  // step was refused. Writes their states.
  void stepBatch(const Bodies& bodies, const std::size_t* members, std::size_t count, double h, std::int64_t steps,
                 std::int64_t* done, bool* running) const;
  // The batch's states before its steps, in storage left unconstructed: State's default constructor would
  // write four states per batch only for them to be overwritten, which took a measurable share of a
  // swarm's step (docs/performance_log.md#batch-stepper). Each is copy-constructed in place; State is
  // trivially destructible, so nothing is destroyed.
  union StatesBefore {
    StatesBefore() {}
    State states[kBatchSize];
  };
  static_assert(std::is_trivially_destructible<State>::value, "StatesBefore destroys nothing");
  bool sameKind(const Bodies& bodies, std::size_t a, std::size_t b) const {
    return turn_kind_[a] == turn_kind_[b] && bodies.terms[a] == bodies.terms[b];
  }

  IntegratorType type_;
  bool wide_;
  bool kinds_stale_ = true;
  // The order in which the bodies are taken: by kind (step terms, semi-implicit Euler's rotation branch),
  // stable, so that a kind's bodies are neighbours and fill batches whatever the order of the body list.
  std::vector<std::size_t> order_;
  std::vector<unsigned char> turn_kind_;  // per body: semi-implicit Euler's rotation branch
};

template <class Admit, class Finish>
void BatchStepper::step(const Bodies& bodies, std::size_t begin, std::size_t end, double h, std::int64_t steps,
                        Admit&& admit, Finish&& finish) const {
  std::array<std::size_t, kBatchSize> members;
  std::size_t count = 0;
  const auto run = [&] {
    if (count == 0) return;
    StatesBefore before;
    for (std::size_t i = 0; i < count; ++i) new (&before.states[i]) State(bodies.states[members[i]]);
    std::array<std::int64_t, kBatchSize> done;
    std::array<bool, kBatchSize> running;
    stepBatch(bodies, members.data(), count, h, steps, done.data(), running.data());
    for (std::size_t i = 0; i < count; ++i) {
      finish(members[i], before.states[i], done[i], running[i] ? StepStatus::kOk : StepStatus::kNonFinite);
    }
    count = 0;
  };
  for (std::size_t position = begin; position < end; ++position) {
    const std::size_t body = order_[position];
    if (!admit(body)) continue;
    if (count > 0 && !sameKind(bodies, members[0], body)) run();
    members[count++] = body;
    if (count == kBatchSize) run();
  }
  run();
}

}  // namespace integrators
}  // namespace rigid_body
