#include "rigid_body_sim/mesh.hpp"

#include <algorithm>
#include <map>
#include <tuple>

namespace rigid_body {

TriangleMesh weldVertices(const TriangleMesh& mesh) {
  const auto key = [](const Eigen::Vector3d& p) { return std::make_tuple(p.x(), p.y(), p.z()); };
  std::map<std::tuple<double, double, double>, int> index;
  std::vector<int> remap(mesh.vertices.size());
  TriangleMesh welded;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto inserted = index.emplace(key(mesh.vertices[i]), static_cast<int>(welded.vertices.size()));
    if (inserted.second) welded.vertices.push_back(mesh.vertices[i]);
    remap[i] = inserted.first->second;
  }
  for (const auto& t : mesh.triangles) welded.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  return welded;
}

double signedVolume(const TriangleMesh& mesh) {
  double six_volume = 0.0;
  for (const auto& t : mesh.triangles) {
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return six_volume / 6.0;
}

TriangleMesh validatedClosedMesh(const TriangleMesh& input, std::vector<std::string>& warnings) {
  if (input.triangles.size() < 4) throw MeshError("mesh has " + std::to_string(input.triangles.size()) +
                                                  " triangles: a closed surface needs at least 4");
  TriangleMesh mesh = input;
  for (const auto& t : mesh.triangles) {
    for (int i : t) {
      if (i < 0 || static_cast<size_t>(i) >= mesh.vertices.size()) throw MeshError("mesh has a vertex index out of range");
      if (!mesh.vertices[i].allFinite()) throw MeshError("mesh has a non-finite vertex");
    }
  }
  // Directed edges: a closed, consistently oriented surface uses every edge once in each direction.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  size_t open = 0, overused = 0;
  for (const auto& edge : directed) {
    if (edge.second > 1) ++overused;  // two triangles run along it the same way
    if (!directed.count({edge.first.second, edge.first.first})) ++open;  // no triangle on the other side
  }
  if (overused > 0) {
    throw MeshError("mesh is not consistently oriented or not manifold: " + std::to_string(overused) +
                    " edges are used twice in the same direction (flip the offending triangles)");
  }
  if (open > 0) {
    throw MeshError("mesh is not closed: " + std::to_string(open) +
                    " edges belong to one triangle only (fill the holes; mass properties need a watertight mesh)");
  }
  const double volume = signedVolume(mesh);
  if (!(std::abs(volume) > 0.0)) throw MeshError("mesh encloses no volume");
  if (volume < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    warnings.push_back("mesh was inside out (inward normals, volume " + std::to_string(volume) +
                       " m^3): flipped every triangle");
  }
  return mesh;
}

TriangleMesh transformed(const TriangleMesh& mesh, double scale, const Eigen::Isometry3d& X) {
  TriangleMesh out = mesh;
  for (auto& p : out.vertices) p = X * (scale * p);
  return out;
}

}  // namespace rigid_body
