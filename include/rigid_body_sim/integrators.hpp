// Time integrators for the state-space form Y = (x, q, P, L), behind one interface.
//
// Every method keeps the momentum form: with no torque, world L is unchanged by any step, so the
// errors of a torque-free body live in the orientation (and, through it, in the energy).
#pragma once

#include <string>
#include <vector>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// The available methods. Add a method here, in kIntegratorNames and in Integrator::doStep's switch.
enum class IntegratorType {
  kExplicitEuler,      ///< Y ← Y + h f(Y), then q normalised. First order.
  kSemiImplicitEuler,  ///< momenta first, then x with the new v and q ← exp(ω h) ⊗ q. First order.
  kRk4,                ///< classic Runge–Kutta on the whole Y, q normalised after the step. Fourth order.
};

/// Every method, in the order of the documentation.
const std::vector<IntegratorType>& allIntegrators();

/// The parameter name of a method, e.g. "rk4".
const std::string& integratorName(IntegratorType type);

/// The method called `name`; throws std::invalid_argument listing the valid names otherwise.
IntegratorType integratorFromName(const std::string& name);

/// "explicit_euler, semi_implicit_euler, rk4": the valid names, for messages.
std::string integratorNameList();

/// Outcome of one step.
enum class StepStatus {
  kOk,            ///< the state was advanced
  kInvalidStep,   ///< h was negative or not finite: the state is unchanged
  kNonFinite,     ///< the step produced a non-finite state: the state is unchanged
};

/// One integrator. `step` is the public entry: it checks h, runs the method on a copy, checks the result
/// and commits it only if it is finite, so on failure the state is unchanged (Drake's contract).
class Integrator {
 public:
  explicit Integrator(IntegratorType type) : type_(type) {}

  IntegratorType type() const { return type_; }

  /// Advances `state` by h ≥ 0 [s] under `input`, held constant over the step. h = 0 leaves it as it is.
  StepStatus step(const Model& model, const AppliedWrench& input, double h, State& state) const;

 private:
  State doStep(const Model& model, const AppliedWrench& input, double h, const State& state) const;

  IntegratorType type_;
};

}  // namespace rigid_body
