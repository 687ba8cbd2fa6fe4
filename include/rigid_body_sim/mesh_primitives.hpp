// Closed, outward-oriented meshes of simple solids, centred where their comments say. Used to make the test
// meshes (scripts/make_test_meshes.sh), by the tests and by the mass-properties benchmark.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rigid_body_sim/mesh.hpp"

namespace rigid_body {
namespace primitives {

/// Box with edge lengths size [m], centred at the origin, edges along the axes (12 triangles).
TriangleMesh box(const Eigen::Vector3d& size);
/// Sphere of `radius` [m] at the origin: an icosahedron subdivided `subdivisions` times (20·4ⁿ triangles),
/// vertices on the sphere.
TriangleMesh icosphere(double radius, int subdivisions);
/// A closed polygon (counter-clockwise in x–y, seen from +z) extruded from z = −height/2 to +height/2. The
/// caps are fanned from vertex `fan`, which must see every other vertex (any vertex of a convex polygon,
/// the inner corner of an L).
TriangleMesh extrudedPolygon(const std::vector<Eigen::Vector2d>& polygon, double height, int fan = 0);
/// Cylinder of `radius` and `length` along z, centred: a regular `segments`-gon prism.
TriangleMesh cylinder(double radius, double length, int segments);
/// L-shaped bracket: legs of length `leg` along +x and +y from the origin, width `width`, thickness
/// `thickness` along z (centred in z). Its volume is (2·leg − width)·width·thickness.
TriangleMesh lBracket(double leg, double width, double thickness);
/// A thin flat ring about z: inner and outer radius, `height` along z, `segments` around.
TriangleMesh ring(double inner_radius, double outer_radius, double height, int segments);
/// The tetrahedron with vertices a, b, c, d (oriented outward whatever their order).
TriangleMesh tetrahedron(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d);

}  // namespace primitives
}  // namespace rigid_body
