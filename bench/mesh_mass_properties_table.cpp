// Prints the README's comparison of the inertia methods (not a test; scripts/benchmark.sh runs it): for a
// box, a sphere, a non-convex L-bracket and a thin ring, each method's relative error of the inertia
// tensor against the true solid (closed forms) and its time (median of 5).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/mesh_mass_properties.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"

using namespace rigid_body;

namespace {

struct Shape {
  std::string name;
  TriangleMesh mesh;
  Eigen::Matrix3d truth;  // about the centre of mass, mass 1 kg
};

}  // namespace

int main() {
  const double r1 = 0.09, r2 = 0.1, h = 0.01;
  const double ring_axial = 0.5 * (r1 * r1 + r2 * r2), ring_transverse = (3 * (r1 * r1 + r2 * r2) + h * h) / 12.0;
  const std::vector<Shape> shapes = {
      {"box 0.4 × 0.2 × 0.1 m (12 triangles)", primitives::box(Eigen::Vector3d(0.4, 0.2, 0.1)),
       MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)).inertia()},
      {"sphere r = 0.5 m (icosphere, 5120 triangles)", primitives::icosphere(0.5, 4),
       MassProperties::sphere(1.0, 0.5).inertia()},
      {"L-bracket 100 × 20 × 5 mm (non-convex, 20 triangles)", primitives::lBracket(0.1, 0.02, 0.005),
       reference::lBracket(1.0 / (0.18 * 0.02 * 0.005), 0.1, 0.02, 0.005).inertia},  // density for 1 kg
      {"thin ring r 90–100 mm, 10 mm (128-gon, 1024 triangles)", primitives::ring(r1, r2, h, 128),
       Eigen::Vector3d(ring_transverse, ring_transverse, ring_axial).asDiagonal()},
  };
  struct Method {
    std::string name;
    MeshMassOptions options;
  };
  std::vector<Method> methods;
  const auto add = [&](const std::string& name, InertiaMethod method, std::uint64_t samples, bool stratified) {
    MeshMassOptions options;
    options.method = method;
    options.mass = 1.0;
    options.samples = samples;
    options.stratified = stratified;
    methods.push_back({name, options});
  };
  add("exact", InertiaMethod::kExact, 0, false);
  add("sampling 1e4", InertiaMethod::kSampling, 10000, false);
  add("sampling 1e5", InertiaMethod::kSampling, 100000, false);
  add("stratified 1e5", InertiaMethod::kSampling, 100000, true);
  add("bounding_box", InertiaMethod::kBoundingBox, 0, false);
  add("oriented_bounding_box", InertiaMethod::kOrientedBoundingBox, 0, false);

  std::printf("| shape | method | relative error of I | time |\n|---|---|---|---|\n");
  for (const Shape& shape : shapes) {
    for (const Method& method : methods) {
      std::vector<double> times;
      MeshMassProperties result;
      for (int repeat = 0; repeat < 5; ++repeat) {
        const auto start = std::chrono::steady_clock::now();
        result = meshMassProperties(shape.mesh, method.options);
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(times.begin(), times.end());
      const double error = (result.I_Bcm_M - shape.truth).norm() / shape.truth.norm();
      const double t = times[2];
      std::printf("| %s | %s | %.2g | %s |\n", shape.name.c_str(), method.name.c_str(), error,
                  t < 1e-3 ? (std::to_string(static_cast<int>(t * 1e6)) + " µs").c_str()
                           : (std::to_string(static_cast<int>(t * 1e3)) + " ms").c_str());
    }
  }
  return 0;
}
