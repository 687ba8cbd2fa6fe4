// A pair's contact points from one contact normal: the face of each shape that meets the normal, one
// clipped against the other (Sutherland–Hodgman), as Box2D's polygon manifolds and Jolt's
// ManifoldBetweenTwoFaces build theirs. One GJK/EPA query gives the normal; the clipping gives a face on a
// face, a cylinder or capsule lying on a face, or a cylinder standing on one, all its points in that one
// pass (Bullet's multi-point mode instead runs GJK again at four perturbed orientations and keeps what it
// finds: five queries, and points only where the perturbation happened to land).
//
// Every point made here lies on both shapes' exact surfaces (no collision margin): a box's or hull's face,
// a capsule's two end spheres' nearest points, a cylinder's rim or the line of its side. Bullet-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "collision_world.hpp"
#include "shape_features.hpp"

namespace rigid_body {
namespace contact {

/// The largest angle between a face and the contact normal at which the face still carries the pair's
/// points. Where a GJK/EPA normal is the normal of a face, the two agree to the penetration's share of the
/// face's size; at an edge on an edge or a corner on an edge no face agrees, and the pair keeps the one
/// point the query found.
constexpr double kFaceAngleCosine = 0.9848077530122080;  // cos 10°

/// The contact points of shapes a and b that offer `face_a` (along −n) and `face_b` (along n), n the unit
/// contact normal from b towards a: the incident face clipped to the reference face's sides (the reference
/// is the polygon more nearly normal to n; two segments must be parallel), each clipped point's distance
/// measured along n to the reference face's plane. Points no farther apart than `max_distance` are kept, at
/// most four (the deepest, then those that span the largest area). Appends to `points` (a, b set by the
/// caller's `pair`) and returns true; returns false, appending nothing, where the faces do not make a
/// manifold (no face, faces not along n, nothing left after clipping).
bool clipFaces(const SupportFace& face_a, const SupportFace& face_b, const Eigen::Vector3d& n, double max_distance,
               const ContactPoint& pair, std::vector<ContactPoint>& points);

/// Keeps at most four of `points[first…]`: the deepest, the one farthest from it, the one that makes the
/// largest triangle with those two, and the one that adds the most area beyond that triangle (Bullet's
/// sortCachedPoints and Box2D keep four the same way: the widest support for the fewest rows).
void keepFourPoints(std::vector<ContactPoint>& points, std::size_t first);

}  // namespace contact
}  // namespace rigid_body
