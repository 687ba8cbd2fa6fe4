// Speculative points (docs/contact.md, step 2): a pair that touches gives, besides its points within the
// slop, the points of its faces that are still apart but near enough to arrive within the step. A box that
// lands on a corner pivots about it, and its far side swings down at several times its centre's speed; its
// points there were no contact the step before (farther than the slop), and without them the solver first
// sees that side once it is deep inside (docs/performance_log.md, the pile's deepest penetration). With them, the solve's
// target for a separated point, a closing speed of at most d/h (contact_solver.hpp), brings that side to
// the surface instead (Catto, "Speculative contacts", GDC 2013; Box2D's speculative margin).
#include "collision_world.hpp"

#include "collision_world_impl.hpp"

namespace rigid_body {
namespace contact {

void CollisionWorld::addSpeculativePoints(std::size_t first, double max_distance, double speculative_distance,
                                          double beyond, PairScratch& scratch, std::vector<ContactPoint>& points) {
  std::size_t deepest = first;
  for (std::size_t i = first; i < points.size(); ++i) {
    if (points[i].distance < points[deepest].distance) deepest = i;
  }
  if (!(points[deepest].distance <= max_distance)) return;
  const ContactPoint query = points[deepest];
  // Shapes with faces only (a sphere's one point is all it has; a triangle of an environment mesh is not
  // known to the face code).
  if (!facedType(proxyType(query.a)) || !facedType(proxyType(query.b))) return;
  std::vector<ContactPoint>& clipped = scratch.speculative_points;
  clipped.clear();
  if (!clipPairFaces(query, speculative_distance, scratch, clipped)) return;
  for (ContactPoint& point : clipped) {
    if (!(point.distance > beyond)) continue;  // the pair's own points already hold what is this near
    point.speculative = point.distance > max_distance;
    points.push_back(point);
  }
}

}  // namespace contact
}  // namespace rigid_body
