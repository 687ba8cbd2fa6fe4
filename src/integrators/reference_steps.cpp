#include "reference_steps.hpp"

#include "methods.hpp"
#include "runge_kutta.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {
namespace integrators {

namespace {
const Tableau<1> kExplicitEulerTableau = {{{{{0}}}}, {{1}}};

// The Cayley rotation (1, t e_axis), normalised: a turn by 2 atan(t) about principal axis `axis`.
Eigen::Quaterniond cayleyTurn(int axis, double t) {
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  e[axis] = t;
  return Eigen::Quaterniond(1.0, e.x(), e.y(), e.z()).normalized();
}

// The free rotation of a body with three distinct moments over h at world momentum L, to first order:
// about its principal axes in turn, smallest moment first (index order: the moments ascend), each by the
// Cayley turn with t = h m_i/(2 I_i) at the body momentum m of that moment. A turn about e_i keeps m_i and
// turns the other two components back by its angle (m ← Qᵀ m), so the next turn reads the turned m.
Eigen::Quaterniond cayleyTurns(const MassProperties& mass, double h, const Eigen::Vector3d& L_W,
                               const Eigen::Quaterniond& q_WB) {
  const Eigen::Quaterniond q_BP = mass.principalAxesRotation();
  Eigen::Vector3d m_P = (q_WB * q_BP).conjugate() * L_W;  // R_BPᵀ R_WBᵀ L
  Eigen::Quaterniond turn_P = Eigen::Quaterniond::Identity();
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Quaterniond turn = cayleyTurn(axis, 0.5 * h * m_P[axis] * mass.inversePrincipalMoments()[axis]);
    turn_P = turn_P * turn;
    m_P = turn.conjugate() * m_P;
  }
  return (q_WB * (q_BP * turn_P * q_BP.conjugate())).normalized();  // the turns in body axes: R_BP turn R_BPᵀ
}
}  // namespace

State explicitEulerReference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                             const State& y) {
  Stages<1> stages;
  return normalised(rungeKutta(kExplicitEulerTableau, OrientationUpdate::kAdditive, model, terms, input, h, y, stages));
}

State rk4Reference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, const State& y) {
  Stages<4> stages;
  return normalised(rungeKutta(kRk4Tableau, OrientationUpdate::kAdditive, model, terms, input, h, y, stages));
}

State semiImplicitEulerReference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                 const State& y) {
  const Derivative rates = derivative(model, terms, y, input);  // the wrench of Y_n
  State next = y;
  next.P_W = y.P_W + h * rates.P_dot;
  next.p_WB = y.p_WB + h * model.mass.inverseMass() * next.P_W;
  next.t = y.t + h;
  if (!terms.rotation) return next;
  next.L_W = y.L_W + h * rates.L_dot;
  const MassProperties& mass = model.mass;
  if (!terms.world_inertia) {  // isotropic: ω = L/I₀ is constant over the free flow, the turn is exact
    next.q_WB = (quaternionExp(h * mass.inverseInertia()(0, 0) * next.L_W) * y.q_WB).normalized();
  } else if (isSymmetricTop(mass)) {
    symmetricTopFlow(mass, h, next.L_W, next.q_WB);
    next.q_WB.normalize();
  } else {
    next.q_WB = cayleyTurns(mass, h, next.L_W, y.q_WB);
  }
  return next;
}

}  // namespace integrators
}  // namespace rigid_body
