// Strang splitting and the two methods built on it: symplectic_splitting and implicit_midpoint.
#include <Eigen/Dense>
#include <cmath>

#include "methods.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {
namespace integrators {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

// Strang splitting, shared by symplectic_splitting and implicit_midpoint:
//   E(h/2) K(h/2) D(h) K(h/2) E(h/2)
// E: the exact flow of damping alone, P ← e^(−ct/M) P and L̇ = −c_ω I⁻¹(t) L at fixed q, i.e.
//    L ← R R_BP exp(−c_ω t Λ⁻¹) R_BPᵀ Rᵀ L (monotone decay at any step: the stiff case needs no small h);
// K: a kick by the external wrench (input and gravity), which does not depend on the momenta;
// D: the drift x += h P/M and the torque-free rotation over h, by the method's own free-body map.
// With no torque, E and K leave L alone, and D keeps world L (below), so world L is exact.

void dampingFlow(const Model& model, const StepTerms& terms, double t, State& s) {
  const ForceModel& forces = model.forces;
  if (terms.linear_damping) s.P_W *= std::exp(-forces.linear_damping * model.mass.inverseMass() * t);
  // c_ω = 0 is the identity flow: skipped also in the general step (the rotation there would round L).
  if (terms.angular_damping && forces.angular_damping > 0.0) {
    const Eigen::Matrix3d R_WP = s.q_WB.toRotationMatrix() * model.mass.principalAxes();
    const Eigen::Array3d decay = (-forces.angular_damping * t / model.mass.principalMoments().array()).exp();
    s.L_W = R_WP * (decay * (R_WP.transpose() * s.L_W).array()).matrix();
  }
}

void kick(const Model& model, const StepTerms& terms, const AppliedWrench& input, double t, State& s) {
  const Wrench external =
      externalWrench(model, terms, terms.input ? rotationMatrix(s.q_WB) : Eigen::Matrix3d::Identity(), input);
  s.P_W += t * external.force;
  s.L_W += t * external.torque;
}

template <typename FreeRotation>
StepStatus strangSplitting(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, State& s,
                           FreeRotation&& free_rotation) {
  dampingFlow(model, terms, 0.5 * h, s);
  kick(model, terms, input, 0.5 * h, s);
  s.p_WB += (h * model.mass.inverseMass()) * s.P_W;
  if (terms.rotation) {
    const StepStatus status = free_rotation(s);
    if (status != StepStatus::kOk) return status;
  }
  kick(model, terms, input, 0.5 * h, s);
  dampingFlow(model, terms, 0.5 * h, s);
  s.t += h;
  s.q_WB.normalize();
  return StepStatus::kOk;
}

// The free-body flow H = Σ m_i²/(2 I_i) split into exactly solvable parts (McLachlan 1993; Touma & Wisdom
// 1994; Fassò 2003). A term c·m_i²/2 turns the body about its own principal axis u_i by t·c·m_i, where
// m_i = u_i·(Rᵀ L) stays constant along that flow, and G²/(2 I_r) turns it about the fixed world L by
// t·G/I_r. Every one of these keeps R m = L, so world L is exact.
//
// Asymmetric body: the three principal-axis rotations c = 1/I_i, composed symmetrically as
//   a(h/2) b(h/2) c(h) b(h/2) a(h/2),  a = smallest moment, b = middle, c = largest.
// Of the six orderings this one measured best in both energy and orientation (asymmetric body at
// h = 50 ms over 10⁵ steps: |ΔE/E| 9.8e-6 against up to 4.9e-4; T handle 1.8e-5; thin rod at 1 ms 1.6e-7).
// Symmetric top (two equal moments I_r): H = G²/(2 I_r) + ½(1/I_s − 1/I_r) m_s², two commuting exact flows:
// the top's exact motion (docs/references.md, torque-free symmetric top), and for a sphere a single rotation about L.
constexpr double kEqualMoments = 1e-12;  // relative difference below which two moments count as equal

// q turned about principal axis `axis` at fixed world L (it moves only q).
void rotateAboutBodyAxis(const MassProperties& mass, int axis, double t, double inverse_reference,
                         const Eigen::Vector3d& L_W, Eigen::Quaterniond& q_WB) {
  const Eigen::Vector3d u_B = mass.principalAxes().col(axis);
  const double m_i = u_B.dot(q_WB.conjugate() * L_W);
  const double I_i = mass.principalMoments()(axis);
  q_WB = q_WB * quaternionExp((t * (1.0 / I_i - inverse_reference) * m_i) * u_B);
}

void rotateAboutBodyAxis(const MassProperties& mass, int axis, double t, double inverse_reference, State& s) {
  rotateAboutBodyAxis(mass, axis, t, inverse_reference, s.L_W, s.q_WB);
}

StepStatus splitFreeRotation(const MassProperties& mass, double h, State& s) {
  if (symmetricTopFlow(mass, h, s)) return StepStatus::kOk;
  rotateAboutBodyAxis(mass, 0, 0.5 * h, 0.0, s);
  rotateAboutBodyAxis(mass, 1, 0.5 * h, 0.0, s);
  rotateAboutBodyAxis(mass, 2, h, 0.0, s);
  rotateAboutBodyAxis(mass, 1, 0.5 * h, 0.0, s);
  rotateAboutBodyAxis(mass, 0, 0.5 * h, 0.0, s);
  return StepStatus::kOk;
}

// Implicit midpoint on Euler's equation in body axes, ṁ = m × I⁻¹m: with y = m_{n+½},
//   y = m_n + h/2 · y × (J y),  J = I_Bcm_B⁻¹,
// solved by Newton (Jacobian 𝟙 − h/2 ([y]× J − [Jy]×)). Then m_{n+1} = C⁻¹ m_n with the Cayley rotation
// C = cay(h ω̂), ω = J y, and the body turns by the same C: R_{n+1} = R_n C, so R_{n+1} m_{n+1} = R_n m_n and
// world L is exact. Energy and |m| are quadratic invariants, kept to the Newton tolerance
// (Austin, Krishnaprasad & Wang, J. Comput. Phys. 107, 1993).
StepStatus midpointFreeRotation(const MassProperties& mass, double h, const IntegratorSettings& settings,
                                std::uint64_t& iterations, State& s) {
  const Eigen::Vector3d m = s.q_WB.conjugate() * s.L_W;
  const Eigen::Matrix3d& J = mass.inverseInertia();
  const double scale = m.norm();
  Eigen::Vector3d y = m;
  bool converged = scale == 0.0;
  for (int k = 0; k < settings.newton_max_iterations && !converged; ++k) {
    const Eigen::Vector3d Jy = J * y;
    const Eigen::Vector3d residual = y - m - (0.5 * h) * y.cross(Jy);
    const Eigen::Matrix3d jacobian = Eigen::Matrix3d::Identity() - (0.5 * h) * (skew(y) * J - skew(Jy));
    const Eigen::Vector3d update = jacobian.partialPivLu().solve(residual);
    y -= update;
    ++iterations;
    converged = update.norm() <= settings.newton_tolerance * scale;
  }
  if (!converged) return StepStatus::kNotConverged;
  const Eigen::Vector3d half_angle = (0.5 * h) * (J * y);
  s.q_WB = s.q_WB * Eigen::Quaterniond(1.0, half_angle.x(), half_angle.y(), half_angle.z()).normalized();
  return StepStatus::kOk;
}

}  // namespace

// A symmetric top (two equal moments I_r) turns exactly: its two flows commute. False for an asymmetric body.
bool isSymmetricTop(const MassProperties& mass) {
  const Eigen::Vector3d& I = mass.principalMoments();  // ascending
  const double tolerance = kEqualMoments * I(2);
  return I(1) - I(0) <= tolerance || I(2) - I(1) <= tolerance;
}

SymmetricTopAxes symmetricTopAxes(const MassProperties& mass) {
  const Eigen::Vector3d& I = mass.principalMoments();  // ascending
  SymmetricTopAxes top;
  // The odd axis s is the one not in the equal pair (either end; for a sphere its term vanishes).
  top.odd = I(1) - I(0) <= kEqualMoments * I(2) ? 2 : 0;
  top.axis = mass.principalAxes().col(top.odd);
  const Eigen::Vector3d& inverse = mass.inversePrincipalMoments();  // computed once: no division per step
  top.inverse_pair = inverse(1);
  top.spin_coefficient = inverse(top.odd) - top.inverse_pair;
  return top;
}

bool symmetricTopFlow(const MassProperties& mass, double h, const Eigen::Vector3d& L_W, Eigen::Quaterniond& q_WB) {
  if (!isSymmetricTop(mass)) return false;
  const SymmetricTopAxes top = symmetricTopAxes(mass);
  rotateAboutBodyAxis(mass, top.odd, h, top.inverse_pair, L_W, q_WB);
  q_WB = quaternionExp((h / mass.principalMoments()(1)) * L_W) * q_WB;
  return true;
}

bool symmetricTopFlow(const MassProperties& mass, double h, State& s) { return symmetricTopFlow(mass, h, s.L_W, s.q_WB); }

StepStatus symplecticSplittingStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                   State& s) {
  return strangSplitting(model, terms, input, h, s, [&](State& state) { return splitFreeRotation(model.mass, h, state); });
}

StepStatus implicitMidpointStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                const IntegratorSettings& settings, std::uint64_t& newton_iterations, State& s) {
  return strangSplitting(model, terms, input, h, s, [&](State& state) {
    return midpointFreeRotation(model.mass, h, settings, newton_iterations, state);
  });
}

}  // namespace integrators
}  // namespace rigid_body
