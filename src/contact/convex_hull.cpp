#include "convex_hull.hpp"

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cstddef>

namespace rigid_body {
namespace contact {

namespace {

Eigen::Vector3d fromBt(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

// The point of a set nearest to a given one, among those whose x lies within a window of it: a hull
// computation's points lie within its rounding (~1e-4 of the size) of the ones it was given.
class NearestPoint {
 public:
  explicit NearestPoint(const std::vector<Eigen::Vector3d>& points) : points_(points) {
    Eigen::Vector3d low = points.front(), high = low;
    for (const Eigen::Vector3d& p : points) low = low.cwiseMin(p), high = high.cwiseMax(p);
    window_ = 1e-3 * (high - low).norm();
    order_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) order_[i] = i;
    std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return points[a].x() < points[b].x(); });
  }
  Eigen::Vector3d operator()(const Eigen::Vector3d& v) const {
    auto it = std::lower_bound(order_.begin(), order_.end(), v.x() - window_,
                               [&](std::size_t i, double x) { return points_[i].x() < x; });
    const Eigen::Vector3d* best = nullptr;
    for (; it != order_.end() && points_[*it].x() <= v.x() + window_; ++it) {
      if (best == nullptr || (points_[*it] - v).squaredNorm() < (*best - v).squaredNorm()) best = &points_[*it];
    }
    return best != nullptr ? *best : v;
  }

 private:
  const std::vector<Eigen::Vector3d>& points_;
  std::vector<std::size_t> order_;
  double window_ = 0.0;
};

}  // namespace

std::vector<Eigen::Vector3d> hullVertices(const std::vector<Eigen::Vector3d>& points) {
  btConvexHullComputer computer;
  computer.compute(points.front().data(), static_cast<int>(sizeof(Eigen::Vector3d)), static_cast<int>(points.size()),
                   0.0, 0.0);
  const NearestPoint exact(points);
  std::vector<Eigen::Vector3d> vertices;
  for (int v = 0; v < computer.vertices.size(); ++v) vertices.push_back(exact(fromBt(computer.vertices[v])));
  return vertices;
}

HullFaces hullFaces(const std::vector<Eigen::Vector3d>& vertices) {
  btConvexHullShape hull;
  for (const Eigen::Vector3d& p : vertices) hull.addPoint(btVector3(p.x(), p.y(), p.z()), false);
  hull.recalcLocalAabb();
  HullFaces faces;
  if (!hull.initializePolyhedralFeatures() || hull.getConvexPolyhedron() == nullptr) return faces;
  const btConvexPolyhedron& polyhedron = *hull.getConvexPolyhedron();
  const NearestPoint exact(vertices);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : vertices) centre += v;
  centre /= static_cast<double>(vertices.size());
  for (int f = 0; f < polyhedron.m_faces.size(); ++f) {
    const btFace& face = polyhedron.m_faces[f];
    if (face.m_indices.size() < 3) continue;
    std::vector<Eigen::Vector3d> loop;
    for (int i = 0; i < face.m_indices.size(); ++i) loop.push_back(exact(fromBt(polyhedron.m_vertices[face.m_indices[i]])));
    // The normal of the exact corners (Newell's method: the polygon's area vector), not Bullet's plane, which
    // the hull computer's rounding tilts by up to ~1e-3 rad on a 0.1 m hull.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < loop.size(); ++i) normal += loop[i].cross(loop[(i + 1) % loop.size()]);
    normal.normalize();
    if (normal.dot(loop[0] - centre) < 0.0) normal = -normal;
    faces.normals.push_back(normal);
    faces.loops.push_back(std::move(loop));
  }
  return faces;
}

std::unique_ptr<btConvexHullShape> hullShape(const std::vector<Eigen::Vector3d>& vertices) {
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector3d& p : vertices) hull->addPoint(btVector3(p.x(), p.y(), p.z()), false);
  hull->setMargin(0.0);
  hull->recalcLocalAabb();
  return hull;
}

}  // namespace contact
}  // namespace rigid_body
