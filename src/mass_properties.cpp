#include "rigid_body_sim/mass_properties.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "rigid_body_sim/number_format.hpp"

namespace rigid_body {

namespace {

// Relative tolerance for symmetry and for the triangle inequality I_max ≤ I_a + I_b. A thin plate sits
// exactly on the triangle bound, and an inertia typed by hand or computed from a mesh carries rounding.
constexpr double kRelativeTolerance = 1e-9;

void requirePositiveFinite(double value, const char* what, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InvalidMassProperties(std::string(what) + " must be a finite number > 0 [" + unit + "], got " +
                                formatNumber(value));
  }
}

}  // namespace

MassProperties::MassProperties(double mass, const Eigen::Matrix3d& I_Bcm_B,
                               const Eigen::Vector3d& principal_moments, const Eigen::Matrix3d& R_BP)
    : mass_(mass),
      inverse_mass_(1.0 / mass),
      I_Bcm_B_(I_Bcm_B),
      // I⁻¹ = R_BP diag(1/λ) R_BPᵀ from the eigen-decomposition: no determinant to underflow (a 1e-300 kg
      // body's det I would be 0, and Eigen's inverse NaN), and exactly symmetric.
      I_Bcm_B_inv_(R_BP * principal_moments.cwiseInverse().asDiagonal() * R_BP.transpose()),
      principal_moments_(principal_moments),
      inverse_principal_moments_(principal_moments.cwiseInverse()),
      R_BP_(R_BP),
      q_BP_(Eigen::Quaterniond(R_BP).normalized()),
      principal_is_body_(R_BP == Eigen::Matrix3d::Identity()),
      // Isotropic only when the tensor is exactly I₀𝟙 up to rounding, so that ω = L/I₀ is the same number.
      isotropic_((I_Bcm_B - I_Bcm_B(0, 0) * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <=
                 1e-15 * std::abs(I_Bcm_B(0, 0))) {}

Eigen::Vector3d boxPrincipalMoments(double mass, const Eigen::Vector3d& size) {
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  return mass / 12.0 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
}

MassProperties MassProperties::box(double mass, const Eigen::Vector3d& size) {
  requirePositiveFinite(size.x(), "box size x", "m");
  requirePositiveFinite(size.y(), "box size y", "m");
  requirePositiveFinite(size.z(), "box size z", "m");
  return fromInertia(mass, boxPrincipalMoments(mass, size).asDiagonal().toDenseMatrix());
}

MassProperties MassProperties::sphere(double mass, double radius) {
  requirePositiveFinite(radius, "sphere radius", "m");
  return fromInertia(mass, 0.4 * mass * radius * radius * Eigen::Matrix3d::Identity());
}

MassProperties MassProperties::cylinder(double mass, double radius, double length) {
  requirePositiveFinite(radius, "cylinder radius", "m");
  requirePositiveFinite(length, "cylinder length", "m");
  const double transverse = mass * (3.0 * radius * radius + length * length) / 12.0;
  const double axial = 0.5 * mass * radius * radius;
  return fromInertia(mass, Eigen::Vector3d(transverse, transverse, axial).asDiagonal().toDenseMatrix());
}

MassProperties MassProperties::fromInertia(double mass, const Eigen::Matrix3d& I, InertiaCheck check) {
  requirePositiveFinite(mass, "mass", "kg");
  if (!I.allFinite()) throw InvalidMassProperties("inertia must be finite");
  const double scale = I.cwiseAbs().maxCoeff();
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > kRelativeTolerance * scale) {
    throw InvalidMassProperties("inertia must be symmetric");
  }
  const Eigen::Matrix3d symmetric = 0.5 * (I + I.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(symmetric);
  const Eigen::Vector3d moments = eigen.eigenvalues();
  Eigen::Matrix3d R_BP = eigen.eigenvectors();
  if (R_BP.determinant() < 0.0) R_BP.col(2) *= -1.0;  // a proper rotation, not a reflection
  if (!(moments(0) > 0.0)) {
    throw InvalidMassProperties("inertia must be positive definite, smallest principal moment is " +
                                formatNumber(moments(0)) + " kg m^2");
  }
  // The step divides by M and by every principal moment: both must stay normal numbers with finite inverses.
  if (!std::isnormal(mass) || !std::isfinite(1.0 / mass)) {
    throw InvalidMassProperties("mass " + formatNumber(mass) + " kg has no finite inverse");
  }
  if (!std::isnormal(moments(0)) || !(moments.cwiseInverse().allFinite())) {
    throw InvalidMassProperties("inertia is too small to invert: smallest principal moment " +
                                formatNumber(moments(0)) + " kg m^2");
  }
  // Principal moments of a real mass distribution obey I_max ≤ I_a + I_b (equality for a flat plate).
  if (check == InertiaCheck::kPhysical && moments(2) > (moments(0) + moments(1)) * (1.0 + kRelativeTolerance)) {
    throw InvalidMassProperties("inertia violates the triangle inequality of principal moments: " +
                                formatNumber(moments(2)) + " > " + formatNumber(moments(0)) + " + " +
                                formatNumber(moments(1)) + " kg m^2");
  }
  return MassProperties(mass, symmetric, moments, R_BP);
}

}  // namespace rigid_body
