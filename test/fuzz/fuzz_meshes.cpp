// Seeded fuzzing of the mesh reader and the mass properties of meshes (scripts/fuzz_inputs.sh; not a test of
// the suite): each iteration takes a test mesh, damages it (bit flips, truncation, inserted tokens such as
// nan, 1e308, 4294967296, "f", "facet", a binary STL's triangle count overwritten) and saves it under a
// mesh extension, possibly another format's; what loads goes through every inertia method and meshBody.
// Must not happen (exit 1): an exception other than MeshError, InvalidMassProperties or invalid_argument,
// a non-finite accepted result. A crash is a finding too (run it under AddressSanitizer, as the script does).
//
// Usage: fuzz_meshes ITERATIONS SEED
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/mesh_mass_properties.hpp"

namespace {

using namespace rigid_body;

const std::vector<std::string> kMeshes = {"box.obj", "box_ascii.stl", "box_binary.stl", "l_bracket.obj",
                                          "sphere.stl", "tetrahedron.obj", "ring.obj"};
const std::vector<std::string> kTokens = {"nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-0",
                                          "4294967296", "-4294967297", "99999999999999999999", "-1", "1/", "//",
                                          "/-1", "f", "v", "vn", "facet", "endsolid", "solid", "vertex",
                                          "outer loop", "\n", "\r\n", " ", "\t", "#", std::string(1, '\0'), "e",
                                          "+", "-", "."};

std::string slurp(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string damaged(std::string bytes, std::mt19937_64& rng) {
  const int edits = 1 + static_cast<int>(rng() % 8);
  for (int e = 0; e < edits && !bytes.empty(); ++e) {
    const std::size_t at = rng() % bytes.size();
    switch (rng() % 6) {
      case 0:
        bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8)));
        break;
      case 1:
        bytes.resize(at);
        break;
      case 2:
        bytes.insert(at, kTokens[rng() % kTokens.size()]);
        break;
      case 3:
        bytes.erase(at, rng() % 16);
        break;
      case 4:
        bytes.insert(at, bytes.substr(rng() % bytes.size(), rng() % 64));
        break;
      default:
        if (bytes.size() >= 84) {  // a binary STL's triangle count: small or anything
          std::uint32_t count = static_cast<std::uint32_t>(rng());
          if (rng() % 2) count %= 1000;
          std::memcpy(&bytes[80], &count, sizeof count);
        }
    }
  }
  return bytes;
}

bool finite(const MeshBody& body) {
  return body.mass.inertia().allFinite() && std::isfinite(body.mass.mass()) && body.X_MB.matrix().allFinite();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_meshes ITERATIONS SEED\n");
    return 2;
  }
  const long iterations = std::atol(argv[1]);
  std::mt19937_64 rng(std::strtoull(argv[2], nullptr, 10));
  char dir[] = "/tmp/fuzz_meshes_XXXXXX";
  if (!mkdtemp(dir)) return 2;
  long loaded = 0, refused = 0, bodies = 0, findings = 0;
  for (long i = 0; i < iterations; ++i) {
    const std::string bytes = damaged(slurp(std::string(TEST_MESH_DIR) + "/" + kMeshes[rng() % kMeshes.size()]), rng);
    const std::string& as = kMeshes[rng() % kMeshes.size()];  // saved as this file's format
    const std::string path = std::string(dir) + "/case" + as.substr(as.find('.'));
    std::ofstream(path, std::ios::binary) << bytes;
    TriangleMesh mesh;
    try {
      mesh = loadMesh(path, std::size_t(1) << 24);
      ++loaded;
    } catch (const MeshError&) {
      ++refused;
      continue;
    } catch (const std::exception& error) {
      ++findings;
      std::printf("FINDING: loadMesh threw a non-MeshError: %s (iteration %ld)\n", error.what(), i);
      continue;
    }
    for (InertiaMethod method : {InertiaMethod::kExact, InertiaMethod::kSampling, InertiaMethod::kBoundingBox,
                                 InertiaMethod::kOrientedBoundingBox}) {
      MeshMassOptions options;
      options.method = method;
      options.mass = 1.0;
      options.samples = 2000;
      try {
        const MeshBody body = meshBody(meshMassProperties(mesh, options), method != InertiaMethod::kBoundingBox);
        ++bodies;
        if (!finite(body)) {
          ++findings;
          std::printf("FINDING: a non-finite body from %s (iteration %ld)\n", inertiaMethodName(method).c_str(), i);
        }
      } catch (const MeshError&) {
      } catch (const InvalidMassProperties&) {
      } catch (const std::invalid_argument&) {
      } catch (const std::exception& error) {
        ++findings;
        std::printf("FINDING: %s threw: %s (iteration %ld)\n", inertiaMethodName(method).c_str(), error.what(), i);
      }
    }
  }
  std::remove((std::string(dir) + "/case.obj").c_str());
  std::remove((std::string(dir) + "/case.stl").c_str());
  rmdir(dir);
  std::printf("fuzz_meshes: %ld files, %ld loaded, %ld refused, %ld bodies, %ld findings\n", iterations, loaded,
              refused, bodies, findings);
  return findings == 0 ? 0 : 1;
}
