// Speculative points (docs/contact.md, step 2): a pair that touches gives, besides its points within the
// slop, the points of its faces that are still apart but near enough to arrive within the step. A box that
// lands on a corner pivots about it, and its far side swings down at several times its centre's speed; its
// points there were no contact the step before (farther than the slop), and without them the solver first
// sees that side once it is deep inside (docs/performance_log.md, the pile's deepest penetration). With them, the solve's
// target for a separated point, a closing speed of at most d/h (contact_solver.hpp), brings that side to
// the surface instead (Catto, "Speculative contacts", GDC 2013; Box2D's speculative margin).
#include "collision_world.hpp"

#include "collision_world_impl.hpp"
#include "face_manifold.hpp"

namespace rigid_body {
namespace contact {

void CollisionWorld::addSpeculativePoints(std::size_t first, double max_distance, double speculative_distance,
                                          double beyond, std::vector<ContactPoint>& points) {
  std::size_t deepest = first;
  for (std::size_t i = first; i < points.size(); ++i) {
    if (points[i].distance < points[deepest].distance) deepest = i;
  }
  if (!(points[deepest].distance <= max_distance)) return;
  const ContactPoint query = points[deepest];
  // Shapes with faces only (a sphere's one point is all it has; a triangle of an environment mesh is not
  // known to the face code); box pairs too, whose detector gives penetrating points only.
  const btCollisionObject* object_a = impl_->objects[query.a].get();
  const btCollisionObject* object_b = impl_->objects[query.b].get();
  if (object_a == nullptr || object_b == nullptr || !facedType(object_a->getCollisionShape()->getShapeType()) ||
      !facedType(object_b->getCollisionShape()->getShapeType())) {
    return;
  }
  const HullFaces *hull_a = nullptr, *hull_b = nullptr;
  const Eigen::Isometry3d *X_WA = nullptr, *X_WB = nullptr;
  const CollisionShape* shape_a = facedShape(query.a, &hull_a, &X_WA);
  const CollisionShape* shape_b = facedShape(query.b, &hull_b, &X_WB);
  supportingFace(*shape_a, hull_a, *X_WA, -query.normal, impl_->face_a);
  supportingFace(*shape_b, hull_b, *X_WB, query.normal, impl_->face_b);
  std::vector<ContactPoint>& clipped = impl_->speculative_points;
  clipped.clear();
  if (!clipFaces(impl_->face_a, impl_->face_b, query.normal, speculative_distance, query, clipped)) return;
  for (ContactPoint& point : clipped) {
    if (!(point.distance > beyond)) continue;  // the pair's own points already hold what is this near
    point.speculative = point.distance > max_distance;
    points.push_back(point);
  }
}

}  // namespace contact
}  // namespace rigid_body
