// Reading and writing triangle meshes: STL (binary and ASCII) and Wavefront OBJ. Small parsers of our own:
// mass properties need only vertices and triangles, and a clear error on anything else.
#pragma once

#include <cstddef>
#include <string>

#include "rigid_body_sim/mesh.hpp"

namespace rigid_body {

/// The default limit of a mesh file's size [bytes]: 256 MiB, about 5 million binary STL triangles.
constexpr std::size_t kDefaultMaxMeshBytes = std::size_t(256) << 20;

/// Loads `path` by its extension (.stl binary or ASCII, .obj; case-insensitive) and welds equal vertices.
/// Polygons in an OBJ are fanned into triangles. The file must be a regular file of at most `max_bytes`,
/// every vertex finite and every face index name a vertex. Throws MeshError naming the file and the problem.
TriangleMesh loadMesh(const std::string& path, std::size_t max_bytes = kDefaultMaxMeshBytes);

/// Writes a binary STL (the test meshes of the project are made this way).
void writeBinaryStl(const TriangleMesh& mesh, const std::string& path);
/// Writes an ASCII STL.
void writeAsciiStl(const TriangleMesh& mesh, const std::string& path);
/// Writes a Wavefront OBJ with 1-based indices.
void writeObj(const TriangleMesh& mesh, const std::string& path);

}  // namespace rigid_body
