#include "near_dispatcher.hpp"

#include "collision_world_impl.hpp"

namespace rigid_body {
namespace contact {

bool NearDispatcher::needsNarrowPhase(const btBroadphasePair& pair) {
  return testsPair(static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject),
                   static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject));
}

bool NearDispatcher::testsPair(const btCollisionObject* a, const btCollisionObject* b) {
  if (!needsCollision(a, b)) return false;
  // The broad phase pairs boxes fattened for motion (Bullet's tree margin and velocity prediction), so in a
  // pile most of its pairs fail this test.
  const auto i = static_cast<std::size_t>(a->getUserIndex()), j = static_cast<std::size_t>(b->getUserIndex());
  if (i < bounding_spheres.size() && j < bounding_spheres.size()) {
    const Eigen::Vector4d& s_i = bounding_spheres[i];
    const Eigen::Vector4d& s_j = bounding_spheres[j];
    if ((s_i.head<3>() - s_j.head<3>()).norm() - s_i[3] - s_j[3] > near_distance) return false;
  }
  return true;
}

void NearDispatcher::processPair(btBroadphasePair& pair, const btDispatcherInfo& info, btManifoldArray& manifolds) {
  auto* a = static_cast<btCollisionObject*>(pair.m_pProxy0->m_clientObject);
  auto* b = static_cast<btCollisionObject*>(pair.m_pProxy1->m_clientObject);
  // Two boxes get their points from the contact step's own separating-axis test and face clipping
  // (CollisionWorld::addBoxPoints), not from Bullet's box–box detector; their manifold stays empty.
  if (boxBoxPair(a->getCollisionShape()->getShapeType(), b->getCollisionShape()->getShapeType())) return;
  btCollisionObjectWrapper a_wrap(nullptr, a->getCollisionShape(), a, a->getWorldTransform(), -1, -1);
  btCollisionObjectWrapper b_wrap(nullptr, b->getCollisionShape(), b, b->getWorldTransform(), -1, -1);
  btManifoldResult result(&a_wrap, &b_wrap);
  const double reach = near_distance + queryReach(*a, *b);
  // Bullet's algorithm for a body on an environment mesh asks each triangle, whenever the result's threshold
  // is above zero, for closest points into a manifold of the triangle's own algorithm, which it frees with
  // them: the pair's own manifold stayed empty and bodies fell through environment meshes. Such a pair
  // keeps the threshold at zero; its triangles then add to its manifold every point no farther apart than
  // the manifold's breaking threshold, which holds the reach instead.
  const bool concave = !a->getCollisionShape()->isConvex() || !b->getCollisionShape()->isConvex();
  result.m_closestPointDistanceThreshold = concave ? 0.0 : reach;
  // A manifold drops points farther out than its breaking threshold (a few per cent of the shapes' size):
  // it must keep what the query's reach asks for (from the pair's second query on; the first makes it).
  manifolds.resizeNoInitialize(0);
  pair.m_algorithm->getAllContactManifolds(manifolds);
  for (int m = 0; m < manifolds.size(); ++m) {
    btPersistentManifold& manifold = *manifolds[m];
    if (manifold.getContactBreakingThreshold() < reach) manifold.setContactBreakingThreshold(reach);
  }
  pair.m_algorithm->processCollision(&a_wrap, &b_wrap, info, &result);
}

void NearDispatcher::dispatchAllCollisionPairs(btOverlappingPairCache* pairs, const btDispatcherInfo& info, btDispatcher*) {
  block_manifolds_.resize(1);
  pooled_pairs_.clear();
  btBroadphasePairArray& all = pairs->getOverlappingPairArray();
  // With fewer pairs than kCheckBlocks blocks' worth, the reuse checks are made here and only the queries
  // go to the pool (a small scene's settled pairs then wake no thread).
  const std::size_t per_block = std::max<std::size_t>(1, pairs_per_block);
  const auto pair_count = static_cast<std::size_t>(all.size());
  const bool checks_pooled = pool != nullptr && pair_count >= scaledBlock(per_block, kCheckBlocks);
  for (int p = 0; p < all.size(); ++p) {
    btBroadphasePair& pair = all[p];
    if (!needsNarrowPhase(pair)) continue;
    auto* a = static_cast<btCollisionObject*>(pair.m_pProxy0->m_clientObject);
    auto* b = static_cast<btCollisionObject*>(pair.m_pProxy1->m_clientObject);
    if (pair.m_algorithm == nullptr) {
      btCollisionObjectWrapper a_wrap(nullptr, a->getCollisionShape(), a, a->getWorldTransform(), -1, -1);
      btCollisionObjectWrapper b_wrap(nullptr, b->getCollisionShape(), b, b->getWorldTransform(), -1, -1);
      pair.m_algorithm = findAlgorithm(&a_wrap, &b_wrap, nullptr, BT_CONTACT_POINT_ALGORITHMS);
      if (pair.m_algorithm == nullptr) continue;
    }
    // A convex pair whose algorithm holds its manifold allocates nothing more; any other (a first query,
    // a body on an environment mesh, whose algorithm makes one per triangle) runs here.
    btManifoldArray& manifolds = block_manifolds_[0];
    manifolds.resizeNoInitialize(0);
    pair.m_algorithm->getAllContactManifolds(manifolds);
    const bool convex = a->getCollisionShape()->isConvex() && b->getCollisionShape()->isConvex();
    const bool pooled = pool != nullptr && convex && manifolds.size() > 0;
    if (pooled && checks_pooled) {
      pooled_pairs_.push_back(&pair);  // its reuse asked there
      continue;
    }
    if (convex && standsStill(manifolds)) continue;
    if (pooled) {
      pooled_pairs_.push_back(&pair);
    } else {
      processPair(pair, info, manifolds);
    }
  }
  const std::size_t count = pooled_pairs_.size();
  block_manifolds_.resize(std::max<std::size_t>(1, blockCount(count, per_block)));
  forEachRange(pool, count, per_block, [&](std::size_t block, std::size_t first, std::size_t end) {
    btManifoldArray& manifolds = block_manifolds_[block];
    for (std::size_t i = first; i < end; ++i) {
      btBroadphasePair& pair = *pooled_pairs_[i];
      manifolds.resizeNoInitialize(0);
      pair.m_algorithm->getAllContactManifolds(manifolds);
      if (!(checks_pooled && standsStill(manifolds))) processPair(pair, info, manifolds);
    }
  });
}

bool NearDispatcher::standsStill(const btManifoldArray& manifolds) const {
  return manifolds.size() == 1 && stands_still && stands_still(*manifolds[0]);
}

}  // namespace contact
}  // namespace rigid_body
