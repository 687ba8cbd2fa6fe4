// A moving mesh collides as its convex hull (docs/contact.md, "Shapes"): the hull's points, taken back to
// the mesh's own vertices, its faces for face clipping, and Bullet's shape for it, sharp (no collision
// margin), so that GJK, the half-space features and the faces all see the mesh's own surface.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "shape_features.hpp"

class btConvexHullShape;

namespace rigid_body {
namespace contact {

/// The vertices of the convex hull of `points` (at least four, not coplanar), each one of `points` to the
/// bit (the hull computer works on rounded coordinates; its vertices are taken back to the points they
/// stand for).
std::vector<Eigen::Vector3d> hullVertices(const std::vector<Eigen::Vector3d>& points);

/// The faces of the convex hull of `vertices` (as hullVertices gives them): coplanar triangles merged, each
/// face's corners among `vertices` in order around it, its normal outward.
HullFaces hullFaces(const std::vector<Eigen::Vector3d>& vertices);

/// Bullet's shape for the hull of `vertices`, with no margin. (Bullet's default margin puts the surface GJK
/// sees a margin outside the hull. Shrunk by the margin instead, the hull keeps its faces but its edges are
/// rounded off: a 0.1 m cube rocking on an edge sank 1.1 mm into a box before GJK saw it touch.)
std::unique_ptr<btConvexHullShape> hullShape(const std::vector<Eigen::Vector3d>& vertices);

}  // namespace contact
}  // namespace rigid_body
