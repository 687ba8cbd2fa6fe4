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
  const Eigen::Quaterniond& q_BP = mass.principalAxesRotation();
  const Eigen::Quaterniond q_WP = body_axes ? s.q_WB : s.q_WB * q_BP;
  // The body momentum in principal axes.
  Eigen::Vector3d m = body_axes && R_WB ? Eigen::Vector3d(R_WB->transpose() * s.L_W) : q_WP.conjugate() * s.L_W;
  const Eigen::Vector3d& inverse_I = mass.inversePrincipalMoments();
  Eigen::Quaterniond r(1.0, 0.0, 0.0, 0.0);  // the turn in principal axes, unnormalised (one sqrt at the end)
  for (int a = 0; a < 3; ++a) {
    const double t = (0.5 * h * inverse_I(a)) * m(a);
    Eigen::Quaterniond turn(1.0, 0.0, 0.0, 0.0);
    turn.coeffs()(a) = t;  // (x, y, z, w) storage: the vector part along e_a
    r = r * turn;
    const int j = (a + 1) % 3, k = (a + 2) % 3;
    const double d = 1.0 / (1.0 + t * t), c = (1.0 - t * t) * d, sn = 2.0 * t * d;
    const double mj = m(j), mk = m(k);
    m(j) = c * mj + sn * mk;
    m(k) = -sn * mj + c * mk;
  }
  s.q_WB = body_axes ? q_WP * r : q_WP * r * q_BP.conjugate();  // normalised by the caller
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
