// Writes the test meshes under a folder (scripts/make_test_meshes.sh writes test/meshes): good solids in
// every supported format, and broken ones for the error paths. Made here, never downloaded.
#include <iostream>
#include <string>

#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"

int main(int argc, char** argv) {
  using namespace rigid_body;
  if (argc != 2) {
    std::cerr << "usage: make_test_meshes DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  const TriangleMesh box = primitives::box(Eigen::Vector3d(0.4, 0.2, 0.1));
  writeObj(box, dir + "/box.obj");                // double precision
  writeAsciiStl(box, dir + "/box_ascii.stl");     // double precision
  writeBinaryStl(box, dir + "/box_binary.stl");   // float32 corners
  writeBinaryStl(primitives::icosphere(0.5, 3), dir + "/sphere.stl");
  writeObj(primitives::tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}), dir + "/tetrahedron.obj");
  writeObj(primitives::lBracket(0.1, 0.02, 0.005), dir + "/l_bracket.obj");
  writeObj(primitives::ring(0.09, 0.1, 0.01, 64), dir + "/ring.obj");

  TriangleMesh open = box;  // a hole: one triangle missing
  open.triangles.pop_back();
  writeObj(open, dir + "/open_box.obj");
  TriangleMesh inside_out = box;  // every normal inward
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  writeObj(inside_out, dir + "/inside_out_box.obj");
  TriangleMesh one_flipped = box;  // one triangle against its neighbours
  std::swap(one_flipped.triangles[0][1], one_flipped.triangles[0][2]);
  writeObj(one_flipped, dir + "/one_flipped_box.obj");
  std::cout << "wrote the test meshes into " << dir << "\n";
  return 0;
}
