// The contact half of a scene's step (docs/contact.md): the colliding bodies move freely by their
// integrator, an isolated impact is located in time and resolved there, then the contacts at the end of
// the step are solved at velocity level with a position projection for what penetration remains.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "collision_world.hpp"
#include "contact_solver.hpp"
#include "island_sleep.hpp"
#include "pair_runs.hpp"
#include "solver_islands.hpp"
#include "rigid_body_sim/contact.hpp"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {
namespace integrators {
class BatchStepper;
}
namespace contact {

/// The scene's arrays the contact step reads and advances (indexed by scene body).
struct SceneBodies {
  const std::vector<Model>& models;
  const std::vector<StepTerms>& terms;
  std::vector<State>& states;
  const std::vector<AppliedWrench>& inputs;
  std::vector<Integrator>& integrators;
  /// The scene's batches (its integrator has a lane kernel; prepared for this step), or none: the colliding
  /// bodies' free steps then run one by one. The same bits either way.
  const integrators::BatchStepper* batches = nullptr;
};

class ContactStep {
 public:
  /// Bodies farther than this from the origin leave the contact world until they come back [m]: double
  /// precision still resolves 1e-10 m there, and nothing past it can overflow Bullet's bounding boxes.
  static constexpr double kContactRange = 1e6;
  /// A colliding body not yet in the solver's list.
  static constexpr std::size_t kUnassigned = std::numeric_limits<std::size_t>::max();

  /// `colliders[k]` is the scene index of the k-th colliding body; body_shapes[that index] its shape;
  /// `states` the scene's states (the bodies enter the broad phase where they are).
  ContactStep(const std::vector<CollisionShape>& environment, const ContactSettings& settings,
              const std::vector<std::optional<CollisionShape>>& body_shapes, const std::vector<std::size_t>& colliders,
              IntegratorType integrator, const std::vector<State>& states);

  /// Throws std::invalid_argument naming both sides when a body starts inside another or the environment
  /// deeper than the penetration slop; otherwise takes the initial touching pairs as resting.
  void start(const std::vector<State>& states);

  /// One step of h for the colliding bodies whose `running[k]` is set. A body whose free step fails, or
  /// whose result is not finite, keeps its state from before the step and gets `failed[k]`; such a step is
  /// counted as refused and reports no contacts. The free steps (in blocks of `bodies_per_block`) and the
  /// resting solve's islands go to `pool` (null: the caller's thread alone); the result does not depend on
  /// its thread count or the block size.
  void step(SceneBodies& bodies, const std::vector<char>& running, double h, std::vector<StepStatus>& failed,
            ThreadPool* pool = nullptr, std::size_t bodies_per_block = 64);

  /// Empty if colliding body k may be at `state` (apart from the environment and the other bodies as they
  /// stand in `states`, within the slop, and not inside a closed environment mesh); otherwise a message
  /// naming both ("crate <verb> ground (...)"). The body's object goes back to where `states` has it.
  std::string placementConflict(std::size_t k, const State& state, const std::vector<State>& states, const char* verb);

  /// Forgets the touching pairs, warm starts and figures (after a reset or a state set from outside).
  void restart(const std::vector<State>& states);

  /// A body that does not collide left the scene at `scene_body`: the colliders after it move down one scene
  /// index (their contact memory stays).
  void renumberAfterRemoval(std::size_t scene_body) {
    for (std::size_t& body : colliders_) body -= body > scene_body ? 1 : 0;
  }

  /// Wakes the island colliding body k sleeps in, if it sleeps (its input or force model changed, or an
  /// awake body reaches it); its bodies are appended to `woken` if given.
  void wake(std::size_t k, std::vector<std::size_t>* woken = nullptr);

  const std::vector<std::size_t>& colliders() const { return colliders_; }
  /// The free steps the batches took since the last call, counted into each collider's integrator (its
  /// statistics): once a tick, not in every step, where a collider's integrator is a cold read.
  void countBatchedSteps(std::vector<Integrator>& integrators);
  /// The contacts of colliding body k at the end of the last step (kept only while recording).
  const std::vector<Contact>& contacts(std::size_t k) const { return contacts_[k]; }
  /// Recording from now on; a scene that starts recording wakes its sleeping islands, so that their reports
  /// are made afresh.
  void setRecording(bool recording);
  /// Whether the resting solve's four lanes run as AVX operations where the CPU has them (the same bits).
  void setWideLanes(bool on) { wide_lanes_ = on; }
  const ContactStatistics& statistics() const { return statistics_; }
  /// The last impacts located in time (at most kImpactLog of them, oldest first).
  const std::vector<ImpactEvent>& impacts() const { return impacts_; }
  static constexpr std::size_t kImpactLog = 64;

 private:
  // A pair that may meet within the step, and the bracket of its first touch along the integrated path:
  // apart at lo, touching (or within kImpactPointTolerance) at hi; `swept` when the continuous test found it.
  struct Candidate {
    std::size_t a, b;  // collision objects
    double lo, hi;     // [s] within the step
    double f_lo, f_hi; // signed distances there [m]
    bool swept;
  };
  // Warm start: last step's impulses by pair and by where the point sits on the body (its own frame).
  struct WarmPoint {
    std::uint64_t key;
    int feature;            // ≥ 0: matched by feature; otherwise by position on the body
    bool anchored;          // anchor_lo and anchor_hi hold (below); beside feature, in its padding
    Eigen::Vector3d local;
    double normal_impulse;
    Eigen::Vector3d friction_impulse_W;
    // A sticking point's anchors (docs/contact.md, step 6) on the pair's lower and higher object, each in
    // that object's frame (the world's for the environment); not anchored for a point that slid, and after a
    // step whose solve converged.
    Eigen::Vector3d anchor_lo, anchor_hi;
    double step;  // the h of the step whose solve left these impulses [s]
  };
  // What a pass over the points last looked up for a pair (a pair's points follow each other, and each asks
  // several times): whether it was touching, and its run of warm_; and the tangent basis of the last normal
  // (a face's points share theirs). Each pass (and each thread of one) has its own, dropped at its end:
  // touching_ and warm_ do not change within a pass.
  struct PairLookup {
    std::uint64_t touching_key = ~std::uint64_t{0};
    bool touching = false;
    std::uint64_t warm_key = ~std::uint64_t{0};
    std::size_t warm_begin = 0, warm_end = 0;
    Eigen::Vector3d basis_normal = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Eigen::Vector3d basis_t1, basis_t2;
  };
  std::uint64_t pairKey(std::size_t a, std::size_t b) const;
  bool wasTouching(std::uint64_t key) const;
  bool wasTouching(std::uint64_t key, PairLookup& lookup) const;
  ContactPartner partner(std::size_t object) const;
  ContactMaterial combined(std::size_t a, std::size_t b) const;
  void placeAll(const std::vector<State>& states);
  // Colliders [first, end) placed in the collision world (or marked outside it); then the count of those
  // outside, for the statistics.
  void placeRange(const std::vector<State>& states, std::size_t first, std::size_t end);
  void countOutside();
  /// The points at the poses as placed; with the bodies and the step, pairs touching within the slop with
  /// a body that moves add their speculative points (speculativeDistance).
  void detectPoints(const SceneBodies* bodies = nullptr, double h = 0.0);
  /// How far apart a touching pair's points may be and still be solved in a step of h (docs/contact.md,
  /// step 2): the slop plus what a point closing at kSpeculativeSpeed covers in the step.
  double speculativeDistance(double h) const;
  bool restoreAfterFailedLocation(SceneBodies& bodies, const Candidate& candidate);
  void findCandidates(SceneBodies& bodies, const std::vector<char>& running, double h);
  bool resolveImpact(SceneBodies& bodies, Candidate candidate, double h);
  /// The impact law at τ on the solver lists: the chain's impacts one after another if `sequential`, else
  /// every contact at once, those from `first_arrival` on still apart (they may close their gap within the
  /// rest of the step); then the rest of the step for the impact's bodies.
  void applyImpact(SceneBodies& bodies, const Candidate& candidate, double tau, double h, bool sequential,
                   std::size_t first_arrival);
  void gatherChain(SceneBodies& bodies, const Candidate& candidate, double tau);
  void indexPointsByBody();
  /// The fastest approach of any point of the chain now [m/s] (0 if none approaches), and its group.
  double fastestApproach(std::size_t& group) const;
  void solveChain(const SolveOptions& options);
  static constexpr std::size_t kMaxChainBodies = 64;  // bodies an impact's chain reaches at most
  static constexpr std::size_t kMaxChainImpacts = 16; // pairwise impacts per pair of a chain at most
  // The pair's signed distance after a partial step tau of both from the step's start (NaN if the partial
  // step fails); `keep_states` leaves the bodies there, `at` (two entries) receives the states.
  double distanceAfter(SceneBodies& bodies, std::size_t a, std::size_t b, double tau, bool keep_states,
                       State* at = nullptr);
  void stepSplitting(SceneBodies& bodies, const std::vector<char>& running, double h, std::vector<StepStatus>& failed,
                     int splits);
  void stepWhole(SceneBodies& bodies, const std::vector<char>& running, double h, std::vector<StepStatus>& failed);
  // Step 1 (free_motion.cpp): every running collider by its integrator as if nothing touched it, its
  // state before in start_, a refused step in failed; every collider placed in the collision world.
  void stepFreeMotion(SceneBodies& bodies, const std::vector<char>& running, double h, std::vector<StepStatus>& failed);
  void stepFreeMotionInBatches(SceneBodies& bodies, const std::vector<char>& running, double h,
                               std::vector<StepStatus>& failed);
  std::vector<std::size_t> collider_of_;  // scratch of stepFreeMotionInBatches: scene body → collider, or none
  std::vector<std::uint64_t> batched_steps_;  // per collider: free steps in batches not yet counted
  // The continuous test (continuous_collision.cpp): steps split while a body would move farther than it is
  // thick near something, and conservative advancement along the integrated path.
  static constexpr int kMaxStepSplits = 8;  // at most 2⁸ = 256 parts of a step
  bool needsShorterStep(const SceneBodies& bodies, const std::vector<char>& running, double h);
  std::vector<double> block_farthest_;  // scratch of needsShorterStep: per block of bodies, the farthest reach
  // A body's reach bound is a few dozen operations: so many of the scene's blocks of bodies make one block of
  // them on the pool, enough work to be worth a hand-out (a small scene's stay on the caller).
  static constexpr std::size_t kBoundBlocks = 8;
  double reachBound(const SceneBodies& bodies, std::size_t k, double h) const;
  bool movesFast(std::size_t k, const State& after) const;
  void sweptBox(const SceneBodies& bodies, std::size_t k, double h, Eigen::Vector3d& low, Eigen::Vector3d& high) const;
  void findFastImpacts(SceneBodies& bodies, const std::vector<char>& running, double h);
  bool advanceToImpact(SceneBodies& bodies, std::size_t a, std::size_t b, double h, Candidate& hit);
  double closingSpeedBound(const SceneBodies& bodies, std::size_t object, const State& at) const;
  // Sleeping (contact_sleep.cpp): islands at rest skip the step; an awake body that may reach a sleeping
  // one within the step wakes it first.
  void wakeReachedIslands(const SceneBodies& bodies, const std::vector<char>& running, double h);
  void updateSleep(SceneBodies& bodies, double h);
  void syncSleep();
  bool sleepingPair(std::uint64_t key) const;
  IslandSleep sleep_;
  std::vector<char> awake_, quiet_, supported_;  // per colliding body
  std::vector<std::pair<std::size_t, std::size_t>> links_;
  std::vector<std::size_t> to_check_;
  // The touching pairs and warm points of sleeping islands, set aside while they sleep (a pair with a
  // sleeping body is neither detected nor solved, so nothing looks them up) and put back when the island
  // wakes: a sleeping island costs no pass over its pairs in a step.
  std::vector<std::uint64_t> asleep_touching_;
  std::vector<WarmPoint> asleep_warm_;
  bool woken_ = false;  // an island woke since its pairs were set aside
  void setAsideSleepingPairs();
  // Puts back the pairs of islands woken since (called wherever a wake may just have happened, before
  // anything looks a pair up); returns whether there were any.
  bool restoreWokenPairs();

  void startSolverLists();
  // A collision object's solver body: solverSlot numbers it (and wakes it if it sleeps), fillSolverBody
  // gives solver body s its velocities and inertia from the body's state; solverIndex does both at once.
  std::size_t solverSlot(std::size_t object);
  void fillSolverBody(const SceneBodies& bodies, std::size_t s);
  std::size_t solverIndex(const SceneBodies& bodies, std::size_t object);
  // A solver contact from a detected point whose solver bodies c.a, c.b are numbered already, with its warm
  // start and anchors (`touching`: in the resting solve, its pair touching at the end of the last step; a
  // located impact's are not warm-started, and have no `local`, the point's place on its body for the warm
  // point it leaves).
  void makeContact(const ContactPoint& point, const SceneBodies& bodies, bool touching, double h, PairLookup& lookup,
                   SolverContact& c, std::pair<Eigen::Vector3d, Eigen::Vector3d>& anchors,
                   Eigen::Vector3d* local) const;
  // A located impact's contact (not warm-started), appended to the solver's lists.
  void addContact(const ContactPoint& point, const SceneBodies& bodies);
  // What one solved contact leaves for the next step, and its reports while recording.
  WarmPoint warmPointOf(std::size_t i, const SceneBodies& bodies, double h) const;
  void reportContact(std::size_t i);
  // The admitted points of the step as the solver's lists, island by island: numbered here, filled by
  // fillBodies for the islands [first_island, end_island) and fillContacts for the contacts [first, end).
  void buildSolverLists();
  void fillBodies(const SceneBodies& bodies, std::size_t first_island, std::size_t end_island);
  void fillContacts(const SceneBodies& bodies, double h, std::size_t first, std::size_t end);
  void solveResting(SceneBodies& bodies, double h);
  // After a block's solve: its bodies' states advanced by the impulses and moves, and its contacts as next
  // step's warm starts (with their anchors: only where the island's solve did not converge).
  void finishBlock(SceneBodies& bodies, double h, std::size_t first_island, std::size_t end_island);
  // After the solve: the pairs touching now (and those of sleeping islands) for the next step; the reports
  // while recording, and the warm points indexed by pair.
  void rememberTouching();
  void rememberContacts();
  // warm_runs_ for warm_ as it now is (warm_ sorted by pair first, should a pair's points not follow each
  // other).
  void indexWarmPoints();
  SolverIslands islands_;
  std::vector<std::size_t> admitted_;  // scratch: the points the resting solve takes
  std::vector<std::pair<std::size_t, std::size_t>> admitted_links_;  // their objects
  std::vector<char> admitted_touching_;  // whether their pairs touched at the end of the last step
  std::vector<char> solver_touching_;    // the same per solver contact
  std::vector<std::size_t> island_body_start_;  // per island: its first solver body (then one past the last)
  // Per island of the last resting solve: whether every impulse, normal and lever arm it ended with is
  // finite (found by finishBlock while its contacts are at hand; a step with one that is not is refused).
  std::vector<char> island_finite_;
  bool wide_lanes_ = true;
  ThreadPool* pool_ = nullptr;  // the scene's, for the islands; set for the duration of a step
  std::size_t bodies_per_block_ = 64;  // the free steps' blocks on the pool; set with pool_

  std::unique_ptr<CollisionWorld> world_;
  std::vector<std::size_t> colliders_;
  std::vector<ContactMaterial> materials_;  // per collision object
  std::vector<char> curved_;                // per collision object: a sphere, cylinder or capsule (it can roll)
  std::vector<std::string> names_;          // per collision object, for messages
  std::vector<double> inner_radius_;        // per colliding body
  std::vector<double> outer_radius_;        // per colliding body, about its centre of mass
  std::vector<char> fast_;                  // per colliding body: moved far enough in the step to sweep
  std::vector<Eigen::Vector3d> swept_low_, swept_high_;  // per colliding body: the box its step sweeps
  std::vector<std::size_t> near_;           // scratch: objects near a swept box
  std::vector<char> reserved_;              // per colliding body: in a located impact of this step already
  // An impact's chain: its bodies (collision objects), each pair's range in solver_contacts_, scratch.
  std::vector<std::size_t> chain_;
  std::vector<std::uint64_t> chain_pairs_;
  std::vector<std::pair<std::size_t, std::size_t>> chain_groups_;
  std::vector<ContactPoint> chain_points_;
  // points_ by body (each body's indices, increasing), made for the first chain of a step.
  std::vector<std::size_t> body_point_start_, body_point_index_;
  bool body_points_indexed_ = false;
  std::vector<SolverContact> chain_contacts_;
  std::vector<Eigen::Vector3d> chain_dP_, chain_dL_;
  std::vector<char> outside_;               // per colliding body: beyond the contact range
  ContactSettings settings_;
  IntegratorType integrator_type_;
  bool recording_ = false;

  // Per step, reused (no allocation once warm).
  std::vector<State> start_;
  std::vector<ContactPoint> points_, pair_points_;
  std::vector<char> moving_;  // scratch of detectPoints: per collider, whether it moves more than the slop
  // touching_: the pairs touching at the end of the last step, in no particular order; touching_index_
  // finds them (built by indexTouching wherever touching_ changes, before anything looks a pair up, on any
  // thread).
  std::vector<std::uint64_t> touching_, engaged_;
  PairRuns touching_index_;
  void indexTouching();
  std::vector<int> engagement_;             // engaged pairs per colliding body
  std::vector<Candidate> candidates_;
  std::vector<SolverBody> solver_bodies_;
  std::vector<std::size_t> solver_of_;      // colliding body → solver body, or kUnassigned
  std::vector<std::size_t> solver_body_of_; // solver body → colliding body
  std::vector<SolverContact> solver_contacts_;
  std::vector<const ContactPoint*> solver_points_;
  std::vector<std::vector<Contact>> contacts_;
  std::vector<ImpactEvent> impacts_;
  ContactStatistics statistics_;
  Eigen::Vector3d localPoint(const ContactPoint& point, const SceneBodies& bodies) const;
  // The impulses of the point of last step's that `point` matches (`local`: its place on its body, as
  // localPoint gives it), as the same force over this step's h, put in `contact`; that point, or null.
  const WarmPoint* warmStart(SolverContact& contact, const ContactPoint& point, const Eigen::Vector3d& local, double h,
                             PairLookup& lookup) const;
  // A point between the world and a collision object's own frame (the environment's is the world's).
  Eigen::Vector3d inObjectFrame(std::size_t object, const Eigen::Vector3d& p_W, const SceneBodies& bodies) const;
  Eigen::Vector3d inWorld(std::size_t object, const Eigen::Vector3d& local, const SceneBodies& bodies) const;
  std::vector<WarmPoint> warm_, warm_next_;
  PairRuns warm_runs_;  // each pair's run of warm_ (indexWarmPoints)
  std::vector<std::pair<std::uint64_t, std::size_t>> warm_order_;  // scratch of indexWarmPoints
  // Per solver contact: the anchors it carries on a and on b (in those objects' frames); zeros if not anchored.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> solver_anchors_;
  // Per solver contact of the resting solve: its point's place on its body (WarmPoint::local), and its two
  // solver bodies (numbered by buildSolverLists, given to the contact when it is filled).
  std::vector<Eigen::Vector3d> solver_local_;
  std::vector<std::pair<std::size_t, std::size_t>> solver_pairs_;
};

}  // namespace contact
}  // namespace rigid_body
