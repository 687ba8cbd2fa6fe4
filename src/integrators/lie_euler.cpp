// Single-stage methods that move q on the rotation group: semi-implicit Euler and Buss's second-order method.
#include "methods.hpp"
#include "runge_kutta.hpp"

namespace rigid_body {
namespace integrators {

namespace {

// The torque-free rotation over h at fixed world L, to first order and without trigonometry: the body turns
// about its principal axes a, b, c in turn (smallest moment first, as the splitting composes them), each
// by the Cayley rotation (1, t e_i), t = h m_i/(2 I_i), an angle 2 atan(t) = h m_i/I_i + O(h³). Each turn
// keeps m_i and R m = L, so world L stays exact and the map is a Poisson map of the free body (a first-order
// splitting of H = Σ m_i²/(2 I_i) into flows of functions of one m_i each): the energy error stays bounded.
// The body momentum m (principal axes) turns the other way, by the same angle's rational cosine and sine.
// R_WB, if not null, is R(q) of s already formed by the caller: Rᵀ L is then one matrix–vector product.
void cayleyFreeRotation(const MassProperties& mass, double h, const Eigen::Matrix3d* R_WB, State& s) {
  const bool body_axes = mass.principalAxesAreBodyAxes();
  const Eigen::Matrix3d& R_BP = mass.principalAxes();
  // The body momentum in principal axes, m = R_BPᵀ R_WBᵀ L (matrix–vector products when R is at hand).
  Eigen::Vector3d m;
  if (R_WB != nullptr) {
    const Eigen::Vector3d m_B = R_WB->transpose() * s.L_W;
    m = body_axes ? m_B : Eigen::Vector3d(R_BP.transpose() * m_B);
  } else {
    const Eigen::Vector3d m_B = s.q_WB.conjugate() * s.L_W;
    m = body_axes ? m_B : Eigen::Vector3d(R_BP.transpose() * m_B);
  }
  // Turn a about e₀ by t₀ = a₀ m₀ (a_i = h/(2 I_i)); it turns m by the rational rotation of D₀ = 1 + t₀²,
  // so t₁ = a₁ N₁/D₀; turn b moves m₂ by the rotation of 1 + t₁², so t₂ = C/E. The three turns' product
  // (1 + t₀ i)(1 + t₁ j)(1 + t₂ k) = (1 − t₀t₁t₂, t₀ + t₁t₂, t₁ − t₀t₂, t₂ + t₀t₁) (ik = −j, jk = i, k² = −1),
  // times the common denominator D₀ E, needs no division at all: the caller's normalisation is the one
  // square root and division of the whole rotation.
  const Eigen::Vector3d a = (0.5 * h) * mass.inversePrincipalMoments();
  const double t0 = a(0) * m(0);
  const double D0 = 1.0 + t0 * t0, c0 = 1.0 - t0 * t0, s0 = 2.0 * t0;
  const double N1 = c0 * m(1) + s0 * m(2);   // D₀ m₁ after turn a
  const double N2 = -s0 * m(1) + c0 * m(2);  // D₀ m₂ after turn a
  const double A = a(1) * N1;                // t₁ = A/D₀
  const double D0sq = D0 * D0, Asq = A * A;
  const double E = D0 * (D0sq + Asq);        // t₂ = C/E
  const double C = a(2) * ((D0sq - Asq) * N2 + 2.0 * A * D0sq * m(0));
  const double w = D0 * E - t0 * A * C;
  const Eigen::Vector3d r_P(t0 * D0 * E + A * C, A * E - t0 * D0 * C, C * D0 + t0 * A * E);
  const Eigen::Vector3d r_B = body_axes ? r_P : Eigen::Vector3d(R_BP * r_P);
  s.q_WB = s.q_WB * Eigen::Quaterniond(w, r_B.x(), r_B.y(), r_B.z());
}

}  // namespace

// Semi-implicit (symplectic) Euler: the momenta take the wrench of Y_n, then the configuration moves with the
// new momenta: x += h P_{n+1}/M, and the body turns by the free rotation at L_{n+1} over h, to first order
// (cayleyFreeRotation; a symmetric top by its exact flow). Turning instead by exp(h ω) with ω = I⁻¹(q_n)
// L_{n+1} frozen over the step puts all of the error into the energy, which drifts and moves the flip times
// (0.46 rad off on the T handle I = (1, 2, 3), ω_B = (0.01, 10, 0.01) at h = 1e-5 over 20 s, against 4e-5 rad
// now). An isotropic body turns by exp(h L/I₀), which is exact.
State semiImplicitEulerStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                            const State& y) {
  // The kick needs ω only for angular damping; the rotation below does not use it at all.
  StepTerms kick_terms = terms;
  kick_terms.rotation = terms.angular_damping;
  const Motion motion = motionOf(model.mass, y, kick_terms);
  const Wrench wrench = totalWrench(model, terms, motion, input);
  State next = y;
  next.P_W = y.P_W + h * wrench.force;
  next.p_WB = y.p_WB + (h * model.mass.inverseMass()) * next.P_W;
  next.t = y.t + h;
  if (!terms.rotation) return next;
  next.L_W = y.L_W + h * wrench.torque;
  if (terms.world_inertia) {
    const bool have_R = kick_terms.rotation || kick_terms.input;  // motionOf formed R(q_n) for the kick
    if (!symmetricTopFlow(model.mass, h, next)) cayleyFreeRotation(model.mass, h, have_R ? &motion.R_WB : nullptr, next);
  } else {
    next.q_WB = quaternionExp((h * model.mass.inverseInertia()(0, 0)) * next.L_W) * y.q_WB;  // isotropic: exact
  }
  return normalised(next);
}

// Buss, "Accurate and efficient simulation of rigid-body rotations", J. Comput. Phys. 164 (2000), the
// augmented second-order method: the body turns by hΩ with Ω = ω + h/2 α + h²/12 α × ω, where
// α = ω̇ = I⁻¹(τ − ω × L) (Euler's equations in world axes). The momenta and x take a second-order Taylor
// step, with Ḟ and τ̇ derived from the force models: d(R f_B)/dt = ω × R f_B, d(−c v)/dt = −c F/M,
// d(−c_ω ω)/dt = −c_ω α. Exact for a constant force through the centre of mass.
State bussStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, const State& y) {
  const Motion motion = motionOf(model.mass, y, terms);
  const Wrench wrench = totalWrench(model, terms, motion, input);
  const Eigen::Vector3d& w = motion.w_WB_W;
  const double half_h2 = 0.5 * h * h;
  // Ḟ = −c F/M, plus ω × R f_B for a body that turns (without rotation there is no input either).
  Eigen::Vector3d force_rate = -(model.forces.linear_damping * model.mass.inverseMass()) * wrench.force;
  if (terms.rotation) force_rate += w.cross(motion.R_WB * input.body.force);
  State next = y;
  next.p_WB = y.p_WB + h * motion.v_WB_W + (half_h2 * model.mass.inverseMass()) * wrench.force;
  next.P_W = y.P_W + h * wrench.force + half_h2 * force_rate;
  next.t = y.t + h;
  if (!terms.rotation) return next;
  const Eigen::Vector3d alpha = applyWorldInverseInertia(model.mass, terms, motion.R_WB, wrench.torque - w.cross(y.L_W));
  const Eigen::Vector3d torque_rate = w.cross(motion.R_WB * input.body.torque) - model.forces.angular_damping * alpha;
  next.L_W = y.L_W + h * wrench.torque + half_h2 * torque_rate;
  const Eigen::Vector3d omega_bar = w + (0.5 * h) * alpha + (h * h / 12.0) * alpha.cross(w);
  next.q_WB = quaternionExp(h * omega_bar) * y.q_WB;
  return normalised(next);
}

}  // namespace integrators
}  // namespace rigid_body
