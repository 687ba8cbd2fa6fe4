// Buss's second-order method, a single-stage method that moves q on the rotation group. (Semi-implicit Euler,
// the other one, is a lane kernel: lane_semi_implicit_euler.hpp, one body or four at once.)
#include "methods.hpp"
#include "runge_kutta.hpp"

namespace rigid_body {
namespace integrators {

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
