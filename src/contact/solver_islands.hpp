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
#include <functional>
#include <utility>
#include <vector>

#include "contact_solver.hpp"
#include "lane_contact_solver.hpp"
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
/// lane_contact_solver.hpp), the move by move_weight Δv, the limit on how far that lifts a contact made
/// within the step, then the position projection. `lift_share` has an entry per body (scratch; only the
/// range's are written). Returns whether the velocity sweeps converged.
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

  /// Work on a block: consecutive islands [first_island, end_island) with enough points between them to be
  /// worth a hand-out to a thread (a block; docs/architecture.md).
  using BlockWork = std::function<void(std::size_t block, std::size_t first_island, std::size_t end_island)>;

  /// Solves contacts made from the points in order() (contact j from point order()[j]) on `bodies` (0 the
  /// environment), island i's bodies being [body_start[i], body_start[i + 1]): afterwards every body has its
  /// dP, dL (the momentum the impulses give it) and dx, dtheta (how far they move it), and every contact its
  /// impulses. `pool` may be null (everything on the caller's thread). With `before` and `after`, each block
  /// calls them on its islands before it prepares them and after it has finished them, on the same thread
  /// (one hand-out per step for the caller's per-contact work as well; what they write must depend on the
  /// block's islands alone).
  void solve(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
             const std::vector<std::size_t>& body_start, const RestingSolveSettings& settings, ThreadPool* pool,
             const BlockWork& before = {}, const BlockWork& after = {});

  /// Per contact of the last solve: whether its island's velocity solve converged.
  bool converged(std::size_t contact) const { return island_converged_[island_of_contact_[contact]] != 0; }

 private:
  std::size_t root(std::size_t body);
  /// Calls `work` once per block of the last group(), spread over `pool` (may be null: the caller's thread).
  /// What a block writes must depend on its islands alone, so that the result does not depend on the threads.
  void forEachBlock(ThreadPool* pool, const BlockWork& work) const;

  std::vector<std::size_t> parent_;             // union–find over bodies
  std::vector<std::size_t> island_of_root_;     // per body that is a root: its island
  std::vector<std::size_t> island_of_point_;
  std::vector<std::size_t> order_, island_start_, next_;
  std::vector<std::size_t> island_of_contact_;  // = island_of_point_ in order()
  std::vector<char> island_converged_;
  std::vector<std::size_t> block_end_;          // islands [block_end_[b−1], block_end_[b]) form block b (group())
  std::vector<SolveRange> ranges_;              // per island
  std::vector<LaneContactSolver> block_solvers_;  // per block: its lanes' buffers, kept between steps
  std::vector<double> lift_share_;              // per solver body
};

}  // namespace contact
}  // namespace rigid_body
