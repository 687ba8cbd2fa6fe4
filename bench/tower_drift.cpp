// How far a tower or a pyramid of cubes drifts while it stands (not a test; numbers in
// docs/performance_log.md): 0.2 m cubes of 1 kg, μ = 0.5, on the ground, rk4 at h = 1 ms, sleeping off.
// After 0.5 s of settling, prints once a second (every 5 s after the first 10) the top cube's lateral and
// vertical displacement, the largest displacement of any cube, and the tower's lean: the largest tilt of a
// cube and the sum of the tilts [rad]. H sets another step (coarse steps: docs/contact.md, step 5), and
// ITERATIONS_DT (in the environment) contact/iterations_dt.
//
// A twisted tower is a tower whose cubes are each turned about the vertical by 0.7 i rad and set off sideways
// by up to 5 mm (no symmetry left for the solver to keep).
//
// Usage: tower_drift tower|twisted|pyramid [CUBES or ROWS = 50] [SECONDS = 60] [SWEEPS = 20] [SLOP = 1e-4] [H = 1e-3]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

int main(int argc, char** argv) {
  const bool pyramid = argc > 1 && std::string(argv[1]) == "pyramid";
  const bool twisted = argc > 1 && std::string(argv[1]) == "twisted";
  const int size = argc > 2 ? std::atoi(argv[2]) : 50;
  const int seconds = argc > 3 ? std::atoi(argv[3]) : 60;
  const double side = 0.2;
  ContactSetup setup;
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.5)};
  setup.settings.iterations = argc > 4 ? std::atoi(argv[4]) : setup.settings.iterations;
  setup.settings.penetration_slop = argc > 5 ? std::atof(argv[5]) : setup.settings.penetration_slop;
  setup.settings.sleep = false;
  const double h = argc > 6 ? std::atof(argv[6]) : 1e-3;
  if (const char* iterations_dt = std::getenv("ITERATIONS_DT")) setup.settings.iterations_dt = std::atof(iterations_dt);
  const auto steps = [&](double seconds_to_step) { return std::llround(seconds_to_step / h); };
  std::vector<BodyDefinition> cubes;
  const auto add = [&](const Eigen::Vector3d& p, double yaw = 0.0) {
    cubes.push_back(reference::contactBody(MassProperties::box(1.0, Eigen::Vector3d::Constant(side)), p,
                                           Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
                                           Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -9.81)));
    setup.bodies.push_back(reference::collisionShape(ShapeType::kBox, Eigen::Vector3d::Constant(side), 0.5, 0.0));
  };
  if (pyramid) {  // row r has size − r cubes, 1 mm apart, each on the two below it
    for (int r = 0; r < size; ++r) {
      for (int i = 0; i < size - r; ++i) add(Eigen::Vector3d((side + 0.001) * (i + 0.5 * r), 0.0, side * (r + 0.5)));
    }
  } else {
    for (int i = 0; i < size; ++i) {
      const Eigen::Vector3d offset = twisted ? Eigen::Vector3d(0.005 * std::sin(1.3 * i), 0.005 * std::cos(2.1 * i), 0.0)
                                             : Eigen::Vector3d::Zero();
      add(offset + Eigen::Vector3d(0.0, 0.0, side * (i + 0.5)), twisted ? 0.7 * i : 0.0);
    }
  }
  Scene scene(cubes, IntegratorType::kRk4, h, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.step(steps(0.5));
  std::vector<Eigen::Vector3d> settled;
  for (std::size_t i = 0; i < cubes.size(); ++i) settled.push_back(scene.state(i).p_WB);
  std::printf("%s of %d, %d sweeps (%d a step at h = %g s), slop %g m; from 0.5 s on:\n",
              pyramid ? "pyramid" : twisted ? "twisted tower" : "tower", size, setup.settings.iterations,
              sweepsPerStep(setup.settings, h), h, setup.settings.penetration_slop);
  const auto start = std::chrono::steady_clock::now();
  for (int s = 1; s <= seconds; ++s) {
    scene.step(steps(1.0));
    if (s > 10 && s % 5 != 0) continue;
    double largest = 0.0, tilt_max = 0.0, tilt_sum = 0.0;
    for (std::size_t i = 0; i < cubes.size(); ++i) {
      largest = std::max(largest, (scene.state(i).p_WB - settled[i]).norm());
      const Eigen::Vector3d up = scene.state(i).q_WB * Eigen::Vector3d::UnitZ();
      const double tilt = std::atan2(up.head<2>().norm(), up.z());
      tilt_max = std::max(tilt_max, tilt);
      tilt_sum += tilt;
    }
    const Eigen::Vector3d top = scene.state(cubes.size() - 1).p_WB - settled.back();
    std::printf("t = %2d s: top lateral %.4f mm, vertical %.4f mm; largest %.4f mm; tilt max %.2e, sum %.2e rad "
                "[%.1f s wall]\n",
                s, 1e3 * top.head<2>().norm(), 1e3 * top.z(), 1e3 * largest, tilt_max, tilt_sum,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::fflush(stdout);
  }
  return 0;
}
