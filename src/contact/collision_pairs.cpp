// One pair of objects at a time: which shapes face clipping serves and the points it makes them, a body's
// points on a half-space, and the pair distance that locates impacts and sweeps fast bodies.
#include "collision_world.hpp"

#include "box_separation.hpp"
#include "collision_world_impl.hpp"
#include "face_manifold.hpp"
#include "pair_reuse.hpp"

namespace rigid_body {
namespace contact {

namespace {

// How much farther out than the one query's point face clipping may put a pair's deepest point [m]: well
// above EPA's accuracy on a face, far below any shape's size.
constexpr double kFaceDepthTolerance = 1e-4;

}  // namespace

const CollisionShape* CollisionWorld::facedShape(std::size_t object, const HullFaces** hull,
                                                 const Eigen::Isometry3d** X_WS) const {
  const bool body = isBody(object);
  const CollisionShape& shape = body ? impl_->body_shapes[object] : impl_->environment_shapes[object - bodyCount()];
  *hull = shape.type == ShapeType::kMesh ? &impl_->hull_faces[object] : nullptr;
  *X_WS = &shapePose(object);
  return &shape;
}

const Eigen::Isometry3d& CollisionWorld::shapePose(std::size_t object) const {
  return isBody(object) ? impl_->shape_poses[object] : impl_->environment_shapes[object - bodyCount()].pose;
}

bool CollisionWorld::addFacePoints(const btPersistentManifold& manifold, double max_distance, PairReuse& reuse,
                                   PairScratch& scratch, std::vector<ContactPoint>& points) {
  const auto a = static_cast<std::size_t>(manifold.getBody0()->getUserIndex());
  const auto b = static_cast<std::size_t>(manifold.getBody1()->getUserIndex());
  if (reuse.reused()) {  // the dispatcher skipped its query (pairStandsStill)
    reuse.appendPoints(shapePose(a), shapePose(b), max_distance, points);
    return true;
  }
  // The one query's point (the deepest, should the manifold hold more) gives the normal.
  int deepest = -1;
  for (int c = 0; c < manifold.getNumContacts(); ++c) {
    if (deepest < 0 || manifold.getContactPoint(c).getDistance() < manifold.getContactPoint(deepest).getDistance()) deepest = c;
  }
  if (deepest < 0) return false;
  const ContactPoint query = pointFrom(manifold.getContactPoint(deepest), manifold.getBody0(), manifold.getBody1());
  const std::size_t first = points.size();
  if (!addFacePoints(query, max_distance, scratch, points)) return false;
  if (impl_->reuse_points) reuse.store(a, b, shapePose(a), shapePose(b), max_distance, points, first);
  return true;
}

bool CollisionWorld::pairStandsStill(const btPersistentManifold& manifold, double max_distance) {
  const auto m = static_cast<std::size_t>(manifold.m_index1a);
  const auto a = static_cast<std::size_t>(manifold.getBody0()->getUserIndex());
  const auto b = static_cast<std::size_t>(manifold.getBody1()->getUserIndex());
  // Points are stored only by a face-clipped pair or a box pair, so a place that holds this pair's needs no
  // look at its shapes' types.
  if (m >= impl_->pair_reuse.size() || !impl_->pair_reuse[m].holds(a, b)) return false;
  return impl_->pair_reuse[m].standsStill(a, b, shapePose(a), shapePose(b), impl_->shape_reach[a],
                                          impl_->shape_reach[b], max_distance);
}

int CollisionWorld::proxyType(std::size_t object) const {
  const btCollisionObject* bullet = impl_->objects[object].get();
  return bullet == nullptr ? -1 : bullet->getCollisionShape()->getShapeType();
}

bool CollisionWorld::clipPairFaces(const ContactPoint& query, double max_distance, PairScratch& scratch,
                                   std::vector<ContactPoint>& points) {
  const HullFaces *hull_a = nullptr, *hull_b = nullptr;
  const Eigen::Isometry3d *X_WA = nullptr, *X_WB = nullptr;
  const CollisionShape* shape_a = facedShape(query.a, &hull_a, &X_WA);
  const CollisionShape* shape_b = facedShape(query.b, &hull_b, &X_WB);
  supportingFace(*shape_a, hull_a, *X_WA, -query.normal, scratch.face_a);
  supportingFace(*shape_b, hull_b, *X_WB, query.normal, scratch.face_b);
  return clipFaces(scratch.face_a, scratch.face_b, query.normal, max_distance, query, points);
}

bool CollisionWorld::addFacePoints(const ContactPoint& query, double max_distance, PairScratch& scratch,
                                   std::vector<ContactPoint>& points) {
  if (!faceClippedPair(proxyType(query.a), proxyType(query.b))) return false;
  const std::size_t first = points.size();
  if (!clipPairFaces(query, max_distance, scratch, points)) return false;
  // The clipped points lie on the exact surfaces, the query's on surfaces whose edges and corners may be
  // rounded inward by a margin (a box's, a cylinder's): the deepest clipped point can lie no farther out
  // than the query's. Farther out, the faces do not hold the contact (a corner of the pair the clipping
  // missed).
  double clipped = max_distance;
  for (std::size_t i = first; i < points.size(); ++i) clipped = std::min(clipped, points[i].distance);
  if (clipped <= query.distance + kFaceDepthTolerance) return true;
  points.resize(first);
  return false;
}

bool CollisionWorld::boxPair(std::size_t a, std::size_t b) const {
  return boxBoxPair(proxyType(a), proxyType(b));
}

bool CollisionWorld::addBoxPoints(std::size_t a, std::size_t b, double max_distance, PairScratch& scratch,
                                  std::vector<ContactPoint>& points) {
  const HullFaces *hull_a = nullptr, *hull_b = nullptr;
  const Eigen::Isometry3d *X_WA = nullptr, *X_WB = nullptr;
  const CollisionShape& box_a = *facedShape(a, &hull_a, &X_WA);
  const CollisionShape& box_b = *facedShape(b, &hull_b, &X_WB);
  const BoxSeparation separation = separateBoxes(*X_WA, 0.5 * box_a.size, *X_WB, 0.5 * box_b.size);
  if (!(separation.distance <= max_distance)) return false;
  ContactPoint query;
  query.a = a, query.b = b;
  query.on_a = separation.on_a, query.on_b = separation.on_b;
  query.normal = separation.normal;
  query.distance = separation.distance;
  // A face along the axis (the axis is a face's normal, or an edge lies on a face): the clipped points;
  // else two edges across each other meet at one point.
  if (clipPairFaces(query, max_distance, scratch, points)) return true;
  if (!separation.edges || !separation.edges_cross) return false;
  points.push_back(query);
  return true;
}

bool CollisionWorld::addBoxPoints(const btPersistentManifold& manifold, double max_distance, PairReuse& reuse,
                                  PairScratch& scratch, std::vector<ContactPoint>& points) {
  const btCollisionObject* object_a = manifold.getBody0();
  const btCollisionObject* object_b = manifold.getBody1();
  const auto a = static_cast<std::size_t>(object_a->getUserIndex());
  const auto b = static_cast<std::size_t>(object_b->getUserIndex());
  if (!boxPair(a, b) || !impl_->dispatcher.testsPair(object_a, object_b)) return false;
  const std::size_t first = points.size();
  if (reuse.reused()) {  // decided in the dispatch (pairStandsStill), as for a queried pair
    reuse.appendPoints(shapePose(a), shapePose(b), max_distance, points);
  } else {
    addBoxPoints(a, b, max_distance, scratch, points);
    if (impl_->reuse_points) reuse.store(a, b, shapePose(a), shapePose(b), max_distance, points, first);
  }
  return points.size() > first;
}

bool CollisionWorld::addTrianglePoints(const btPersistentManifold& manifold, double max_distance, PairScratch& scratch,
                                       std::vector<ContactPoint>& points) {
  const auto index0 = static_cast<std::size_t>(manifold.getBody0()->getUserIndex());
  const auto index1 = static_cast<std::size_t>(manifold.getBody1()->getUserIndex());
  const bool mesh_is_0 = proxyType(index0) == TRIANGLE_MESH_SHAPE_PROXYTYPE;
  const std::size_t mesh = mesh_is_0 ? index0 : index1, body = mesh_is_0 ? index1 : index0;
  if (proxyType(mesh) != TRIANGLE_MESH_SHAPE_PROXYTYPE || !isBody(body) || !facedType(proxyType(body))) return false;
  if (manifold.getNumContacts() == 0) return false;
  const std::vector<std::array<Eigen::Vector3d, 3>>& triangles = impl_->environment_triangles[mesh - bodyCount()];
  const HullFaces* hull = nullptr;
  const Eigen::Isometry3d* X_WS = nullptr;
  const CollisionShape& shape = *facedShape(body, &hull, &X_WS);
  const std::size_t first = points.size();
  // Each triangle once, from its deepest point (a manifold holds at most four points).
  for (int c = 0; c < manifold.getNumContacts(); ++c) {
    const btManifoldPoint& p = manifold.getContactPoint(c);
    const int triangle = mesh_is_0 ? p.m_index0 : p.m_index1;
    bool deepest = triangle >= 0 && static_cast<std::size_t>(triangle) < triangles.size();
    for (int o = 0; o < manifold.getNumContacts() && deepest; ++o) {
      const btManifoldPoint& q = manifold.getContactPoint(o);
      const int other = mesh_is_0 ? q.m_index0 : q.m_index1;
      deepest = other != triangle || q.getDistance() > p.getDistance() || (q.getDistance() == p.getDistance() && o >= c);
    }
    if (!deepest) continue;
    const ContactPoint query = pointFrom(p, manifold.getBody0(), manifold.getBody1());
    if (query.distance > max_distance + queryReach(*manifold.getBody0(), *manifold.getBody1())) continue;
    // The triangle as a face of the mesh's side, its normal the side of the triangle the body is on; the
    // body's face along the normal towards the mesh (n points from b to a).
    SupportFace& face = query.a == mesh ? scratch.face_a : scratch.face_b;
    SupportFace& body_face = query.a == mesh ? scratch.face_b : scratch.face_a;
    const auto& t = triangles[static_cast<std::size_t>(triangle)];
    face.vertices.assign(t.begin(), t.end());
    face.normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    const Eigen::Vector3d towards_body = query.a == mesh ? Eigen::Vector3d(-query.normal) : query.normal;
    if (face.normal.dot(towards_body) < 0.0) face.normal = -face.normal;
    supportingFace(shape, hull, *X_WS, -towards_body, body_face);
    if (!clipFaces(scratch.face_a, scratch.face_b, query.normal, max_distance, query, points) &&
        query.distance <= max_distance) {
      points.push_back(query);  // an edge or corner on the triangle: its one point
    }
  }
  keepFourPoints(points, first);
  return true;
}

double CollisionWorld::planeContacts(std::size_t body, std::size_t plane_object, double max_distance,
                                     std::vector<ContactPoint>& points, double beyond) const {
  const Impl::Plane* plane = &impl_->planes[static_cast<std::size_t>(impl_->plane_of_object[plane_object])];
  double smallest = max_distance;
  const Eigen::Vector3d& n = plane->normal;
  planeFeatures(impl_->body_shapes[body], impl_->shape_poses[body], n, [&](int feature, const Eigen::Vector3d& x) {
    const double distance = n.dot(x) - plane->offset;
    smallest = std::min(smallest, distance);
    if (distance > max_distance || distance <= beyond) return;
    ContactPoint point;
    point.speculative = beyond > -std::numeric_limits<double>::infinity();
    point.a = body;
    point.b = plane_object;
    point.on_a = x;
    point.on_b = x - distance * n;
    point.normal = n;
    point.distance = distance;
    point.feature = feature;
    points.push_back(point);
  });
  return smallest;
}

namespace {

// The smallest distance of `points`, or max_distance if there are none.
double smallestDistance(const std::vector<ContactPoint>& points, double max_distance) {
  double smallest = max_distance;
  for (const ContactPoint& point : points) smallest = std::min(smallest, point.distance);
  return smallest;
}

struct PairCollector : btCollisionWorld::ContactResultCallback {
  std::vector<ContactPoint>* points = nullptr;
  btScalar addSingleResult(btManifoldPoint& p, const btCollisionObjectWrapper* a, int, int,
                           const btCollisionObjectWrapper* b, int, int) override {
    points->push_back(pointFrom(p, a->getCollisionObject(), b->getCollisionObject()));
    return 0;
  }
};

}  // namespace

double CollisionWorld::pairDistance(std::size_t a, std::size_t b, double max_distance, std::vector<ContactPoint>* points) {
  std::vector<ContactPoint>& out = points ? *points : impl_->clipped_points;
  out.clear();
  if (isPlane(a) || isPlane(b)) {
    return isPlane(b) ? planeContacts(a, b, max_distance, out) : planeContacts(b, a, max_distance, out);
  }
  if (boxPair(a, b)) {
    addBoxPoints(a, b, max_distance, impl_->scratch, out);
    return smallestDistance(out, max_distance);
  }
  std::vector<ContactPoint>& found = impl_->pair_points;
  found.clear();
  PairCollector collector;
  collector.points = &found;
  collector.m_closestDistanceThreshold = max_distance + queryReach(*impl_->objects[a], *impl_->objects[b]);
  impl_->world.contactPairTest(impl_->objects[a].get(), impl_->objects[b].get(), collector);
  // A pair that face clipping serves gets its points, and its distance, as the detection does: from the
  // query's deepest point, on the exact surfaces (a located impact then meets a face with the whole face).
  const auto deepest = std::min_element(found.begin(), found.end(), [](const ContactPoint& x, const ContactPoint& y) {
    return x.distance < y.distance;
  });
  if (deepest != found.end() && addFacePoints(*deepest, max_distance, impl_->scratch, out)) {
    return smallestDistance(out, max_distance);
  }
  // Else the query's own points, those within max_distance (the reach may have found farther ones).
  double smallest = max_distance;
  for (const ContactPoint& point : found) {
    if (point.distance > max_distance) continue;
    smallest = std::min(smallest, point.distance);
    if (points) points->push_back(point);
  }
  return smallest;
}

}  // namespace contact
}  // namespace rigid_body
