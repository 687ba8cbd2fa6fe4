// A closed triangle mesh, as mass properties need it: checked for holes and orientation, repaired where a
// repair is unambiguous (a mesh that is inside out is flipped).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace rigid_body {

/// A mesh that cannot be used (unreadable, open, inconsistently oriented, degenerate); what() says why.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Vertices [m] in the mesh's own frame M and triangles as vertex indices, counter-clockwise seen from
/// outside (outward normals by the right-hand rule).
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Merges vertices that are bitwise equal (STL stores each triangle's corners separately).
TriangleMesh weldVertices(const TriangleMesh& mesh);

/// The signed volume by the divergence theorem, Σ p0·(p1 × p2)/6 [m³]: positive for outward normals.
double signedVolume(const TriangleMesh& mesh);

/// Checks that `mesh` is a closed, consistently oriented surface (every edge used by exactly two
/// triangles, once in each direction) with positive volume. A mesh whose volume is negative (inside out)
/// is flipped and a warning is appended to `warnings`. Throws MeshError otherwise, naming the problem.
TriangleMesh validatedClosedMesh(const TriangleMesh& mesh, std::vector<std::string>& warnings);

/// Every vertex scaled by `scale` (> 0) and moved by X: p ← X (scale·p).
TriangleMesh transformed(const TriangleMesh& mesh, double scale, const Eigen::Isometry3d& X = Eigen::Isometry3d::Identity());

}  // namespace rigid_body
