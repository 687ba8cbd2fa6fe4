// A moving mesh collides as its convex hull (docs/contact.md, "Shapes"): the hull's points, taken back to
// the mesh's own vertices, its faces for face clipping, and Bullet's shape for it, rounded inside the hull
// as Bullet's boxes and cylinders are (a margin that GJK adds back onto a shrunken hull), so that GJK, the
// half-space features and the faces all see the mesh's own surface.
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

/// Bullet's shape for the hull of `vertices`: the hull shrunk by `margin` (at most a quarter of its inner
/// radius) with that margin, so that its faces lie where the hull's do and its edges and corners are
/// rounded inside it.
std::unique_ptr<btConvexHullShape> roundedHullShape(const std::vector<Eigen::Vector3d>& vertices, double margin);

}  // namespace contact
}  // namespace rigid_body
