// Random solver bodies for the contact solver's tests: a unit vector and a body (mass 0.1–10 kg, principal
// moments 0.01–1 kg m² about random axes) that no axis favours.
#pragma once

#include <Eigen/Geometry>
#include <random>

#include "../../src/contact/contact_solver.hpp"

namespace rigid_body {
namespace contact {
namespace test {

inline Eigen::Vector3d randomUnit(std::mt19937& random) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return Eigen::Vector3d(normal(random), normal(random), normal(random)).normalized();
}

inline SolverBody randomBody(std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SolverBody body;
  body.inverse_mass = 1.0 / (0.1 + 10.0 * unit(random));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(6.3 * unit(random), randomUnit(random)).toRotationMatrix();
  const Eigen::Vector3d moments(0.01 + unit(random), 0.01 + unit(random), 0.01 + unit(random));
  body.inverse_inertia_W = R * moments.cwiseInverse().asDiagonal() * R.transpose();
  return body;
}

}  // namespace test
}  // namespace contact
}  // namespace rigid_body
