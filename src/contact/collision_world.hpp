// The collision library behind the contact step: Bullet's collision module (double precision), used for what
// it is made for: a dynamic AABB tree broad phase, narrow phases per shape pair (one GJK/EPA query whose
// normal face clipping turns into the pair's points, face_manifold.hpp; for two boxes a separating-axis test
// of our own gives that normal, box_separation.hpp; Bullet's own sphere algorithms), pair distances and box
// queries. Nothing of Bullet leaves its sources (collision_world.cpp, collision_pairs.cpp,
// speculative_points.cpp, near_dispatcher.cpp, their collision_world_impl.hpp, and convex_hull.cpp); the
// rest of the core sees Eigen types.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"

class btPersistentManifold;

namespace rigid_body {

class ThreadPool;

namespace contact {

struct HullFaces;
class PairReuse;

/// One point of contact between two collision objects. Objects 0 … bodies−1 are the colliding bodies (in
/// the order given), the rest the environment shapes.
struct ContactPoint {
  std::size_t a = 0, b = 0;
  Eigen::Vector3d on_a = Eigen::Vector3d::Zero();     ///< witness point on a's surface, world [m]
  Eigen::Vector3d on_b = Eigen::Vector3d::Zero();     ///< witness point on b's surface, world [m]
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< from b towards a, unit
  double distance = 0.0;                              ///< signed: < 0 when penetrating [m]
  int feature = -1;  ///< against a half-space: which feature of the body's shape (the same from step to step)
  /// Farther than detect's max_distance, from a pair touching within it: a point of the pair's faces that
  /// may arrive within the step (docs/contact.md, step 2, "speculative points").
  bool speculative = false;
};

class CollisionWorld {
 public:
  /// `bodies[i]` is the shape of colliding body i (its pose is in the body frame), `body_poses[i]` where the
  /// body starts (X_WB).
  CollisionWorld(const std::vector<CollisionShape>& environment, const std::vector<CollisionShape>& bodies,
                 const std::vector<Eigen::Isometry3d>& body_poses);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  std::size_t bodyCount() const;
  bool isBody(std::size_t object) const { return object < bodyCount(); }

  /// Places body i's shape for the body at (p_WB, q_WB); nothing to do if it stands there already (a
  /// sleeping body, every step). Safe on the pool for distinct bodies; everything else here runs on the
  /// caller.
  void setPose(std::size_t body, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB);

  /// A sleeping body keeps its pose and is left out of detection: no pair of it with the environment or
  /// another sleeping body is tested (a pair with an awake body still is).
  void setAsleep(std::size_t body, bool asleep);

  /// Body i's bounding box in the world as its pose is set.
  void bounds(std::size_t body, Eigen::Vector3d& low, Eigen::Vector3d& high) const;

  /// Broad and narrow phase on the poses as set: every contact point no farther apart than `max_distance`
  /// goes to `points` (cleared first), made afresh (no memory of the last call). A pair with such a point
  /// whose shapes have faces (boxes, cylinders, capsules, hulls; a body on a half-space), and one of whose
  /// bodies is `moving` (per body: its points may close more than max_distance within the step), also
  /// gives the points of its faces up to `speculative_distance` apart, marked speculative, after its others.
  /// With a `pool`, the pairs' narrow phases go to it in blocks of `block` pairs, their manifolds' points in
  /// blocks of 2 × `block` manifolds and the half-spaces' in blocks of 16 × `block` bodies (the scene's
  /// bodies per block: 64 by default, any size from 1); the list is the same on any number of threads.
  void detect(std::vector<ContactPoint>& points, double max_distance, double speculative_distance = 0.0,
              const std::vector<char>* moving = nullptr, ThreadPool* pool = nullptr, std::size_t block = 64);

  /// Whether detect keeps a pair's points for the next detection while the pair stays put (pair_reuse.hpp;
  /// on unless set off).
  void setReusePoints(bool reuse);

  /// How many pairs the last detect gave the points kept from an earlier one (pair_reuse.hpp): two boxes,
  /// or two shapes whose points come from face clipping, that had not moved relative to each other.
  std::size_t reusedPairs() const;

  /// Whether an environment object is a half-space (handled here in closed form, not by Bullet).
  bool isPlane(std::size_t object) const;

  /// The closest points of two objects at their poses as set, no farther apart than `max_distance` [m];
  /// none if they are farther (a pair that face clipping serves: its clipped points, as detect gives them).
  /// Returns the smallest signed distance, or +max_distance.
  double pairDistance(std::size_t a, std::size_t b, double max_distance, std::vector<ContactPoint>* points);

  /// Every object but `self` whose bounding box in the broad phase (as of the last detect) meets the box
  /// [low, high], and every half-space whose solid side the box reaches, into `objects` (cleared first).
  void objectsNear(std::size_t self, const Eigen::Vector3d& low, const Eigen::Vector3d& high,
                   std::vector<std::size_t>& objects) const;

  /// Whether a point lies inside an environment object that is a (closed) triangle mesh: no surface of it
  /// need be near a body wholly inside, so no pair distance tells.
  bool insideClosedMesh(std::size_t object, const Eigen::Vector3d& p_W) const;

  /// The tangent basis the friction impulses of a point are expressed in (a function of the normal alone,
  /// so that it is the same from step to step while the normal is).
  static void tangentBasis(const Eigen::Vector3d& normal, Eigen::Vector3d& t1, Eigen::Vector3d& t2);

 private:
  /// Puts the bounding boxes of sleeping bodies placed elsewhere into the broad phase, in body order.
  void updateStaleBounds() const;

  struct PairScratch;
  /// What one detection asks: the near distance, and where the pairs of moving bodies get speculative
  /// points (`speculative` false: none).
  struct DetectRequest {
    double max_distance = 0.0;
    double speculative_distance = 0.0;
    const std::vector<char>* moving = nullptr;
    bool speculative = false;
  };
  /// One manifold's points (detect's first loop), and one body's on the half-spaces (its second).
  void addManifoldPoints(int manifold, const DetectRequest& request, PairScratch& scratch,
                         std::vector<ContactPoint>& points);
  void addPlanePoints(std::size_t body, const DetectRequest& request, std::vector<ContactPoint>& points);
  /// Whether a speculative request covers the pair of points[first] (one of its bodies moves).
  bool movesInStep(const DetectRequest& request, const std::vector<ContactPoint>& points, std::size_t first) const;
  /// The body's features within max_distance of the half-space (and beyond `beyond`: those are marked
  /// speculative); returns the smallest distance, or max_distance.
  double planeContacts(std::size_t body, std::size_t plane_object, double max_distance, std::vector<ContactPoint>& points,
                       double beyond = -std::numeric_limits<double>::infinity()) const;
  /// A pair's speculative points: points[first…] are the pair's, at least one within max_distance. Its
  /// faces' points farther apart than `beyond` are added (those within max_distance as ordinary points):
  /// max_distance for a pair whose points came from face clipping (box pairs included), 0 for a pair whose
  /// narrow phase gave others.
  void addSpeculativePoints(std::size_t first, double max_distance, double speculative_distance, double beyond,
                            PairScratch& scratch, std::vector<ContactPoint>& points);
  /// The shape of an object whose faces give its contact points (faceClippedPair in collision_world_impl.hpp
  /// decides which), with its hull's faces (kMesh) and its pose.
  const CollisionShape* facedShape(std::size_t object, const HullFaces** hull, const Eigen::Isometry3d** X_WS) const;
  /// Where an object's shape stands (X_WS): a body's as last placed, the environment's own.
  const Eigen::Isometry3d& shapePose(std::size_t object) const;
  /// Bullet's shape type of an object (its proxy type), or −1 for a half-space (not in Bullet's world).
  int proxyType(std::size_t object) const;
  /// The pair's faces along the query's normal, clipped (face_manifold.hpp): their points up to
  /// max_distance apart appended to `points`; false where the faces make none.
  bool clipPairFaces(const ContactPoint& query, double max_distance, PairScratch& scratch,
                     std::vector<ContactPoint>& points);
  /// A pair's points by face clipping from the normal of its one query's point (face_manifold.hpp), or of
  /// its manifold's deepest; false, adding nothing, where the pair's shapes or faces do not make them.
  bool addFacePoints(const ContactPoint& query, double max_distance, PairScratch& scratch,
                     std::vector<ContactPoint>& points);
  /// The manifold's: with `reuse`, the points kept there when the dispatcher found the pair had not moved
  /// (pairStandsStill), else made from its query and kept there.
  bool addFacePoints(const btPersistentManifold& manifold, double max_distance, PairReuse& reuse,
                     PairScratch& scratch, std::vector<ContactPoint>& points);
  /// Whether a pair's points from its last detection stand (pair_reuse.hpp), asked by the dispatcher before
  /// the pair's narrow phase: a queried pair's query is then skipped, and the detection gives back the
  /// points kept (addFacePoints, addBoxPoints).
  bool pairStandsStill(const btPersistentManifold& manifold, double max_distance);
  /// Whether both objects are boxes.
  bool boxPair(std::size_t a, std::size_t b) const;
  /// Two boxes: their points within max_distance by face clipping along their best separating axis
  /// (box_separation.hpp), or the nearest points of two edges across each other; returns whether it added
  /// any. The manifold's: false, adding nothing, for a pair that is not two boxes or that the detection did
  /// not test (asleep, or beyond the near distance).
  bool addBoxPoints(std::size_t a, std::size_t b, double max_distance, PairScratch& scratch,
                    std::vector<ContactPoint>& points);
  /// With `reuse`, the points kept there when the dispatcher found the pair had not moved (pairStandsStill),
  /// else made and kept there.
  bool addBoxPoints(const btPersistentManifold& manifold, double max_distance, PairReuse& reuse, PairScratch& scratch,
                    std::vector<ContactPoint>& points);
  /// A body on an environment mesh: for each triangle that holds a point of the manifold, the body's face
  /// along the triangle's deepest point's normal clipped against the triangle (the triangle's own point
  /// where they are not faces along it), at most four points for the pair; false, adding nothing, where the
  /// pair is not a faced body on a mesh.
  bool addTrianglePoints(const btPersistentManifold& manifold, double max_distance, PairScratch& scratch,
                         std::vector<ContactPoint>& points);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace contact
}  // namespace rigid_body
