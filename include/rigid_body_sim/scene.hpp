// The bodies of a scene and their step: constant models, mutable states, inputs and integrators, kept as
// contiguous arrays one per field, stepped together. No clock here: World owns time (world.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/contact.hpp"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"
#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {

namespace contact {
class ContactStep;
}
namespace integrators {
class BatchStepper;
}

/// Why a body stopped integrating; kNone while it runs.
enum class Divergence {
  kNone,
  kNonFiniteState,  ///< a step produced NaN or Inf (e.g. a momentum that overflowed)
  kEnergyGrowth,    ///< the energy grew by more than max_energy_growth in one call with nothing to explain it
  kStepFailure,     ///< the integrator gave up (implicit solve or step-size control)
};

const char* divergenceName(Divergence divergence);

/// One body as a scene declares it.
struct BodyDefinition {
  Model model;               ///< mass properties (constant) and force models (changed only by setForceModel)
  State initial;             ///< the state at start-up and after reset
  bool takes_input = true;   ///< the body has a wrench input (false: no input term, setInput refuses a wrench)
};

/// How a Scene sets each body's StepTerms.
enum class StepAssembly {
  kLeaveOut,  ///< assembleTerms: only the terms the scene declares (the default, and the node's)
  kGeneral,   ///< every term (StepTerms::all()), the reference the specialised steps are tested against
};

/// What one Scene::step did.
struct SceneStepResult {
  std::int64_t steps = 0;               ///< steps integrated (by the bodies still running)
  StepStatus status = StepStatus::kOk;  ///< kNonFinite if a body's step failed; it keeps its last good state
  bool diverged = false;                ///< this call latched some body's divergence
};

/// Bodies sharing one integrator method and dt. A body without a collision shape is independent: it steps
/// with its own model, terms, input and integrator memory, body by body over contiguous arrays: no
/// allocation, no virtual call, a cost linear in the bodies. The colliding bodies step together, one step
/// at a time, with the contact step between them (docs/contact.md); a scene without colliders has no
/// contact step at all (the same trajectory, bit for bit, and the same cost as without contact). A body whose step fails or whose energy grows
/// beyond the guard latches its own divergence and holds its last good state; the others go on.
/// Accessors without a body index mean body 0 (the one-body shorthand).
class Scene {
 public:
  /// Throws std::invalid_argument for no bodies, a non-finite initial state or a dt that is not > 0.
  /// With contact: throws std::invalid_argument for invalid shapes or settings, or a body that starts inside
  /// another or the environment (the message names both).
  Scene(const std::vector<BodyDefinition>& bodies, IntegratorType integrator, double dt,
        const IntegratorSettings& settings = IntegratorSettings(), StepAssembly assembly = StepAssembly::kLeaveOut,
        const ContactSetup& contact = ContactSetup());
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  /// The divergence guard: when no wrench is commanded, the mechanical energy E = T + V may not grow by more
  /// than this factor (> 1) within one step() call; physics allows no growth at all then (damping only
  /// removes energy), so a larger growth is a numerical blow-up. Infinity disables the check.
  void setMaxEnergyGrowth(double factor) { max_energy_growth_ = factor; }

  /// Integrates `steps` ≥ 0 steps of dt for every running body, under the inputs as they stand.
  SceneStepResult step(std::int64_t steps);

  /// Threads that step the independent bodies, the calling one included (0: as many as the machine has;
  /// 1, the default: the caller alone). Bodies go to the threads in blocks of `bodies_per_block` (≥ 1), so a
  /// scene of no more bodies runs on the caller whatever this says. Every body's arithmetic is the same on
  /// any thread and in any block: the trajectories do not depend on either (tested bit for bit). The
  /// colliding bodies' free steps go to the threads in blocks of the same size, and their contact solve in
  /// blocks of islands; the rest of the contact step runs on the caller.
  void setThreads(std::size_t threads, std::size_t bodies_per_block = kBodiesPerBlock);
  std::size_t threads() const { return pool_->threads(); }
  /// A block of 64 bodies is enough rk4 work per step to pay for handing it to another thread
  /// (docs/performance_log.md#block-size).
  static constexpr std::size_t kBodiesPerBlock = 64;

  std::size_t bodyCount() const { return states_.size(); }
  double dt() const { return dt_; }
  IntegratorType integratorType() const { return integrators_.front().type(); }

  /// Replaces a body's input from the next step on. Throws std::invalid_argument for a non-zero wrench on a
  /// body without input (its step has no input term to carry it).
  void setInput(std::size_t body, const AppliedWrench& input);
  const AppliedWrench& input(std::size_t body = 0) const { return inputs_[body]; }
  bool takesInput(std::size_t body = 0) const { return records_[body].takes_input; }

  /// Every body back to its initial state (and terms) with no input, divergences cleared, integrator memory
  /// dropped.
  void reset();
  /// Replaces a body's force models (a live setting); its terms are assembled again.
  void setForceModel(std::size_t body, const ForceModel& forces);
  /// Replaces a body's state if it is finite (returns whether it was). Its terms are assembled again: a
  /// state with spin gives a body rotation it did not need before.
  bool setState(std::size_t body, const State& state);
  /// Empty if a colliding body may be set to `state`: not inside another body or the environment (deeper
  /// than the penetration slop, or inside a closed environment mesh); otherwise a message naming both.
  std::string placementConflict(std::size_t body, const State& state);

  // ----- edits of the body list (scene_edits.cpp), between steps -----
  /// Appends a body at its initial state, with `shape` as its collision shape (none: it collides with
  /// nothing), and returns its index (the last). The other bodies keep their indices, states, inputs and
  /// integrator memory: a body that does not collide steps on bit for bit as without the edit. A colliding
  /// arrival rebuilds the contact step, whose memory (touching pairs, warm starts, sleep, figures) restarts
  /// as after setState. Throws std::invalid_argument, the scene unchanged, for a non-finite state, an invalid
  /// shape, or a colliding body placed inside another body or the environment (the message names both).
  std::size_t addBody(const BodyDefinition& body, const std::optional<CollisionShape>& shape = std::nullopt);
  /// Removes a body: the later ones move down one index. Throws std::invalid_argument for a body out of
  /// range or the only one (a scene has at least one body). Removing a collider restarts the contact
  /// memory as addBody does.
  void removeBody(std::size_t body);

  const State& state(std::size_t body = 0) const { return states_[body]; }
  const Model& model(std::size_t body = 0) const { return models_[body]; }
  /// The terms a body's step evaluates: the assembled-terms query.
  const StepTerms& terms(std::size_t body = 0) const { return terms_[body]; }
  Divergence divergence(std::size_t body = 0) const { return records_[body].divergence; }
  /// The first body that has diverged, or bodyCount() when none has.
  std::size_t firstDiverged() const;
  /// Bodies still integrating (not diverged).
  std::size_t runningBodies() const;
  /// Bodies with a collision shape (stepped with the contact step).
  std::size_t collidingBodies() const;
  /// Steps a body integrated since construction (paused, dropped and diverged steps do not count).
  std::int64_t integratedSteps(std::size_t body = 0) const { return records_[body].integrated_steps; }
  /// A body's state at construction (and after every reset), for drift diagnostics.
  const State& initialState(std::size_t body = 0) const { return records_[body].initial; }

  /// Whether four-body batches and the contact solver's four lanes run as 256-bit (AVX) operations, and a
  /// body without a batch in AVX-512's instructions (where the CPU has them); on by default where the CPU
  /// has AVX.
  /// Off, both run in the build's baseline instructions (SSE2). The results are the same bits either way;
  /// returns the setting taken (on only where AVX is available).
  bool setWideLanes(bool on);
  bool wideLanes() const { return wide_lanes_; }

  /// Contact: whether the scene has a contact step, whether a body collides, and what the last step found.
  bool hasContact() const { return contact_ != nullptr; }
  bool collides(std::size_t body) const { return contact_ != nullptr && collider_of_[body] != kNoCollider; }
  /// Keeps each colliding body's contacts of the last step (off by default: nothing is gathered unasked).
  void setRecordContacts(bool record);
  /// A colliding body's contacts at the end of the last step (empty unless recording).
  const std::vector<Contact>& contacts(std::size_t body) const;
  /// Touching points of a colliding body at the end of the last step (counted while recording).
  std::size_t contactCount(std::size_t body) const { return contacts(body).size(); }
  ContactStatistics contactStatistics() const;
  /// The last impacts located in time, oldest first.
  const std::vector<ImpactEvent>& impacts() const;

 private:
  // What the step loop does not read: kept apart so the hot arrays stay dense.
  struct BodyRecord {
    State initial;
    bool takes_input = true;
    Divergence divergence = Divergence::kNone;
    std::int64_t integrated_steps = 0;
  };

  static constexpr std::size_t kNoCollider = std::numeric_limits<std::size_t>::max();

  // The independent bodies in [begin, end), each `steps` steps, their outcome merged into `result`.
  void stepBodies(std::size_t begin, std::size_t end, std::int64_t steps, SceneStepResult& result);
  // explicit_euler, semi_implicit_euler, rk4: the bodies at positions [begin, end) of the batches' kind
  // order, those of a kind four at a time (src/integrators/batch_stepper.hpp).
  void stepBodiesInBatches(std::size_t begin, std::size_t end, std::int64_t steps, SceneStepResult& result);
  // A part's outcome (a block's, a body's) into a step's result: the most steps, the first failure, any divergence.
  static void merge(const SceneStepResult& part, SceneStepResult& result);
  // A body's outcome into a step's result.
  void mergeBody(std::size_t body, std::int64_t done, StepStatus status, SceneStepResult& result) const;
  // After a body's `done` steps ending in `status`: its count, its divergence (the step's failure or the
  // energy guard) and, on divergence, its state back to `before` (the state before the call).
  void finishBody(std::size_t body, const State& before, std::int64_t done, StepStatus status);
  // One body's `steps` steps and its divergence check; returns the steps done.
  std::int64_t stepBody(std::size_t body, std::int64_t steps, StepStatus& status);
  // The colliding bodies' `steps` steps together with contact.
  void stepColliders(std::int64_t steps, SceneStepResult& result);
  void assemble(std::size_t body);
  // The contact step for the colliders among `shapes` (one per body) at `states`, started without the
  // start-up's all-pairs check; null when none collides. Throws for invalid settings or shapes.
  std::unique_ptr<contact::ContactStep> contactStepFor(const std::vector<std::optional<CollisionShape>>& shapes,
                                                       const std::vector<State>& states) const;
  // Takes `step` as the contact step of the current body list (collider_of_ and the scratch follow it).
  void adoptContactStep(std::unique_ptr<contact::ContactStep> step);

  // The hot arrays, one entry per body. models_ changes only by setForceModel (between steps).
  std::vector<Model> models_;
  std::vector<StepTerms> terms_;
  std::vector<State> states_;
  std::vector<AppliedWrench> inputs_;
  std::vector<Integrator> integrators_;
  std::vector<BodyRecord> records_;
  IntegratorType integrator_type_;
  IntegratorSettings settings_;
  StepAssembly assembly_;
  double dt_;
  double max_energy_growth_ = std::numeric_limits<double>::infinity();
  std::unique_ptr<contact::ContactStep> contact_;  // null: no body collides
  ContactSetup contact_setup_;                      // the environment, settings and shape of each body (for edits)
  bool record_contacts_ = false;
  std::vector<std::size_t> collider_of_;            // body → its index among the colliders, or kNoCollider
  std::vector<char> collider_running_;              // per collider, reused
  std::vector<StepStatus> collider_failed_;         // per collider, reused
  std::unique_ptr<ThreadPool> pool_;                // steps the independent bodies in blocks
  std::vector<SceneStepResult> block_results_;      // one per block of the last threaded step, reused
  // The independent bodies' batches, under a method with a lane kernel (null under the others).
  std::unique_ptr<integrators::BatchStepper> batches_;
  std::size_t bodies_per_block_ = kBodiesPerBlock;
  bool wide_lanes_;
};

}  // namespace rigid_body
