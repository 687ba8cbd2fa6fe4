#include "collision_world.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "convex_hull.hpp"
#include "face_manifold.hpp"
#include "shape_features.hpp"

namespace rigid_body {
namespace contact {

namespace {

btVector3 toBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d fromBt(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }
btQuaternion toBt(const Eigen::Quaterniond& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
btTransform toBt(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.rotation());
  return btTransform(toBt(q), toBt(Eigen::Vector3d(X.translation())));
}

// GJK-based pairs round a convex shape's corners by its margin; Bullet's default (0.04 m) is large for
// small bodies, so the margin is a small fraction of the shape, at most 4 mm.
double marginFor(double smallest_extent) { return std::min(0.004, 0.05 * smallest_extent); }

ContactPoint pointFrom(const btManifoldPoint& p, const btCollisionObject* a, const btCollisionObject* b) {
  ContactPoint point;
  point.a = static_cast<std::size_t>(a->getUserIndex());
  point.b = static_cast<std::size_t>(b->getUserIndex());
  point.on_a = fromBt(p.getPositionWorldOnA());
  point.on_b = fromBt(p.getPositionWorldOnB());
  point.normal = fromBt(p.m_normalWorldOnB);
  point.distance = p.getDistance();
  return point;
}

// A sphere meets another shape where the normal through its centre leaves it, so its normal force passes
// through the centre. Bullet's multi-point iterations rotate a shape a little, find the closest points again
// and rotate them back; for a sphere that puts points r·θ beside that line, and the manifold, which merges
// points nearer than its breaking threshold, may keep such a point instead of the true one (a ball on a
// 20 m box had its only point 1 cm off the line and 5e-5 m too far out, δ²/2r). The normal force then turns a
// resting ball, which rolls off a flat box. So the points of a pair with a sphere are rebuilt on the line
// through the centre c along the normal n: the sphere's point at c − r s n (s the side of the other point,
// whose distance along n is exact on a face) and the other point moved along the face onto the line; the
// iterations' points then coincide and one is kept. A sphere touches one convex shape at one point.
const btSphereShape* sphereOf(const btCollisionObject* object) {
  const btCollisionShape* shape = object->getCollisionShape();
  return shape->getShapeType() == SPHERE_SHAPE_PROXYTYPE ? static_cast<const btSphereShape*>(shape) : nullptr;
}

void ontoSphereNormalLine(const btCollisionObject* sphere, ContactPoint& point) {
  const Eigen::Vector3d c = fromBt(sphere->getWorldTransform().getOrigin());
  const double r = sphereOf(sphere)->getRadius();
  const Eigen::Vector3d& n = point.normal;
  // The witness on the sphere is the one at its radius from the centre; the other lies on the other shape.
  const bool sphere_is_a = std::abs((point.on_a - c).norm() - r) <= std::abs((point.on_b - c).norm() - r);
  Eigen::Vector3d& on_sphere = sphere_is_a ? point.on_a : point.on_b;
  Eigen::Vector3d& on_other = sphere_is_a ? point.on_b : point.on_a;
  const double along = (on_other - c).dot(n);
  on_other = c + along * n;
  on_sphere = c + (along < 0.0 ? -r : r) * n;
  point.distance = (point.on_a - point.on_b).dot(n);
}

// Adds a pair's points from `first` on; with a sphere in the pair, one point per normal line.
void addSpherePoint(const btCollisionObject* sphere, ContactPoint point, std::size_t first, std::vector<ContactPoint>& points) {
  ontoSphereNormalLine(sphere, point);
  const double radius = static_cast<const btSphereShape*>(sphere->getCollisionShape())->getRadius();
  for (std::size_t i = first; i < points.size(); ++i) {
    if ((points[i].on_b - point.on_b).norm() <= 1e-3 * radius && points[i].normal.dot(point.normal) > 1.0 - 1e-9) {
      if (point.distance < points[i].distance) points[i] = point;
      return;
    }
  }
  points.push_back(point);
}

// Bullet's dispatcher, which reports the points of a pair up to `near_distance` apart (its own near callback
// asks for touching points only: two spheres 1e-17 m apart had no contact, so a ball resting against
// another did not count as touching, and an impact could not travel through the pair).
struct NearDispatcher : btCollisionDispatcher {
  explicit NearDispatcher(btCollisionConfiguration* configuration) : btCollisionDispatcher(configuration) {
    setNearCallback(&NearDispatcher::nearCallback);
  }
  double near_distance = 0.0;
  /// Each body's bounding sphere as placed: its centre of mass and its outer radius [m]. (A box's or
  /// cylinder's collision margin lies inside it, a hull has none: GJK never sees a shape larger than it is.)
  std::vector<Eigen::Vector4d> bounding_spheres;

  // btCollisionDispatcher::defaultNearCallback, with the result's distance threshold set.
  static void nearCallback(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info) {
    auto* a = static_cast<btCollisionObject*>(pair.m_pProxy0->m_clientObject);
    auto* b = static_cast<btCollisionObject*>(pair.m_pProxy1->m_clientObject);
    if (!dispatcher.needsCollision(a, b)) return;
    // Two bodies whose bounding spheres are farther apart than the near distance have no point within it:
    // one subtraction instead of a GJK query. The broad phase pairs boxes fattened for motion (Bullet's
    // tree margin and velocity prediction), so in a pile most of its pairs are such.
    auto& near = static_cast<NearDispatcher&>(dispatcher);
    const auto i = static_cast<std::size_t>(a->getUserIndex()), j = static_cast<std::size_t>(b->getUserIndex());
    if (i < near.bounding_spheres.size() && j < near.bounding_spheres.size()) {
      const Eigen::Vector4d& s_i = near.bounding_spheres[i];
      const Eigen::Vector4d& s_j = near.bounding_spheres[j];
      if ((s_i.head<3>() - s_j.head<3>()).norm() - s_i[3] - s_j[3] > near.near_distance) return;
    }
    btCollisionObjectWrapper a_wrap(nullptr, a->getCollisionShape(), a, a->getWorldTransform(), -1, -1);
    btCollisionObjectWrapper b_wrap(nullptr, b->getCollisionShape(), b, b->getWorldTransform(), -1, -1);
    if (!pair.m_algorithm) pair.m_algorithm = dispatcher.findAlgorithm(&a_wrap, &b_wrap, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    if (!pair.m_algorithm) return;
    btManifoldResult result(&a_wrap, &b_wrap);
    result.m_closestPointDistanceThreshold = static_cast<NearDispatcher&>(dispatcher).near_distance;
    pair.m_algorithm->processCollision(&a_wrap, &b_wrap, info, &result);
  }
};

// How much farther out than the one query's point face clipping may put a pair's deepest point [m]: well
// above EPA's accuracy on a face, far below any shape's size.
constexpr double kFaceDepthTolerance = 1e-4;

// Box–box (btBoxBoxDetector: a face's points in one pass), sphere–sphere and sphere–box keep Bullet's
// dedicated algorithms; the other convex pairs get one query and face clipping. (A triangle of an
// environment mesh keeps the multi-point mode: its pairs are not registered here.)
bool hasDedicatedAlgorithm(int a, int b) {
  const auto box_or_sphere = [](int type) { return type == BOX_SHAPE_PROXYTYPE || type == SPHERE_SHAPE_PROXYTYPE; };
  return box_or_sphere(a) && box_or_sphere(b);
}

}  // namespace

struct CollisionWorld::Impl {
  btDefaultCollisionConfiguration configuration;
  // One GJK/EPA query per pair of the shapes whose faces give the points (face_manifold.hpp): Bullet's
  // convex–convex algorithm with its perturbation turned off.
  btGjkEpaPenetrationDepthSolver penetration_solver;
  btConvexConvexAlgorithm::CreateFunc one_query{&penetration_solver};
  NearDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btTriangleMesh>> triangle_meshes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;  // bodies first, then the environment
  std::vector<btTransform> body_offsets;                     // X_BS of each body's shape
  std::size_t body_count = 0;
  // Half-spaces are not in Bullet's world: a plane meets a body at the body's features (below).
  struct Plane {
    Eigen::Vector3d normal;
    double offset;
    std::size_t object;
  };
  std::vector<Plane> planes;
  std::vector<int> plane_of_object;  // per object: its index in planes, or −1
  std::vector<CollisionShape> body_shapes;
  std::vector<Eigen::Isometry3d> shape_poses;  // X_WS of each body's shape as last placed
  std::vector<Eigen::Vector3d> body_origins;   // p_WB of each body as last placed
  std::vector<double> body_reach;              // each body's outer radius about its origin [m]
  std::vector<char> asleep;                    // per body: left out of detection (setAsleep)
  std::vector<HullFaces> hull_faces;           // per body: its hull's faces (kMesh), else empty
  std::vector<CollisionShape> environment_shapes;  // without their triangles: what face clipping reads
  SupportFace face_a, face_b;                  // scratch of the face clipping
  std::vector<ContactPoint> pair_points, clipped_points;  // scratch of pairDistance()

  Impl() {
    // A face resting on a face needs several points in one pass. Convex pairs get them by face clipping
    // after one query (registered below, for detection and for pairDistance); a shape on a triangle of an
    // environment mesh, and box pairs' closest points, by perturbing the orientation (Bullet's multi-point
    // iterations).
    configuration.setPlaneConvexMultipointIterations(4, 4);
    configuration.setConvexConvexMultipointIterations(4, 4);
    one_query.m_numPerturbationIterations = 0;
    one_query.m_minimumPointsPerturbationThreshold = 0;
    const int convex[] = {BOX_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE, CAPSULE_SHAPE_PROXYTYPE,
                          CONVEX_HULL_SHAPE_PROXYTYPE, SPHERE_SHAPE_PROXYTYPE};
    for (const int first : convex) {
      for (const int second : convex) {
        if (hasDedicatedAlgorithm(first, second)) continue;
        dispatcher.registerCollisionCreateFunc(first, second, &one_query);
        dispatcher.registerClosestPointsCreateFunc(first, second, &one_query);
      }
    }
    // Objects enter the tree without pairing: the broad phase pairs them all at the first detection, after
    // the start-up check (placementConflict) has refused a scene whose bodies sit inside each other. Paired
    // as they entered, 5 000 bodies at one point made 12.5 million pairs (gigabytes) before any check.
    broadphase.m_deferedcollide = true;
  }

  std::unique_ptr<btCollisionShape> makeShape(const CollisionShape& shape, bool in_environment) {
    const Eigen::Vector3d& s = shape.size;
    switch (shape.type) {
      case ShapeType::kPlane:
        return std::make_unique<btStaticPlaneShape>(toBt(shape.normal.normalized()), shape.offset);
      case ShapeType::kBox: {
        auto box = std::make_unique<btBoxShape>(toBt(0.5 * s));
        box->setMargin(marginFor(s.minCoeff()));
        return box;
      }
      case ShapeType::kSphere:
        return std::make_unique<btSphereShape>(s.x());
      case ShapeType::kCylinder: {
        auto cylinder = std::make_unique<btCylinderShapeZ>(btVector3(s.x(), s.x(), 0.5 * s.y()));
        cylinder->setMargin(marginFor(std::min(s.x(), 0.5 * s.y())));
        return cylinder;
      }
      case ShapeType::kCapsule:
        return std::make_unique<btCapsuleShapeZ>(s.x(), s.y());
      case ShapeType::kMesh: {
        if (in_environment) {
          auto mesh = std::make_unique<btTriangleMesh>();
          for (const auto& t : shape.mesh.triangles) {
            mesh->addTriangle(toBt(shape.mesh.vertices[t[0]]), toBt(shape.mesh.vertices[t[1]]),
                              toBt(shape.mesh.vertices[t[2]]));
          }
          auto bvh = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), true);
          triangle_meshes.push_back(std::move(mesh));
          return bvh;
        }
        // A moving mesh collides as its convex hull (docs/contact.md): the narrow phases for convex
        // shapes are exact and fast; a concave body needs a convex decomposition given as the shape. The
        // constructor has made shape.mesh the hull's vertices.
        return hullShape(shape.mesh.vertices);
      }
    }
    throw std::invalid_argument("unknown collision shape type");
  }

  // `X_WB`: a body's pose, set before the object enters the broad phase (an object added at the origin would
  // pair with every other one there first: N² pairs for a large scene).
  btCollisionObject* add(const CollisionShape& shape, bool in_environment, int id, const btTransform& X_WB) {
    plane_of_object.push_back(shape.type == ShapeType::kPlane ? static_cast<int>(planes.size()) : -1);
    if (shape.type == ShapeType::kPlane) {
      planes.push_back({shape.normal.normalized(), shape.offset, static_cast<std::size_t>(id)});
      shapes.push_back(nullptr);
      objects.push_back(nullptr);
      return nullptr;
    }
    shapes.push_back(makeShape(shape, in_environment));
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shapes.back().get());
    object->setUserIndex(id);
    if (in_environment) {
      object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
      // Inactive, as Bullet's own static objects are: its dispatcher skips a pair of two inactive objects,
      // so a sleeping body (setAsleep) on the environment costs no narrow phase.
      object->setActivationState(ISLAND_SLEEPING);
      if (shape.type != ShapeType::kPlane) object->setWorldTransform(toBt(shape.pose));
    } else {
      object->setActivationState(DISABLE_DEACTIVATION);
      object->setWorldTransform(X_WB * toBt(shape.pose));
    }
    // Static objects never test each other: bodies are in the default group, the environment in the static.
    const int group = in_environment ? btBroadphaseProxy::StaticFilter : btBroadphaseProxy::DefaultFilter;
    const int mask = in_environment ? btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter
                                    : btBroadphaseProxy::AllFilter;
    world.addCollisionObject(object.get(), group, mask);
    objects.push_back(std::move(object));
    return objects.back().get();
  }

};

CollisionWorld::CollisionWorld(const std::vector<CollisionShape>& environment, const std::vector<CollisionShape>& bodies,
                               const std::vector<Eigen::Isometry3d>& body_poses)
    : impl_(std::make_unique<Impl>()) {
  impl_->body_count = bodies.size();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    impl_->body_shapes.push_back(bodies[i]);
    CollisionShape& shape = impl_->body_shapes.back();
    if (shape.type == ShapeType::kMesh) {  // only the hull's vertices can touch anything
      shape.mesh.vertices = hullVertices(bodies[i].mesh.vertices);
      shape.mesh.triangles.clear();
      impl_->hull_faces.push_back(hullFaces(shape.mesh.vertices));
    } else {
      impl_->hull_faces.emplace_back();
    }
    impl_->add(shape, false, static_cast<int>(i), toBt(body_poses[i]));
    impl_->body_offsets.push_back(toBt(bodies[i].pose));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    impl_->shape_poses.push_back(body_poses[i] * bodies[i].pose);
    impl_->body_origins.push_back(body_poses[i].translation());
    impl_->body_reach.push_back(outerRadius(bodies[i]));
  }
  impl_->asleep.assign(bodies.size(), 0);
  for (std::size_t i = 0; i < environment.size(); ++i) {
    impl_->add(environment[i], true, static_cast<int>(bodies.size() + i), btTransform::getIdentity());
    impl_->environment_shapes.push_back(environment[i]);
    impl_->environment_shapes.back().mesh = TriangleMesh();
  }
}

CollisionWorld::~CollisionWorld() {
  for (auto& object : impl_->objects) {
    if (object) impl_->world.removeCollisionObject(object.get());
  }
}

std::size_t CollisionWorld::bodyCount() const { return impl_->body_count; }

void CollisionWorld::setPose(std::size_t body, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB) {
  const btTransform X_WS = btTransform(toBt(q_WB), toBt(p_WB)) * impl_->body_offsets[body];
  impl_->objects[body]->setWorldTransform(X_WS);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q_WB.toRotationMatrix();
  pose.translation() = p_WB;
  impl_->shape_poses[body] = pose * impl_->body_shapes[body].pose;
  impl_->body_origins[body] = p_WB;
}

void CollisionWorld::setAsleep(std::size_t body, bool asleep) {
  if (impl_->asleep[body] == asleep) return;
  impl_->asleep[body] = asleep;
  impl_->objects[body]->forceActivationState(asleep ? ISLAND_SLEEPING : DISABLE_DEACTIVATION);
}

void CollisionWorld::bounds(std::size_t body, Eigen::Vector3d& low, Eigen::Vector3d& high) const {
  const btCollisionObject* object = impl_->objects[body].get();
  btVector3 lo, hi;
  object->getCollisionShape()->getAabb(object->getWorldTransform(), lo, hi);
  low = fromBt(lo);
  high = fromBt(hi);
}

void CollisionWorld::detect(std::vector<ContactPoint>& points, double max_distance) {
  points.clear();
  btCollisionDispatcher& dispatcher = impl_->dispatcher;
  // Each step's manifold is made afresh: Bullet's persistence drops the points of a sliding face when they
  // drift from where they were found; warm starting is the contact step's own (by matching points).
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) dispatcher.getManifoldByIndexInternal(m)->clearManifold();
  impl_->dispatcher.near_distance = std::max(0.0, max_distance);
  impl_->dispatcher.bounding_spheres.resize(impl_->body_count);
  for (std::size_t body = 0; body < impl_->body_count; ++body) {
    impl_->dispatcher.bounding_spheres[body] << impl_->body_origins[body], impl_->body_reach[body];
  }
  impl_->world.performDiscreteCollisionDetection();
  impl_->broadphase.m_deferedcollide = false;  // paired once as a whole; from now on as objects move
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    if (addFacePoints(*manifold, max_distance, points)) continue;
    const std::size_t first = points.size();
    for (int c = 0; c < manifold->getNumContacts(); ++c) {
      const btManifoldPoint& p = manifold->getContactPoint(c);
      if (p.getDistance() > max_distance) continue;
      const ContactPoint point = pointFrom(p, manifold->getBody0(), manifold->getBody1());
      if (sphereOf(manifold->getBody0()) != nullptr) {
        addSpherePoint(manifold->getBody0(), point, first, points);
      } else if (sphereOf(manifold->getBody1()) != nullptr) {
        addSpherePoint(manifold->getBody1(), point, first, points);
      } else {
        points.push_back(point);
      }
    }
  }
  // A half-space meets a body only if the body's bounding sphere reaches it: one dot product per plane and
  // body before any feature is looked at.
  for (std::size_t body = 0; body < impl_->body_count; ++body) {
    if (impl_->asleep[body]) continue;
    const Eigen::Vector3d& origin = impl_->body_origins[body];
    const double reach = impl_->body_reach[body] + max_distance;
    for (const Impl::Plane& plane : impl_->planes) {
      if (plane.normal.dot(origin) - plane.offset > reach) continue;
      planeContacts(body, plane.object, max_distance, points);
    }
  }
}

const CollisionShape* CollisionWorld::facedShape(std::size_t object, const HullFaces** hull,
                                                 const Eigen::Isometry3d** X_WS) const {
  const bool body = isBody(object);
  const CollisionShape& shape = body ? impl_->body_shapes[object] : impl_->environment_shapes[object - bodyCount()];
  const bool faced = shape.type == ShapeType::kBox || shape.type == ShapeType::kCylinder ||
                     shape.type == ShapeType::kCapsule || (shape.type == ShapeType::kMesh && body);
  if (!faced) return nullptr;
  *hull = shape.type == ShapeType::kMesh ? &impl_->hull_faces[object] : nullptr;
  *X_WS = body ? &impl_->shape_poses[object] : &shape.pose;
  return &shape;
}

bool CollisionWorld::addFacePoints(const btPersistentManifold& manifold, double max_distance,
                                   std::vector<ContactPoint>& points) {
  // The one query's point (the deepest, should the manifold hold more) gives the normal.
  int deepest = -1;
  for (int c = 0; c < manifold.getNumContacts(); ++c) {
    if (deepest < 0 || manifold.getContactPoint(c).getDistance() < manifold.getContactPoint(deepest).getDistance()) deepest = c;
  }
  if (deepest < 0) return false;
  const ContactPoint query = pointFrom(manifold.getContactPoint(deepest), manifold.getBody0(), manifold.getBody1());
  return addFacePoints(query, max_distance, points);
}

bool CollisionWorld::addFacePoints(const ContactPoint& query, double max_distance, std::vector<ContactPoint>& points) {
  const HullFaces *hull_a = nullptr, *hull_b = nullptr;
  const Eigen::Isometry3d *X_WA = nullptr, *X_WB = nullptr;
  const CollisionShape* shape_a = facedShape(query.a, &hull_a, &X_WA);
  const CollisionShape* shape_b = facedShape(query.b, &hull_b, &X_WB);
  if (shape_a == nullptr || shape_b == nullptr) return false;
  if (shape_a->type == ShapeType::kBox && shape_b->type == ShapeType::kBox) return false;  // btBoxBoxDetector's
  if (query.distance > max_distance) return false;
  supportingFace(*shape_a, hull_a, *X_WA, -query.normal, impl_->face_a);
  supportingFace(*shape_b, hull_b, *X_WB, query.normal, impl_->face_b);
  const std::size_t first = points.size();
  if (!clipFaces(impl_->face_a, impl_->face_b, query.normal, max_distance, query, points)) return false;
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

double CollisionWorld::planeContacts(std::size_t body, std::size_t plane_object, double max_distance,
                                     std::vector<ContactPoint>& points) const {
  const Impl::Plane* plane = &impl_->planes[static_cast<std::size_t>(impl_->plane_of_object[plane_object])];
  double smallest = max_distance;
  const Eigen::Vector3d& n = plane->normal;
  planeFeatures(impl_->body_shapes[body], impl_->shape_poses[body], n, [&](int feature, const Eigen::Vector3d& x) {
    const double distance = n.dot(x) - plane->offset;
    smallest = std::min(smallest, distance);
    if (distance > max_distance) return;
    ContactPoint point;
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

bool CollisionWorld::isPlane(std::size_t object) const {
  return !isBody(object) && impl_->objects[object] == nullptr;
}

namespace {

struct PairCollector : btCollisionWorld::ContactResultCallback {
  std::vector<ContactPoint>* points = nullptr;
  double smallest = 0.0;
  btScalar addSingleResult(btManifoldPoint& p, const btCollisionObjectWrapper* a, int, int,
                           const btCollisionObjectWrapper* b, int, int) override {
    smallest = std::min(smallest, static_cast<double>(p.getDistance()));
    if (points) points->push_back(pointFrom(p, a->getCollisionObject(), b->getCollisionObject()));
    return 0;
  }
};

}  // namespace

double CollisionWorld::pairDistance(std::size_t a, std::size_t b, double max_distance, std::vector<ContactPoint>* points) {
  if (isPlane(a) || isPlane(b)) {
    std::vector<ContactPoint> scratch;
    std::vector<ContactPoint>& out = points ? *points : scratch;
    out.clear();
    return isPlane(b) ? planeContacts(a, b, max_distance, out) : planeContacts(b, a, max_distance, out);
  }
  std::vector<ContactPoint>& found = impl_->pair_points;
  found.clear();
  PairCollector collector;
  collector.points = &found;
  collector.smallest = max_distance;
  collector.m_closestDistanceThreshold = max_distance;
  impl_->world.contactPairTest(impl_->objects[a].get(), impl_->objects[b].get(), collector);
  // A pair that face clipping serves gets its points, and its distance, as the detection does: from the
  // query's deepest point, on the exact surfaces (a located impact then meets a face with the whole face).
  const auto deepest = std::min_element(found.begin(), found.end(), [](const ContactPoint& x, const ContactPoint& y) {
    return x.distance < y.distance;
  });
  std::vector<ContactPoint>& out = points ? *points : impl_->clipped_points;
  out.clear();
  if (deepest != found.end() && addFacePoints(ContactPoint(*deepest), max_distance, out)) {
    double smallest = max_distance;
    for (const ContactPoint& point : out) smallest = std::min(smallest, point.distance);
    return smallest;
  }
  if (points) *points = found;
  return collector.smallest;
}

namespace {

struct BoxQuery : btBroadphaseAabbCallback {
  std::vector<std::size_t>* objects = nullptr;
  std::size_t self = 0;
  bool process(const btBroadphaseProxy* proxy) override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    const auto index = static_cast<std::size_t>(object->getUserIndex());
    if (index != self) objects->push_back(index);
    return true;
  }
};

}  // namespace

void CollisionWorld::objectsNear(std::size_t self, const Eigen::Vector3d& low, const Eigen::Vector3d& high,
                                 std::vector<std::size_t>& objects) const {
  objects.clear();
  BoxQuery query;
  query.objects = &objects;
  query.self = self;
  impl_->broadphase.aabbTest(toBt(low), toBt(high), query);
  // The box reaches the solid side n·x ≤ offset where its lowest corner along n does.
  const Eigen::Vector3d centre = 0.5 * (low + high), half = 0.5 * (high - low);
  for (const Impl::Plane& plane : impl_->planes) {
    if (plane.normal.dot(centre) - plane.normal.cwiseAbs().dot(half) <= plane.offset) objects.push_back(plane.object);
  }
}

bool CollisionWorld::insideClosedMesh(std::size_t object, const Eigen::Vector3d& p_W) const {
  if (isBody(object) || isPlane(object) || impl_->objects[object] == nullptr) return false;
  const btCollisionObject* mesh = impl_->objects[object].get();
  if (mesh->getCollisionShape()->getShapeType() != TRIANGLE_MESH_SHAPE_PROXYTYPE) return false;
  btVector3 low, high;
  mesh->getCollisionShape()->getAabb(mesh->getWorldTransform(), low, high);
  const Eigen::Vector3d lo = fromBt(low), hi = fromBt(high);
  if ((p_W.array() < lo.array()).any() || (p_W.array() > hi.array()).any()) return false;
  // A ray from the point to beyond the mesh's box crosses a closed surface an odd number of times from
  // inside (Jordan); the direction is one no mesh of axis-aligned or regular faces lines up with.
  const Eigen::Vector3d direction = Eigen::Vector3d(0.5773502691896258, 0.4082482904638631, 0.7071067811865476).normalized();
  const btVector3 from = toBt(p_W), to = toBt(p_W + 2.0 * (hi - lo).norm() * direction + direction);
  btCollisionWorld::AllHitsRayResultCallback hits(from, to);
  btTransform ray_from, ray_to;
  ray_from.setIdentity(), ray_to.setIdentity();
  ray_from.setOrigin(from), ray_to.setOrigin(to);
  btCollisionWorld::rayTestSingle(ray_from, ray_to, const_cast<btCollisionObject*>(mesh), mesh->getCollisionShape(),
                                  mesh->getWorldTransform(), hits);
  return hits.m_hitFractions.size() % 2 == 1;
}

void CollisionWorld::tangentBasis(const Eigen::Vector3d& normal, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  btVector3 a, b;
  btPlaneSpace1(toBt(normal), a, b);
  t1 = fromBt(a);
  t2 = fromBt(b);
}

}  // namespace contact
}  // namespace rigid_body
