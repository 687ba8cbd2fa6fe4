// The resting solve island by island (docs/contact.md, "Islands"): the colliding bodies linked by the step's
// contacts form islands (the environment links nothing), and no impulse of one island reaches a body of
// another, so each island's velocity solve, lift limit and position projection run on their own, on the
// thread pool where there are several, and each island stops sweeping when its own impulses have converged.
//
// The bits do not depend on the thread count: the solve's lists are built island by island (group() gives
// the order), an island works on its own run of them in that order, writes nothing outside it (the
// environment's entry is never written), and depends on nothing outside it but the sweep budget, which is
// the whole solve's (SolveOptions::budget_contacts).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <mutex>
#include <vector>

#include "contact_solver.hpp"
#include "lane_contact_solver.hpp"
#include "sticking_solve.hpp"
#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

/// What the resting solve does besides the velocity sweeps.
struct RestingSolveSettings {
  SolveOptions options;
  /// The impulses move a body by move_weight Δv and turn it by move_weight Δω (h times the integrator's
  /// constant-force weight: as the integrator would have moved it under a force constant over the step) [s].
  double move_weight = 0.0;
  int position_iterations = 4;
  double penetration_slop = 1e-4;  ///< [m]
  double position_correction = 0.2;
  LaneSettings lanes;  ///< how the velocity sweeps run (the same bits either way)
};

/// The impulses of the resting solve on `range`, with the moves they make: the velocity sweeps (in lanes,
/// lane_contact_solver.hpp) and, where they did not converge within the sweeps asked for, the island
/// solved at once if it sticks (sticking_solve.hpp), the move by move_weight Δv, the limit on how far that
/// lifts a contact made within the step, then the position projection. `lift_share` has an entry per body (scratch; only the
/// range's are written). Returns whether the velocity solve converged (in its sweeps or at once).
bool solveRestingContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                          const RestingSolveSettings& settings, const SolveRange& range,
                          std::vector<double>& lift_share);
/// What solveRestingContacts does after the velocity sweeps: dP and dL, the moves and the projection.
void finishRestingContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                           const RestingSolveSettings& settings, const SolveRange& range,
                           std::vector<double>& lift_share);

class SolverIslands {
 public:
  /// Groups contact points into islands: point i links objects links[i].first and .second, and an object
  /// ≥ `bodies` (the environment) links nothing. Islands are numbered by their smallest body (union–find with
  /// the smaller index as root), so the grouping does not depend on the order of the points.
  void group(const std::vector<std::pair<std::size_t, std::size_t>>& links, std::size_t bodies);
  /// The points island by island, each island's in their given order.
  const std::vector<std::size_t>& order() const { return order_; }
  std::size_t islands() const { return island_start_.empty() ? 0 : island_start_.size() - 1; }
  /// Island i's points are order()[islandStart(i)] up to order()[islandStart(i + 1)] (exclusive).
  std::size_t islandStart(std::size_t island) const { return island_start_[island]; }

  /// Whether an island has more points than a block holds (a large island; docs/architecture.md). It is a
  /// block of its own.
  bool large(std::size_t island) const { return island_start_[island + 1] - island_start_[island] > kContactsPerBlock; }

  /// Work on a block: consecutive islands [first_island, end_island) with enough points between them to be
  /// worth a hand-out to a thread (a block; docs/architecture.md).
  using BlockWork = std::function<void(std::size_t block, std::size_t first_island, std::size_t end_island)>;
  /// Work on the contacts [first, end) of one island.
  using ContactWork = std::function<void(std::size_t first, std::size_t end)>;
  /// What the caller does around the solve, on the thread that solves the islands concerned: fill the
  /// islands' solver bodies, then their contacts, before they are prepared; after they are finished, apply
  /// them. What each writes must depend on its own islands (or contacts) alone.
  struct Hooks {
    BlockWork fill_bodies;
    ContactWork fill_contacts;
    BlockWork after;
  };

  /// Solves contacts made from the points in order() (contact j from point order()[j]) on `bodies` (0 the
  /// environment), island i's bodies being [body_start[i], body_start[i + 1]): afterwards every body has its
  /// dP, dL (the momentum the impulses give it) and dx, dtheta (how far they move it), and every contact its
  /// impulses. `pool` may be null (everything on the caller's thread). Each block fills, prepares, sweeps
  /// and finishes its islands in one hand-out; on a pool of several threads a large island's bodies are
  /// filled first on the caller and its contacts filled and their rows prepared (prepareContactRows) in runs
  /// of a block's size over the pool, so that only its warm start, sweeps and projection stay on one thread.
  /// The same bits either way: those steps are per contact.
  void solve(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
             const std::vector<std::size_t>& body_start, const RestingSolveSettings& settings, ThreadPool* pool,
             const Hooks& hooks = {});

  /// Per contact of the last solve: whether its island's velocity solve converged (in its sweeps, or solved
  /// at once as if it stuck).
  bool converged(std::size_t contact) const { return island_converged_[island_of_contact_[contact]] != 0; }
  /// How many islands the last solve solved at once, kept or refused (each a factorisation).
  std::size_t triedAtOnce() const;

 private:
  // Islands go to the threads in blocks of about this many contacts: enough work per hand-out that the pool's
  // wake-ups stay small beside it, and enough blocks that two threads share a scene of a few stacks.
  static constexpr std::size_t kContactsPerBlock = 128;
  // An island whose solve at once was refused n times in a row (n ≤ this) waits 2ⁿ − 1 of its unconverged
  // steps before the next try (docs/contact.md, step 5): a settled pile's island, refused in most steps, paid
  // a factorisation in every one.
  static constexpr int kMostBackOffDoublings = 6;

  /// Whether the island waits (and counts down) before its next solve at once; noteOutcome records one.
  bool waitsToSolveAtOnce(std::size_t island);
  void noteOutcome(std::size_t island, StickingOutcome outcome);

  std::size_t root(std::size_t body);
  /// The large islands' bodies filled (on the caller), then their contacts filled and prepared in runs over
  /// the pool; returns whether it did (a pool of several threads and a large island).
  bool prepareLargeIslands(std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                           const SolveOptions& options, ThreadPool* pool, const Hooks& hooks);
  /// Calls `work` once per block of the last group(), spread over `pool` (may be null: the caller's thread).
  /// What a block writes must depend on its islands alone, so that the result does not depend on the threads.
  void forEachBlock(ThreadPool* pool, const BlockWork& work) const;

  std::vector<std::size_t> parent_;             // union–find over bodies
  std::vector<std::size_t> island_of_root_;     // per body that is a root: its island
  std::vector<std::size_t> island_root_;        // per island: its smallest body (the same from step to step)
  // Per body, for the island it is the smallest body of: solves at once refused in a row, and the
  // unconverged steps it still waits. Each island writes its own body's entries (any thread count).
  std::vector<std::uint8_t> refusals_;
  std::vector<std::uint32_t> waits_;
  std::vector<std::size_t> tried_at_once_;      // per block of the last solve
  std::vector<std::size_t> island_of_point_;
  std::vector<std::size_t> order_, island_start_, next_;
  std::vector<std::size_t> island_of_contact_;  // = island_of_point_ in order()
  std::vector<char> island_converged_;
  std::vector<std::size_t> block_end_;          // islands [block_end_[b−1], block_end_[b]) form block b (group())
  std::vector<SolveRange> ranges_;              // per island
  // What a block's solve works in: its lanes' buffers and its direct solves' lists, nothing that outlives
  // the block. The blocks share as many as run at once (one per thread), each taken from free_scratch_ and
  // given back, so that one thread's blocks reuse memory still in its caches; kept between steps.
  struct BlockScratch {
    LaneContactSolver lanes;
    StickingScratch sticking;
  };
  std::vector<BlockScratch> scratch_;
  std::vector<std::size_t> free_scratch_;  // indices into scratch_, under scratch_mutex_
  std::mutex scratch_mutex_;
  std::size_t takeScratch();
  void giveBackScratch(std::size_t slot);
  std::vector<double> lift_share_;              // per solver body
  std::vector<std::pair<std::size_t, std::size_t>> large_runs_;  // scratch: runs of the large islands' contacts
};

}  // namespace contact
}  // namespace rigid_body
