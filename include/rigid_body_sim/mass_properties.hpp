// Mass and inertia of one rigid body about its centre of mass.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace rigid_body {

/// Thrown for mass properties no physical body can have; the message names the quantity and the rule.
class InvalidMassProperties : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// How strictly fromInertia checks a tensor.
enum class InertiaCheck {
  kPhysical,              ///< symmetric positive definite and the triangle inequality: a real mass distribution
  kPositiveDefiniteOnly,  ///< symmetric positive definite only: for the published numerical test bodies that
                          ///< break the triangle inequality (Principia's I = (3, 3, 9) and (3, 5, 9)); never
                          ///< for user input
};

/// Principal moments of a solid box of `mass` [kg] and edge lengths size = (x, y, z) [m] about its centre,
/// along its edges: M/12 (y² + z², x² + z², x² + y²) [kg m²]. Not validated (MassProperties::box is).
Eigen::Vector3d boxPrincipalMoments(double mass, const Eigen::Vector3d& size);

/// Constant mass properties of a body: mass and inertia about the centre of mass in body axes.
/// Made only through the factories below, which validate; so a MassProperties always holds
/// a positive mass and a symmetric positive-definite inertia that (unless explicitly exempted with
/// InertiaCheck::kPositiveDefiniteOnly) satisfies the triangle inequality.
class MassProperties {
 public:
  /// 1 kg with unit inertia 𝟙 kg m^2: a valid body, so that holders can be default-constructed.
  MassProperties()
      : MassProperties(1.0, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Ones(), Eigen::Matrix3d::Identity()) {}

  /// Solid box with edge lengths size = (x, y, z) [m]: I = M/12 diag(y²+z², x²+z², x²+y²).
  static MassProperties box(double mass, const Eigen::Vector3d& size);
  /// Solid sphere of radius r [m]: I = 2/5 M r² 𝟙.
  static MassProperties sphere(double mass, double radius);
  /// Solid cylinder of radius r and length l [m] along body z: I_xx = I_yy = M(3r² + l²)/12, I_zz = M r²/2.
  static MassProperties cylinder(double mass, double radius, double length);
  /// A full inertia tensor about the centre of mass [kg m^2], body axes.
  static MassProperties fromInertia(double mass, const Eigen::Matrix3d& I_Bcm_B,
                                    InertiaCheck check = InertiaCheck::kPhysical);

  double mass() const { return mass_; }                                 ///< M [kg]
  double inverseMass() const { return inverse_mass_; }                  ///< 1/M [1/kg]
  const Eigen::Matrix3d& inertia() const { return I_Bcm_B_; }           ///< I_Bcm_B [kg m^2]
  const Eigen::Matrix3d& inverseInertia() const { return I_Bcm_B_inv_; }///< I_Bcm_B⁻¹ [1/(kg m^2)]
  /// Principal moments in ascending order [kg m^2].
  const Eigen::Vector3d& principalMoments() const { return principal_moments_; }
  /// Their inverses [1/(kg m^2)], computed once (the hot step multiplies instead of dividing).
  const Eigen::Vector3d& inversePrincipalMoments() const { return inverse_principal_moments_; }
  /// R_BP: columns are the principal axes in body coordinates (a proper rotation), so that
  /// I_Bcm_B = R_BP diag(principalMoments()) R_BPᵀ.
  const Eigen::Matrix3d& principalAxes() const { return R_BP_; }
  /// R_BP as a unit quaternion q_BP (computed once).
  const Eigen::Quaterniond& principalAxesRotation() const { return q_BP_; }
  /// True when R_BP is the identity: the body axes are the principal axes (a diagonal inertia in ascending
  /// order, as boxes, cylinders and most shapes give), so no change of axes is needed.
  bool principalAxesAreBodyAxes() const { return principal_is_body_; }
  /// True when I_Bcm_B = I₀𝟙 (sphere, cube): then ω = L/I₀ in any axes. Decided once, at construction.
  bool isIsotropic() const { return isotropic_; }

 private:
  MassProperties(double mass, const Eigen::Matrix3d& I_Bcm_B, const Eigen::Vector3d& principal_moments,
                 const Eigen::Matrix3d& R_BP);

  double mass_;
  double inverse_mass_;
  Eigen::Matrix3d I_Bcm_B_;
  Eigen::Matrix3d I_Bcm_B_inv_;
  Eigen::Vector3d principal_moments_;
  Eigen::Vector3d inverse_principal_moments_;
  Eigen::Matrix3d R_BP_;
  Eigen::Quaterniond q_BP_;
  bool principal_is_body_;
  bool isotropic_;
};

}  // namespace rigid_body
