// Which collision library for the contact step: Bullet's collision module (double build) against FCL 0.7 on
// the queries contact needs, timed and with the number of points each returns. Built only when FCL is
// installed (apt-get install libfcl-dev); the numbers are quoted in docs/contact.md.
//   ws/devel/lib/rigid_body_sim/collision_libraries
#include <btBulletCollisionCommon.h>
#include <fcl/fcl.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>

namespace {

double nanosecondsPer(int repetitions, const std::function<void()>& query) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < repetitions; ++i) query();
  const std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count() / repetitions;
}

struct Counter : btCollisionWorld::ContactResultCallback {
  int points = 0;
  btScalar addSingleResult(btManifoldPoint&, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*,
                           int, int) override {
    ++points;
    return 0;
  }
};

}  // namespace

int main() {
  constexpr int kRepetitions = 200000;
  // A 0.4 x 0.2 x 0.1 box resting 1 µm deep on another box (0.3 m cube), slightly turned: a face contact.
  const double depth = 1e-6;
  // --- Bullet: the persistent-manifold path the contact step uses (one narrow phase per pair and call).
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &configuration);
  btBoxShape top_shape(btVector3(0.2, 0.1, 0.05)), bottom_shape(btVector3(0.15, 0.15, 0.15));
  btCollisionObject top, bottom;
  top.setCollisionShape(&top_shape);
  bottom.setCollisionShape(&bottom_shape);
  top.setWorldTransform(btTransform(btQuaternion(btVector3(0, 0, 1), 0.1), btVector3(0, 0, 0.15 + 0.05 - depth)));
  world.addCollisionObject(&top);
  world.addCollisionObject(&bottom);
  int bullet_points = 0;
  const double bullet_ns = nanosecondsPer(kRepetitions, [&] {
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) dispatcher.getManifoldByIndexInternal(m)->clearManifold();
    world.performDiscreteCollisionDetection();
    bullet_points = dispatcher.getNumManifolds() ? dispatcher.getManifoldByIndexInternal(0)->getNumContacts() : 0;
  });
  // --- FCL: collide() with contacts requested, as its broad phase would call it per pair.
  auto fcl_top = std::make_shared<fcl::Boxd>(0.4, 0.2, 0.1);
  auto fcl_bottom = std::make_shared<fcl::Boxd>(0.3, 0.3, 0.3);
  fcl::Transform3d X_top = fcl::Transform3d::Identity();
  X_top.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_top.translation() = Eigen::Vector3d(0, 0, 0.15 + 0.05 - depth);
  fcl::CollisionObjectd top_object(fcl_top, X_top), bottom_object(fcl_bottom, fcl::Transform3d::Identity());
  fcl::CollisionRequestd request(8, true);
  std::size_t fcl_points = 0;
  const double fcl_ns = nanosecondsPer(kRepetitions, [&] {
    fcl::CollisionResultd result;
    fcl::collide(&top_object, &bottom_object, request, result);
    fcl_points = result.numContacts();
  });
  // --- Box on a half-space (the ground): FCL's box-halfspace test.
  auto ground = std::make_shared<fcl::Halfspaced>(Eigen::Vector3d::UnitZ(), 0.0);
  fcl::Transform3d X_box = fcl::Transform3d::Identity();
  X_box.translation() = Eigen::Vector3d(0, 0, 0.05 - depth);
  fcl::CollisionObjectd box_object(fcl_top, X_box), ground_object(ground, fcl::Transform3d::Identity());
  std::size_t fcl_ground_points = 0;
  const double fcl_ground_ns = nanosecondsPer(kRepetitions, [&] {
    fcl::CollisionResultd result;
    fcl::collide(&box_object, &ground_object, request, result);
    fcl_ground_points = result.numContacts();
  });
  // Bullet's convex-plane algorithm, one call on a fresh manifold.
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0.0);
  btCollisionObject plane_object, box_on_ground;
  plane_object.setCollisionShape(&plane);
  box_on_ground.setCollisionShape(&top_shape);
  box_on_ground.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.05 - depth)));
  Counter counter;
  const double bullet_ground_ns = nanosecondsPer(kRepetitions / 10, [&] {
    counter.points = 0;
    world.contactPairTest(&box_on_ground, &plane_object, counter);
  });
  std::printf("box on box, face contact:  Bullet %.0f ns, %d points;  FCL %.0f ns, %zu points\n", bullet_ns, bullet_points,
              fcl_ns, fcl_points);
  std::printf("box on the ground plane:   Bullet %.0f ns, %d points;  FCL %.0f ns, %zu points\n", bullet_ground_ns,
              counter.points, fcl_ground_ns, fcl_ground_points);
  return 0;
}
