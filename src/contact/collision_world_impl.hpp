// The inside of CollisionWorld, shared by its two source files (collision_world.cpp: the world, its objects
// and the detection; collision_pairs.cpp: one pair at a time, its distance and its points): Bullet's world,
// the dispatcher that asks narrow phases for near points, and the conversions. Bullet's headers appear here,
// in those two files and in convex_hull.cpp only.
#pragma once

#include <btBulletCollisionCommon.h>
#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <stdexcept>
#include <vector>

#include "collision_world.hpp"
#include "convex_hull.hpp"
#include "near_dispatcher.hpp"
#include "pair_reuse.hpp"
#include "shape_features.hpp"

namespace rigid_body {
namespace contact {

inline btVector3 toBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
inline Eigen::Vector3d fromBt(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }
inline btQuaternion toBt(const Eigen::Quaterniond& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
inline btTransform toBt(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.rotation());
  return btTransform(toBt(q), toBt(Eigen::Vector3d(X.translation())));
}

// GJK-based pairs round a convex shape's corners by its margin; Bullet's default (0.04 m) is large for
// small bodies, so the margin is a small fraction of the shape, at most 4 mm.
inline double marginFor(double smallest_extent) { return std::min(0.004, 0.05 * smallest_extent); }

inline ContactPoint pointFrom(const btManifoldPoint& p, const btCollisionObject* a, const btCollisionObject* b) {
  ContactPoint point;
  point.a = static_cast<std::size_t>(a->getUserIndex());
  point.b = static_cast<std::size_t>(b->getUserIndex());
  point.on_a = fromBt(p.getPositionWorldOnA());
  point.on_b = fromBt(p.getPositionWorldOnB());
  point.normal = fromBt(p.m_normalWorldOnB);
  point.distance = p.getDistance();
  return point;
}

// Which pairs face clipping from a GJK/EPA query serves (face_manifold.hpp), by Bullet's shape types: both
// shapes with faces to clip (a box, a cylinder's ends and side, a capsule's segment, a body's hull), except
// box–box, whose normal comes from the boxes' separating-axis test instead (CollisionWorld::addBoxPoints).
// The one rule for the query's reach below and for CollisionWorld::addFacePoints.
inline bool facedType(int type) {
  return type == BOX_SHAPE_PROXYTYPE || type == CYLINDER_SHAPE_PROXYTYPE || type == CAPSULE_SHAPE_PROXYTYPE ||
         type == CONVEX_HULL_SHAPE_PROXYTYPE;
}
inline bool boxBoxPair(int type_a, int type_b) {
  return type_a == BOX_SHAPE_PROXYTYPE && type_b == BOX_SHAPE_PROXYTYPE;
}
inline bool faceClippedPair(int type_a, int type_b) {
  return facedType(type_a) && facedType(type_b) && !boxBoxPair(type_a, type_b);
}

// How much farther than the near distance a pair's one query must look for face clipping to find what is
// within it [m]: a box's and a cylinder's collision margins round their edges and corners inside them, so
// GJK sees such an edge only once the exact edge is up to a margin deep (a box's edge tilted 20° with a
// 4 mm margin: 1.1 mm); the clipped points, on the exact surfaces, then decide. Zero for pairs
// that face clipping does not serve (box–box, spheres, triangles) and for shapes without such rounding (a
// capsule's margin is its radius, which GJK treats exactly; a hull has none).
inline double queryReach(const btCollisionObject& a, const btCollisionObject& b) {
  const int type_a = a.getCollisionShape()->getShapeType(), type_b = b.getCollisionShape()->getShapeType();
  if (!faceClippedPair(type_a, type_b)) return 0.0;
  const auto rounding = [](const btCollisionObject& object, int type) {
    return type == BOX_SHAPE_PROXYTYPE || type == CYLINDER_SHAPE_PROXYTYPE ? object.getCollisionShape()->getMargin() : 0.0;
  };
  return rounding(a, type_a) + rounding(b, type_b);
}

// Box–box (whose narrow phase the dispatcher skips: CollisionWorld::addBoxPoints), sphere–sphere and
// sphere–box keep Bullet's dedicated algorithms; the other convex pairs get one query and face clipping. (A triangle of an
// environment mesh keeps the multi-point mode: its pairs are not registered here.)
inline bool hasDedicatedAlgorithm(int a, int b) {
  const auto box_or_sphere = [](int type) { return type == BOX_SHAPE_PROXYTYPE || type == SPHERE_SHAPE_PROXYTYPE; };
  return box_or_sphere(a) && box_or_sphere(b);
}

// What the face clipping of one pair writes as it goes (one per thread of a detection).
struct CollisionWorld::PairScratch {
  SupportFace face_a, face_b;
  std::vector<ContactPoint> speculative_points;  // of addSpeculativePoints()
};

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
  // Per body: the half-spaces in its reach at its last full scan of them, and how far its origin may move
  // from where it was then before one out of reach could come into it (CollisionWorld::addPlanePoints).
  struct PlaneScan {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double reach = -1.0;  // none yet: the first detection scans
    double slack = 0.0;
    std::vector<std::size_t> near;
  };
  std::vector<PlaneScan> plane_scans;
  std::vector<int> plane_of_object;  // per object: its index in planes, or −1
  std::vector<CollisionShape> body_shapes;
  std::vector<Eigen::Isometry3d> shape_poses;  // X_WS of each body's shape as last placed
  std::vector<Eigen::Vector3d> body_origins;   // p_WB of each body as last placed
  std::vector<Eigen::Quaterniond> body_rotations;  // q_WB of each body as last placed (NaN: not yet)
  std::vector<double> body_reach;              // each body's outer radius about its origin [m]
  std::vector<char> asleep;                    // per body: left out of detection (setAsleep)
  // Per body: asleep, placed elsewhere since its bounding box was last put in the broad phase. Set by
  // setPose, which may run on the pool (each block placing its own bodies); the boxes are updated in body
  // order on the caller (updateStaleBounds): Bullet's broad phase takes no concurrent updates, and the order
  // of its updates decides the order of its pairs, and so of the points and of the solve's rounding.
  std::vector<char> stale_bounds;
  std::atomic<bool> any_stale_bounds{false};
  std::vector<HullFaces> hull_faces;           // per body: its hull's faces (kMesh), else empty
  std::vector<CollisionShape> environment_shapes;  // without their triangles: what face clipping reads
  // Per environment object: a mesh's triangles in the world (else empty), for clipping a body's face
  // against the triangle it touches (CollisionWorld::addTrianglePoints).
  std::vector<std::vector<std::array<Eigen::Vector3d, 3>>> environment_triangles;
  // Per manifold of the dispatcher (its index, btPersistentManifold::m_index1a): the points of a box pair
  // or a face-clipped pair as last detected, reused while the pair stays put (pair_reuse.hpp). When a
  // manifold is released another takes its index; the stored points then name another pair, and its own
  // check refuses them.
  std::vector<PairReuse> pair_reuse;
  bool reuse_points = true;
  // Per object: its shape's outer radius about the shape's origin (the environment's: infinite, for
  // PairReuse, which then bounds the motion by the body's).
  std::vector<double> shape_reach;
  PairScratch scratch;                         // of pairDistance() and of a detection on one thread
  std::vector<ContactPoint> pair_points, clipped_points;  // scratch of pairDistance() (points it returns to no one)
  // A detection on the pool: each block of manifolds or of bodies on the half-spaces makes its points in a
  // list of its own, with its own scratch; the lists are joined in block order.
  struct DetectBlock {
    PairScratch scratch;
    std::vector<ContactPoint> points;
  };
  std::vector<DetectBlock> detect_blocks;
  std::vector<std::size_t> block_offsets;  // where each block's points go in the joined list (then the total)

  Impl() {
    // A face resting on a face needs several points in one pass. Convex pairs get them by face clipping
    // after one query (registered below, for detection and for pairDistance), two boxes from their
    // separating axis (CollisionWorld::addBoxPoints); a shape on a triangle of an environment mesh by
    // perturbing the orientation (Bullet's multi-point iterations).
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

}  // namespace contact
}  // namespace rigid_body
