// Closed-form solutions to test integrators against, from docs/references.md §2 (each checked there
// against a fine RK4 run). Not integrators: every value comes from a formula, or for the asymmetric body's
// orientation from a quadrature of a closed-form rate.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {
namespace reference {

/// §2.4 Constant force F [N] on mass m [kg]: x(t) = x₀ + v₀t + F t²/(2m).
Eigen::Vector3d ballisticPosition(const Eigen::Vector3d& x0, const Eigen::Vector3d& v0, const Eigen::Vector3d& force,
                                  double mass, double t);

/// §2.6 Linear damping m v̇ = −c v: v(t) = v₀ e^(−ct/m).
Eigen::Vector3d dampedVelocity(const Eigen::Vector3d& v0, double damping, double mass, double t);

/// §2.5 Sphere (I = I₀𝟙) at rest under a constant body-fixed torque τ_b: q(t) = q₀ ⊗ exp(θ(t) τ̂_b),
/// θ = |τ_b| t²/(2 I₀).
Eigen::Quaterniond sphereUnderBodyTorque(const Eigen::Quaterniond& q0, double I0, const Eigen::Vector3d& tau_B,
                                         double t);

/// Mass properties of a solid L-bracket (legs of length `leg` along +x and +y from the origin, width
/// `width`, thickness along z centred at z = 0; primitives::lBracket's shape), as two boxes joined by the
/// parallel-axis theorem: [0, leg]×[0, width] and [0, width]×[width, leg].
struct SolidMassProperties {
  double mass;                 ///< [kg]
  Eigen::Vector3d centre;      ///< centre of mass [m]
  Eigen::Matrix3d inertia;     ///< about the centre of mass [kg m²]
};
SolidMassProperties lBracket(double density, double leg, double width, double thickness);

/// §2.1 Torque-free symmetric top, I = diag(I⊥, I⊥, I_s) in body axes, world momentum L_W:
/// q(t) = exp(t L_W/I⊥) ⊗ q₀ ⊗ exp(t (1/I_s − 1/I⊥) m₃ e₃), m₃ = (q₀⁻¹ L_W)_z.
Eigen::Quaterniond symmetricTop(double I_perp, double I_s, const Eigen::Quaterniond& q0, const Eigen::Vector3d& L_W,
                                double t);

/// §2.2 Torque-free asymmetric body with principal moments I₁ < I₂ < I₃ along the body axes, by Jacobi
/// elliptic functions (Leroy's cancellation-free form, both cases of sign Δ₂, both signs σ) and the
/// orientation by the semi-exact quadrature R(t) = Q₀ Rot_{e_a}(ψ(t)) P(t).
class TorqueFreeBody {
 public:
  /// m0_B: initial body angular momentum [kg m²/s]; q0: initial orientation. Throws std::invalid_argument
  /// unless I₁ < I₂ < I₃ and the motion is away from the separatrix (|Δ₂|/G² > 1e-9) and m0 ≠ 0.
  TorqueFreeBody(const Eigen::Vector3d& principal_moments, const Eigen::Vector3d& m0_B, const Eigen::Quaterniond& q0);

  /// Body angular momentum m(t) [kg m²/s].
  Eigen::Vector3d bodyMomentum(double t) const;
  /// Orientation q(t), body to world.
  Eigen::Quaterniond orientation(double t) const;
  /// World angular momentum (constant) [kg m²/s].
  const Eigen::Vector3d& worldMomentum() const { return L_W_; }
  /// Kinetic energy T = ½ Σ m_i²/I_i (constant) [J].
  double energy() const { return 0.5 * two_T_; }
  /// Period of m(t): 4K(k²)/λ [s].
  double period() const;
  /// §2.3 Time between sign changes of m₂ (the intermediate-axis flip): 2K(k²)/λ [s].
  double flipTime() const { return 0.5 * period(); }
  /// The modulus squared k² and the rate λ [1/s] of the elliptic solution.
  double modulusSquared() const { return k2_; }
  double lambda() const { return lambda_; }

 private:
  // m(t) in the relabelled frame (σ = +1 after the flip S = Rot_{e₂}(π) when needed).
  Eigen::Vector3d relabelledMomentum(double t) const;
  // ψ̇ = (2T + G m_a/I_a)/(G + m_a) on the relabelled momentum.
  double psiRate(double t) const;
  // P(t): the minimal rotation taking m(t) to G e_a.
  Eigen::Quaterniond alignToAxis(const Eigen::Vector3d& m) const;

  Eigen::Vector3d I_;
  Eigen::Vector3d L_W_;
  double G_;
  double two_T_;
  bool circulates_about_3_;  // Δ₂ > 0: the dn axis a is 3; otherwise 1
  bool flipped_;             // σ = −1: solved in the frame relabelled by S = Rot_{e₂}(π)
  double k2_;
  double lambda_;
  Eigen::Vector3d B_;        // amplitudes (B₁, B₂ or B₂′, B₃)
  double nu_;                // phase ν = F(φ₀|k²)
  Eigen::Quaterniond Q0_;    // R₀' P(0)ᵀ in the relabelled frame
};

/// Least-squares slope of y against x over the points (x, y), e.g. the drift rate of an energy error.
double leastSquaresSlope(const std::vector<std::pair<double, double>>& points);
/// The same of log y against log x: the empirical order of a method when x is the step and y its error.
double logLogSlope(const std::vector<std::pair<double, double>>& points);

/// A body at rest at the origin (identity orientation), pushed for `duration` [s] by the body-fixed force F_B
/// [N] at the body point r_B [m], with no closed form: integrated in the body-axes form (Landau & Lifshitz
/// §36), I ω̇_B = τ_B − ω_B × I ω_B with τ_B = r_B × F_B constant in body axes, q̇ = ½ q ⊗ [0, ω_B],
/// ẍ = R(q) F_B / M, by classic RK4 on (q, ω_B, x, v) with step h, q normalised after each step. Nothing here
/// is shared with the integrators' momentum form Y = (x, q, P, L): a wrong lever arm or frame there shows.
State bodyFixedPush(const MassProperties& mass, const Eigen::Vector3d& F_B, const Eigen::Vector3d& r_B,
                    double duration, double h);

// ---------------------------------------------------------------------------------------------------------
// The test bodies the tests and the accuracy report share, so that a scene means the same in both.

/// The initial orientation of the torque-free test scenes: 0.4 rad about (1, 2, 3)/√14, so that no body
/// axis starts along a world axis.
const Eigen::Quaterniond& testOrientation();

/// A body of `mass` [kg] whose principal axes are its body axes, I = diag(moments) [kg m²], no forces.
/// `check` is InertiaCheck::kPositiveDefiniteOnly only for the published test bodies that break the
/// triangle inequality (Principia's I = (3, 3, 9) and (3, 5, 9)).
Model principalBody(const Eigen::Vector3d& moments, double mass = 1.0, InertiaCheck check = InertiaCheck::kPhysical);

/// At the origin, at rest, turned by q0 (testOrientation() by default), with body angular momentum m0_B.
State torqueFreeStart(const Eigen::Vector3d& m0_B, const Eigen::Quaterniond& q0 = testOrientation());

// The building blocks of the contact scenes (docs/references.md §4).

/// The half-space n·x ≤ offset named "ground" with friction μ and restitution e.
CollisionShape groundPlane(const Eigen::Vector3d& normal, double friction, double restitution = 0.0, double offset = 0.0);

/// A collision shape of `type` and `size` (see ShapeType) with friction μ and restitution e.
CollisionShape collisionShape(ShapeType type, const Eigen::Vector3d& size, double friction, double restitution);

/// The mass properties of a solid box, sphere or cylinder of `mass` with the shape's size (others: its box).
MassProperties solidMass(const CollisionShape& shape, double mass);

/// How far the lowest point of a box, sphere, cylinder or capsule (axis z of its frame) at `state` is below the
/// ground z = 0 [m] (≤ 0 when it is above).
double depthBelowGround(const State& state, const CollisionShape& shape);

/// A body without wrench input at p_WB, turned by q_WB, moving at v_WB_W and turning at w_WB_B, under gravity.
BodyDefinition contactBody(const MassProperties& mass, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB,
                           const Eigen::Vector3d& v_WB_W, const Eigen::Vector3d& w_WB_B, const Eigen::Vector3d& gravity_W);

/// Every body's kinetic energy (translation and rotation) and potential energy under its gravity, summed [J]:
/// what contact must never raise.
double mechanicalEnergy(const Scene& scene);

}  // namespace reference
}  // namespace rigid_body
