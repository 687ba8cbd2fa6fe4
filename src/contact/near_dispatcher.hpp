// Bullet's collision dispatcher as the contact step asks it: the points of a pair up to `near_distance`
// apart (Bullet's own near callback asks for touching points only: two spheres 1e-17 m apart had no contact,
// so a ball resting against another did not count as touching, and an impact could not travel through the
// pair), with the pairs' narrow phases spread over the scene's thread pool. Bullet-private: included by
// collision_world_impl.hpp only.
#pragma once

#include <btBulletCollisionCommon.h>

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <vector>

#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

struct NearDispatcher : btCollisionDispatcher {
  explicit NearDispatcher(btCollisionConfiguration* configuration) : btCollisionDispatcher(configuration) {}

  double near_distance = 0.0;
  /// Each body's bounding sphere as placed: its centre of mass and its outer radius [m]. (A box's or
  /// cylinder's collision margin lies inside it, a hull has none: GJK never sees a shape larger than it is.)
  std::vector<Eigen::Vector4d> bounding_spheres;
  /// Where the pairs' narrow phases run (null: the caller), in blocks of how many pairs; set for the
  /// duration of a detection.
  ThreadPool* pool = nullptr;
  std::size_t pairs_per_block = 64;
  /// Asked of a convex pair that has its manifold: whether the points it gave last time still stand
  /// (pair_reuse.hpp); its narrow phase is then skipped and its manifold left empty. Asked on the pool,
  /// where the pair's query would run (each pair its own entry), once the broad phase has kCheckBlocks
  /// blocks' worth of pairs; on the caller below that. Empty: every pair is queried.
  std::function<bool(const btPersistentManifold&)> stands_still;

  /// Every overlapping pair of the broad phase, in its order: those that need one get their algorithm (and a
  /// pair's first manifold) here, in that order, on the caller, since Bullet's dispatcher hands both out of
  /// pools without a lock; a pair whose algorithm holds its manifold already (any convex pair after its
  /// first detection) then runs its narrow phase on the pool, each writing its own manifold only. The
  /// manifolds' order, and so the points', is that of the serial dispatch on any thread count.
  void dispatchAllCollisionPairs(btOverlappingPairCache* pairs, const btDispatcherInfo& info, btDispatcher*) override;

  /// Whether a pair is tested at all: Bullet's filter (two sleeping bodies, or a sleeping body and the
  /// environment, are not), then the bounding spheres (two bodies whose spheres are farther apart than the
  /// near distance have no point within it: one subtraction instead of a query).
  bool testsPair(const btCollisionObject* a, const btCollisionObject* b);

 private:
  bool needsNarrowPhase(const btBroadphasePair& pair);
  /// stands_still's answer for a convex pair whose manifolds are `manifolds` (false unless it has one).
  bool standsStill(const btManifoldArray& manifolds) const;
  /// One pair's narrow phase (btCollisionDispatcher::defaultNearCallback, with the result's distance
  /// threshold set); `manifolds` is scratch.
  void processPair(btBroadphasePair& pair, const btDispatcherInfo& info, btManifoldArray& manifolds);

  // A reuse check is a few dozen operations: so many blocks of pairs make them worth a hand-out.
  static constexpr std::size_t kCheckBlocks = 8;
  std::vector<btBroadphasePair*> pooled_pairs_;          // this detection's pairs for the pool
  std::vector<btManifoldArray> block_manifolds_;          // scratch of processPair, one per block of pairs
};

}  // namespace contact
}  // namespace rigid_body
