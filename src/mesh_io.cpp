#include "rigid_body_sim/mesh_io.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rigid_body {

namespace {

// A binary STL is an 80-byte header, a uint32 count and 50 bytes per triangle.
constexpr size_t kStlHeader = 80;
constexpr size_t kStlTriangle = 50;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

// The whole file, if it is a regular file of at most max_bytes: a device (/dev/zero), a FIFO (which would
// block in open) or a directory is refused before it is opened, and no more than max_bytes + 1 are read.
std::string readFile(const std::string& path, std::size_t max_bytes) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) throw MeshError("cannot open mesh file '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) throw MeshError("mesh file '" + path + "' is not a regular file");
  if (static_cast<std::uint64_t>(info.st_size) > max_bytes) {
    throw MeshError("mesh file '" + path + "' has " + std::to_string(info.st_size) + " bytes, more than the limit of " +
                    std::to_string(max_bytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot open mesh file '" + path + "'");
  // One byte more than expected, to notice a file that grew since stat.
  std::string content(static_cast<std::size_t>(info.st_size) + 1, '\0');
  in.read(&content[0], static_cast<std::streamsize>(content.size()));
  content.resize(static_cast<std::size_t>(in.gcount()));
  if (content.size() > max_bytes) throw MeshError("mesh file '" + path + "' grew beyond the limit while read");
  return content;
}

// A face corner "i", "i/t", "i//n" or "i/t/n" as a 0-based vertex index: 1-based positive indices, negative
// ones counting back from the vertices read so far (Wavefront OBJ). Anything else, 0, or an index outside
// the vertices read so far is an error naming the line.
int objVertexIndex(const std::string& corner, std::size_t vertices, const std::string& where) {
  const std::string text = corner.substr(0, corner.find('/'));
  errno = 0;
  char* end = nullptr;
  const long long index = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) {
    throw MeshError(where + ": face corner '" + corner + "' is not a vertex index");
  }
  const long long count = static_cast<long long>(vertices);
  const long long zero_based = index > 0 ? index - 1 : count + index;
  if (index == 0 || zero_based < 0 || zero_based >= count) {
    throw MeshError(where + ": face corner '" + corner + "' names no vertex (" + std::to_string(vertices) +
                    " read so far; OBJ indices start at 1)");
  }
  return static_cast<int>(zero_based);
}

TriangleMesh parseBinaryStl(const std::string& data, const std::string& path) {
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + kStlHeader, sizeof count);
  if (data.size() != kStlHeader + 4 + static_cast<size_t>(count) * kStlTriangle) {
    throw MeshError("'" + path + "' is not a valid binary STL: " + std::to_string(data.size()) + " bytes for " +
                    std::to_string(count) + " triangles");
  }
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < count; ++i) {
    const char* record = data.data() + kStlHeader + 4 + i * kStlTriangle + 12;  // skip the normal
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, record + 12 * k, sizeof xyz);
      mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
    mesh.triangles.push_back({static_cast<int>(3 * i), static_cast<int>(3 * i + 1), static_cast<int>(3 * i + 2)});
  }
  return mesh;
}

TriangleMesh parseAsciiStl(const std::string& data, const std::string& path) {
  std::istringstream in(data);
  std::string word;
  TriangleMesh mesh;
  int corners = 0;
  while (in >> word) {
    if (lower(word) != "vertex") continue;
    Eigen::Vector3d p;
    if (!(in >> p.x() >> p.y() >> p.z())) throw MeshError("'" + path + "': a vertex line without three numbers");
    mesh.vertices.push_back(p);
    if (++corners % 3 == 0) {
      const int n = static_cast<int>(mesh.vertices.size());
      mesh.triangles.push_back({n - 3, n - 2, n - 1});
    }
  }
  if (corners % 3 != 0 || mesh.triangles.empty()) throw MeshError("'" + path + "' is not a valid ASCII STL");
  return mesh;
}

TriangleMesh parseObj(const std::string& data, const std::string& path) {
  std::istringstream lines(data);
  std::string line;
  TriangleMesh mesh;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    std::istringstream in(line);
    std::string tag;
    if (!(in >> tag)) continue;
    if (tag == "v") {
      Eigen::Vector3d p;
      if (!(in >> p.x() >> p.y() >> p.z())) throw MeshError("'" + path + "' line " + std::to_string(number) + ": bad vertex");
      mesh.vertices.push_back(p);
    } else if (tag == "f") {
      std::vector<int> polygon;
      std::string corner;
      const std::string where = "'" + path + "' line " + std::to_string(number);
      while (in >> corner) polygon.push_back(objVertexIndex(corner, mesh.vertices.size(), where));
      if (polygon.size() < 3) throw MeshError("'" + path + "' line " + std::to_string(number) + ": a face with < 3 vertices");
      for (size_t k = 1; k + 1 < polygon.size(); ++k) mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  if (mesh.triangles.empty()) throw MeshError("'" + path + "' has no faces");
  return mesh;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, std::size_t max_bytes) {
  const std::string extension = lower(path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.')));
  if (extension != ".stl" && extension != ".obj") throw MeshError("'" + path + "': unknown mesh format (use .stl or .obj)");
  const std::string data = readFile(path, max_bytes);
  TriangleMesh mesh;
  if (extension == ".stl") {
    // An ASCII STL starts with "solid" and has "facet"; some binary headers start with "solid" too.
    const bool ascii = data.compare(0, 5, "solid") == 0 && data.find("facet") != std::string::npos;
    if (!ascii && data.size() < kStlHeader + 4) throw MeshError("'" + path + "' is too short to be an STL");
    mesh = ascii ? parseAsciiStl(data, path) : parseBinaryStl(data, path);
  } else if (extension == ".obj") {
    mesh = parseObj(data, path);
  }
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    if (!vertex.allFinite()) throw MeshError("'" + path + "' has a vertex that is not a finite number");
  }
  return weldVertices(mesh);
}

void writeBinaryStl(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  const std::string header(kStlHeader, ' ');
  out.write(header.data(), kStlHeader);
  const std::uint32_t count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&count), sizeof count);
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    const Eigen::Vector3f normal = (b - a).cross(c - a).normalized().cast<float>();
    out.write(reinterpret_cast<const char*>(normal.data()), 12);
    for (const Eigen::Vector3d* p : {&a, &b, &c}) {
      const Eigen::Vector3f corner = p->cast<float>();
      out.write(reinterpret_cast<const char*>(corner.data()), 12);
    }
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
  if (!out) throw MeshError("cannot write '" + path + "'");
}

void writeAsciiStl(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid mesh\n";
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d normal =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).normalized();
    out << "facet normal " << normal.x() << " " << normal.y() << " " << normal.z() << "\n outer loop\n";
    for (int i : t) out << "  vertex " << mesh.vertices[i].x() << " " << mesh.vertices[i].y() << " " << mesh.vertices[i].z() << "\n";
    out << " endloop\nendfacet\n";
  }
  out << "endsolid mesh\n";
  if (!out) throw MeshError("cannot write '" + path + "'");
}

void writeObj(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& p : mesh.vertices) out << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  if (!out) throw MeshError("cannot write '" + path + "'");
}

}  // namespace rigid_body
