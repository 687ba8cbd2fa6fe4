#include "collision_world.hpp"

#include <cmath>
#include <limits>

#include "collision_world_impl.hpp"
#include "face_manifold.hpp"
#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

namespace {

// A detection on the pool hands out blocks of this many times the scene's block of manifolds, or of bodies
// on the half-spaces: a manifold's points and a body's plane test are less work than a pair's narrow phase.
constexpr std::size_t kManifoldBlocks = 2;
constexpr std::size_t kPlaneBlocks = 16;

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

}  // namespace

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
    impl_->body_rotations.emplace_back(Eigen::Vector4d::Constant(std::numeric_limits<double>::quiet_NaN()));
    impl_->body_reach.push_back(outerRadius(bodies[i]));
    CollisionShape about_origin = impl_->body_shapes[i];
    about_origin.pose = Eigen::Isometry3d::Identity();
    impl_->shape_reach.push_back(outerRadius(about_origin));
  }
  impl_->asleep.assign(bodies.size(), 0);
  impl_->stale_bounds.assign(bodies.size(), 0);
  impl_->world.setForceUpdateAllAabbs(false);  // only active objects: awake bodies (setPose)
  impl_->plane_scans.resize(bodies.size());
  for (std::size_t i = 0; i < environment.size(); ++i) {
    impl_->add(environment[i], true, static_cast<int>(bodies.size() + i), btTransform::getIdentity());
    impl_->shape_reach.push_back(std::numeric_limits<double>::infinity());
    impl_->environment_shapes.push_back(environment[i]);
    impl_->environment_triangles.emplace_back();
    if (environment[i].type == ShapeType::kMesh) {
      for (const auto& t : environment[i].mesh.triangles) {
        const auto& v = environment[i].mesh.vertices;
        const Eigen::Isometry3d& X = environment[i].pose;
        impl_->environment_triangles.back().push_back({X * v[t[0]], X * v[t[1]], X * v[t[2]]});
      }
    }
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
  if (impl_->body_origins[body] == p_WB && impl_->body_rotations[body].coeffs() == q_WB.coeffs()) return;
  btCollisionObject& object = *impl_->objects[body];
  object.setWorldTransform(btTransform(toBt(q_WB), toBt(p_WB)) * impl_->body_offsets[body]);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q_WB.toRotationMatrix();
  pose.translation() = p_WB;
  impl_->shape_poses[body] = pose * impl_->body_shapes[body].pose;
  impl_->body_origins[body] = p_WB;
  impl_->body_rotations[body] = q_WB;
  // The detection updates the bounding boxes of awake bodies only (setForceUpdateAllAabbs(false) in the
  // constructor: a sleeping body's stays, and costs nothing); a sleeping body placed elsewhere (moved by the
  // solve in the step it fell asleep, a state set from outside, a placement test) has its box updated before
  // the broad phase is next read (updateStaleBounds).
  if (impl_->asleep[body]) {
    impl_->stale_bounds[body] = 1;
    impl_->any_stale_bounds.store(true, std::memory_order_relaxed);
  }
}

void CollisionWorld::updateStaleBounds() const {
  if (!impl_->any_stale_bounds.load(std::memory_order_relaxed)) return;
  impl_->any_stale_bounds.store(false, std::memory_order_relaxed);
  for (std::size_t body = 0; body < impl_->body_count; ++body) {
    if (!impl_->stale_bounds[body]) continue;
    impl_->stale_bounds[body] = 0;
    impl_->world.updateSingleAabb(impl_->objects[body].get());
  }
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

void CollisionWorld::detect(std::vector<ContactPoint>& points, double max_distance, double speculative_distance,
                            const std::vector<char>* moving, ThreadPool* pool, std::size_t block) {
  points.clear();
  NearDispatcher& dispatcher = impl_->dispatcher;
  // Each step's manifold is made afresh: Bullet's persistence drops the points of a sliding face when they
  // drift from where they were found; warm starting is the contact step's own (by matching points). Each
  // manifold its own: over the pool.
  const auto known = static_cast<std::size_t>(dispatcher.getNumManifolds());
  forEachRange(pool, known, scaledBlock(std::max<std::size_t>(1, block), kManifoldBlocks),
               [&](std::size_t, std::size_t first, std::size_t end) {
                 for (std::size_t m = first; m < end; ++m) {
                   dispatcher.getManifoldByIndexInternal(static_cast<int>(m))->clearManifold();
                 }
               });
  dispatcher.near_distance = std::max(0.0, max_distance);
  dispatcher.bounding_spheres.resize(impl_->body_count);
  for (std::size_t body = 0; body < impl_->body_count; ++body) {
    dispatcher.bounding_spheres[body] << impl_->body_origins[body], impl_->body_reach[body];
  }
  block = std::max<std::size_t>(1, block);
  updateStaleBounds();
  dispatcher.pool = pool;
  dispatcher.pairs_per_block = block;
  for (PairReuse& pair : impl_->pair_reuse) pair.forget();
  if (impl_->reuse_points) {
    dispatcher.stands_still = [this, max_distance](const btPersistentManifold& manifold) {
      return pairStandsStill(manifold, max_distance);
    };
  }
  impl_->world.performDiscreteCollisionDetection();
  dispatcher.stands_still = nullptr;
  dispatcher.pool = nullptr;
  impl_->broadphase.m_deferedcollide = false;  // paired once as a whole; from now on as objects move
  // A pair (or a body on a half-space) with a point within max_distance, one of whose bodies moves: its
  // faces may hold more points that arrive within the step.
  DetectRequest request;
  request.max_distance = max_distance;
  request.speculative_distance = speculative_distance;
  request.moving = moving;
  request.speculative = speculative_distance > max_distance && moving != nullptr;
  const auto manifolds = static_cast<std::size_t>(dispatcher.getNumManifolds());
  if (impl_->pair_reuse.size() < manifolds) impl_->pair_reuse.resize(manifolds);
  const std::size_t per_manifold_block = scaledBlock(block, kManifoldBlocks);
  const std::size_t per_body_block = scaledBlock(block, kPlaneBlocks);
  const std::size_t manifold_blocks = blockCount(manifolds, per_manifold_block);
  const std::size_t body_blocks = impl_->planes.empty() ? 0 : blockCount(impl_->body_count, per_body_block);
  const std::size_t blocks = manifold_blocks + body_blocks;
  if (pool == nullptr || pool->threads() == 1 || blocks < 2) {
    for (std::size_t m = 0; m < manifolds; ++m) addManifoldPoints(static_cast<int>(m), request, impl_->scratch, points);
    for (std::size_t body = 0; body < impl_->body_count; ++body) addPlanePoints(body, request, points);
    return;
  }
  // On the pool each block of manifolds, or of bodies on the half-spaces, makes its points in a list of its
  // own; joined in block order they are the list the loops above make.
  if (impl_->detect_blocks.size() < blocks) impl_->detect_blocks.resize(blocks);
  pool->parallelFor(blocks, [&](std::size_t b) {
    Impl::DetectBlock& out = impl_->detect_blocks[b];
    out.points.clear();
    if (b < manifold_blocks) {
      const std::size_t first = b * per_manifold_block;
      const std::size_t end = blockEnd(first, per_manifold_block, manifolds);
      for (std::size_t m = first; m < end; ++m) addManifoldPoints(static_cast<int>(m), request, out.scratch, out.points);
    } else {
      const std::size_t first = (b - manifold_blocks) * per_body_block;
      const std::size_t end = blockEnd(first, per_body_block, impl_->body_count);
      for (std::size_t body = first; body < end; ++body) addPlanePoints(body, request, out.points);
    }
  });
  // Joined in block order, each block copied to its place over the pool.
  impl_->block_offsets.assign(blocks + 1, 0);
  for (std::size_t b = 0; b < blocks; ++b) {
    impl_->block_offsets[b + 1] = impl_->block_offsets[b] + impl_->detect_blocks[b].points.size();
  }
  points.resize(impl_->block_offsets[blocks]);
  pool->parallelFor(blocks, [&](std::size_t b) {
    const std::vector<ContactPoint>& made = impl_->detect_blocks[b].points;
    std::copy(made.begin(), made.end(), points.begin() + static_cast<std::ptrdiff_t>(impl_->block_offsets[b]));
  });
}

bool CollisionWorld::movesInStep(const DetectRequest& request, const std::vector<ContactPoint>& points,
                                 std::size_t first) const {
  if (!request.speculative || points.size() <= first) return false;
  const auto moves = [&](std::size_t object) { return isBody(object) && (*request.moving)[object] != 0; };
  return moves(points[first].a) || moves(points[first].b);
}

void CollisionWorld::addManifoldPoints(int m, const DetectRequest& request, PairScratch& scratch,
                                       std::vector<ContactPoint>& points) {
  const btPersistentManifold* manifold = impl_->dispatcher.getManifoldByIndexInternal(m);
  // Two inactive objects (sleeping bodies, the environment) are not tested (Bullet's needsCollision), and
  // their manifold was cleared above: a sleeping island's pairs cost this test alone.
  if (!manifold->getBody0()->isActive() && !manifold->getBody1()->isActive()) return;
  const double max_distance = request.max_distance;
  const std::size_t first = points.size();
  PairReuse& reuse = impl_->pair_reuse[static_cast<std::size_t>(m)];
  if (addBoxPoints(*manifold, max_distance, reuse, scratch, points) ||
      addFacePoints(*manifold, max_distance, reuse, scratch, points) ||
      addTrianglePoints(*manifold, max_distance, scratch, points)) {
    if (movesInStep(request, points, first)) {
      addSpeculativePoints(first, max_distance, request.speculative_distance, max_distance, scratch, points);
    }
    return;
  }
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
  if (movesInStep(request, points, first)) {
    addSpeculativePoints(first, max_distance, request.speculative_distance, 0.0, scratch, points);
  }
}

void CollisionWorld::addPlanePoints(std::size_t body, const DetectRequest& request, std::vector<ContactPoint>& points) {
  // A half-space meets a body only if the body's bounding sphere reaches it: n·origin − offset ≤ reach.
  if (impl_->asleep[body]) return;
  const Eigen::Vector3d& origin = impl_->body_origins[body];
  const double reach = impl_->body_reach[body] + request.max_distance;
  Impl::PlaneScan& scan = impl_->plane_scans[body];
  // The planes out of reach at the last scan stay out of it while the body's origin is nearer than `slack`
  // to where it was then (n·x changes by at most |Δx| for a unit n): only the planes in reach then are
  // tested, and 2 000 planes far away cost what one does. Strictly nearer, less a rounding margin, so that
  // every test comes out as a full scan's would.
  const bool rescan = !(scan.reach == reach && (origin - scan.origin).squaredNorm() < scan.slack * scan.slack);
  if (rescan) {
    scan.origin = origin;
    scan.reach = reach;
    scan.slack = std::numeric_limits<double>::infinity();
    scan.near.clear();
    for (std::size_t k = 0; k < impl_->planes.size(); ++k) {
      const double gap = impl_->planes[k].normal.dot(origin) - impl_->planes[k].offset - reach;
      if (gap > 0.0) {
        scan.slack = std::min(scan.slack, std::max(0.0, gap * (1.0 - 1e-12) - 1e-12));
      } else {
        scan.near.push_back(k);
      }
    }
  }
  for (const std::size_t k : scan.near) {
    const Impl::Plane& plane = impl_->planes[k];
    if (plane.normal.dot(origin) - plane.offset > reach) continue;
    const std::size_t first = points.size();
    planeContacts(body, plane.object, request.max_distance, points);
    if (movesInStep(request, points, first)) {
      planeContacts(body, plane.object, request.speculative_distance, points, request.max_distance);
    }
  }
}

void CollisionWorld::setReusePoints(bool reuse) { impl_->reuse_points = reuse; }

std::size_t CollisionWorld::reusedPairs() const {
  std::size_t reused = 0;
  for (const PairReuse& pair : impl_->pair_reuse) reused += pair.reused() ? 1 : 0;
  return reused;
}

bool CollisionWorld::isPlane(std::size_t object) const {
  return !isBody(object) && impl_->objects[object] == nullptr;
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
  updateStaleBounds();
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
