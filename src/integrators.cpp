#include "rigid_body_sim/integrators.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {

namespace {

const std::array<std::string, 3> kIntegratorNames = {"explicit_euler", "semi_implicit_euler", "rk4"};

// Every method ends a step with a unit quaternion: those that move q off the unit sphere project back.
State normalised(State state) {
  state.q_WB.normalize();
  return state;
}

// Explicit Euler: Y_{n+1} = Y_n + h f(Y_n), then q ← q/|q| (the seed's method).
State explicitEulerStep(const Model& model, const AppliedWrench& input, double h, const State& y) {
  return normalised(addScaled(y, derivative(model, y, input), h));
}

// Semi-implicit (symplectic) Euler: the momenta take the wrench of Y_n, then the configuration moves with
// the new velocities: x += h P_{n+1}/M and q ← exp(h ω_{n+1}) ⊗ q with ω_{n+1} = I⁻¹(q_n) L_{n+1}.
// The exponential keeps |q| = 1 up to rounding; the final normalisation only removes that rounding.
State semiImplicitEulerStep(const Model& model, const AppliedWrench& input, double h, const State& y) {
  const Motion motion = motionOf(model.mass, y);
  const Wrench wrench = totalWrench(model, motion, input);
  State next;
  next.P_W = y.P_W + h * wrench.force;
  next.L_W = y.L_W + h * wrench.torque;
  next.p_WB = y.p_WB + (h * model.mass.inverseMass()) * next.P_W;
  next.q_WB = quaternionExp(h * (motion.I_inv_W * next.L_W)) * y.q_WB;
  next.t = y.t + h;
  return normalised(next);
}

// Classic RK4 on the whole state:
//   k1 = f(Y), k2 = f(Y + h/2 k1), k3 = f(Y + h/2 k2), k4 = f(Y + h k3),
//   Y_{n+1} = Y + h/6 (k1 + 2 k2 + 2 k3 + k4), then q normalised.
State rk4Step(const Model& model, const AppliedWrench& input, double h, const State& y) {
  const Derivative k1 = derivative(model, y, input);
  const Derivative k2 = derivative(model, addScaled(y, k1, 0.5 * h), input);
  const Derivative k3 = derivative(model, addScaled(y, k2, 0.5 * h), input);
  const Derivative k4 = derivative(model, addScaled(y, k3, h), input);
  Derivative sum;
  sum.p_dot = k1.p_dot + 2.0 * (k2.p_dot + k3.p_dot) + k4.p_dot;
  sum.q_dot = k1.q_dot + 2.0 * (k2.q_dot + k3.q_dot) + k4.q_dot;
  sum.P_dot = k1.P_dot + 2.0 * (k2.P_dot + k3.P_dot) + k4.P_dot;
  sum.L_dot = k1.L_dot + 2.0 * (k2.L_dot + k3.L_dot) + k4.L_dot;
  State next = addScaled(y, sum, h / 6.0);
  next.t = y.t + h;
  return normalised(next);
}

}  // namespace

const std::vector<IntegratorType>& allIntegrators() {
  static const std::vector<IntegratorType> all = {IntegratorType::kExplicitEuler, IntegratorType::kSemiImplicitEuler,
                                                  IntegratorType::kRk4};
  return all;
}

const std::string& integratorName(IntegratorType type) { return kIntegratorNames.at(static_cast<size_t>(type)); }

std::string integratorNameList() {
  std::string list;
  for (const std::string& name : kIntegratorNames) list += (list.empty() ? "" : ", ") + name;
  return list;
}

IntegratorType integratorFromName(const std::string& name) {
  for (IntegratorType type : allIntegrators()) {
    if (integratorName(type) == name) return type;
  }
  throw std::invalid_argument("unknown integrator '" + name + "', valid names are: " + integratorNameList());
}

StepStatus Integrator::step(const Model& model, const AppliedWrench& input, double h, State& state) const {
  if (!std::isfinite(h) || h < 0.0) return StepStatus::kInvalidStep;
  if (h == 0.0) return StepStatus::kOk;
  const State next = doStep(model, input, h, state);
  if (!isFinite(next)) return StepStatus::kNonFinite;
  state = next;
  return StepStatus::kOk;
}

State Integrator::doStep(const Model& model, const AppliedWrench& input, double h, const State& state) const {
  switch (type_) {
    case IntegratorType::kExplicitEuler:
      return explicitEulerStep(model, input, h, state);
    case IntegratorType::kSemiImplicitEuler:
      return semiImplicitEulerStep(model, input, h, state);
    case IntegratorType::kRk4:
      return rk4Step(model, input, h, state);
  }
  throw std::logic_error("unhandled integrator type");
}

}  // namespace rigid_body
