#include "rigid_body_sim/mesh_primitives.hpp"

#include <cmath>
#include <map>

namespace rigid_body {
namespace primitives {

TriangleMesh box(const Eigen::Vector3d& size) {
  const std::vector<Eigen::Vector2d> square = {{-0.5 * size.x(), -0.5 * size.y()}, {0.5 * size.x(), -0.5 * size.y()},
                                               {0.5 * size.x(), 0.5 * size.y()}, {-0.5 * size.x(), 0.5 * size.y()}};
  return extrudedPolygon(square, size.z());
}

TriangleMesh icosphere(double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(-1, t, 0), Eigen::Vector3d(1, t, 0), Eigen::Vector3d(-1, -t, 0),
                                   Eigen::Vector3d(1, -t, 0), Eigen::Vector3d(0, -1, t), Eigen::Vector3d(0, 1, t),
                                   Eigen::Vector3d(0, -1, -t), Eigen::Vector3d(0, 1, -t), Eigen::Vector3d(t, 0, -1),
                                   Eigen::Vector3d(t, 0, 1), Eigen::Vector3d(-t, 0, -1), Eigen::Vector3d(-t, 0, 1)}) {
    mesh.vertices.push_back(v.normalized());
  }
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      return midpoints[key] = static_cast<int>(mesh.vertices.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : mesh.triangles) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh.triangles = finer;
  }
  for (auto& v : mesh.vertices) v *= radius;
  return mesh;
}

TriangleMesh extrudedPolygon(const std::vector<Eigen::Vector2d>& polygon, double height, int fan) {
  const int n = static_cast<int>(polygon.size());
  TriangleMesh mesh;
  for (double z : {-0.5 * height, 0.5 * height}) {
    for (const auto& p : polygon) mesh.vertices.emplace_back(p.x(), p.y(), z);
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    // Side quad (bottom i, bottom j, top j, top i), outward for a counter-clockwise polygon.
    mesh.triangles.push_back({i, j, n + j});
    mesh.triangles.push_back({i, n + j, n + i});
  }
  for (int k = 1; k + 1 < n; ++k) {
    const int a = (fan + k) % n, b = (fan + k + 1) % n;
    mesh.triangles.push_back({fan, b, a});              // bottom cap, facing −z
    mesh.triangles.push_back({n + fan, n + a, n + b});  // top cap, facing +z
  }
  return mesh;
}

TriangleMesh cylinder(double radius, double length, int segments) {
  std::vector<Eigen::Vector2d> polygon;
  for (int k = 0; k < segments; ++k) {
    const double angle = 2.0 * M_PI * k / segments;
    polygon.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  }
  return extrudedPolygon(polygon, length);
}

TriangleMesh lBracket(double leg, double width, double thickness) {
  // Counter-clockwise; vertex 3 is the inner corner, which sees all the others.
  const std::vector<Eigen::Vector2d> l = {{0, 0}, {leg, 0}, {leg, width}, {width, width}, {width, leg}, {0, leg}};
  return extrudedPolygon(l, thickness, 3);
}

TriangleMesh ring(double inner_radius, double outer_radius, double height, int segments) {
  TriangleMesh mesh;
  // Per angle k: 4k inner bottom, 4k+1 outer bottom, 4k+2 inner top, 4k+3 outer top.
  for (int k = 0; k < segments; ++k) {
    const double angle = 2.0 * M_PI * k / segments;
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    for (double z : {-0.5 * height, 0.5 * height}) {
      mesh.vertices.emplace_back(inner_radius * u.x(), inner_radius * u.y(), z);
      mesh.vertices.emplace_back(outer_radius * u.x(), outer_radius * u.y(), z);
    }
  }
  for (int k = 0; k < segments; ++k) {
    const int a = 4 * k, b = 4 * ((k + 1) % segments);
    const int ib = a, ob = a + 1, it = a + 2, ot = a + 3;
    const int ib2 = b, ob2 = b + 1, it2 = b + 2, ot2 = b + 3;
    mesh.triangles.push_back({ob, ob2, ot2});  // outer wall, facing out
    mesh.triangles.push_back({ob, ot2, ot});
    mesh.triangles.push_back({ib, it2, ib2});  // inner wall, facing the axis
    mesh.triangles.push_back({ib, it, it2});
    mesh.triangles.push_back({it, ot, ot2});   // top, facing +z
    mesh.triangles.push_back({it, ot2, it2});
    mesh.triangles.push_back({ib, ib2, ob2});  // bottom, facing −z
    mesh.triangles.push_back({ib, ob2, ob});
  }
  return mesh;
}

TriangleMesh tetrahedron(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d) {
  TriangleMesh mesh;
  mesh.vertices = {a, b, c, d};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  if (signedVolume(mesh) < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

}  // namespace primitives
}  // namespace rigid_body
