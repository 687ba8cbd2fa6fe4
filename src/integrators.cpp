// The integrator registry and the one public step: validation, dispatch by one switch, the result checked.
// The methods themselves live in src/integrators/, one family per file.
#include "rigid_body_sim/integrators.hpp"

#include <cmath>
#include <stdexcept>

#include "integrators/lane_dispatch.hpp"
#include "integrators/methods.hpp"
#include "integrators/reference_steps.hpp"
#include "registry_row.hpp"
#include "integrators/runge_kutta.hpp"

namespace rigid_body {

using namespace integrators;

const std::vector<IntegratorInfo>& integratorRegistry() {
  // In the enumeration's order. type, name, order, f evaluations a step, adaptive, exact damping,
  // constant-force weight, lane kernel, summary, the lane kernel's scalar reference
  static const std::vector<IntegratorInfo> registry = {
      {IntegratorType::kExplicitEuler, "explicit_euler", 1, 1, false, false, 0.0, true, "Y += h f(Y), q normalised",
       explicitEulerReference},
      {IntegratorType::kSemiImplicitEuler, "semi_implicit_euler", 1, 1, false, false, 1.0, true,
       "momenta first, then x and q turned by the free rotation at the new L", semiImplicitEulerReference},
      {IntegratorType::kRk4, "rk4", 4, 4, false, false, 0.5, true, "classic Runge-Kutta on Y, q normalised",
       rk4Reference},
      {IntegratorType::kRkmk4, "rkmk4", 4, 4, false, false, 0.5, false,
       "Runge-Kutta-Munthe-Kaas: RK4 with q on the rotation group"},
      {IntegratorType::kBuss, "buss", 2, 1, false, false, 0.5, false, "Buss's augmented second-order rotation update"},
      {IntegratorType::kSymplecticSplitting, "symplectic_splitting", 2, 2, false, true, 0.5, false,
       "Strang splitting with exact free rotations"},
      {IntegratorType::kImplicitMidpoint, "implicit_midpoint", 2, 2, false, true, 0.5, false,
       "midpoint rule on body momentum, Cayley rotation"},
      {IntegratorType::kDopri5, "dopri5", 5, 6, true, false, 0.5, false,
       "Dormand-Prince 5(4), error control and dense output"},
  };
  return registry;
}

const IntegratorInfo& integratorInfo(IntegratorType type) {
  return registryRow(integratorRegistry(), type, "integrator");
}

const std::vector<IntegratorType>& allIntegrators() {
  static const std::vector<IntegratorType> all = [] {
    std::vector<IntegratorType> types;
    for (const IntegratorInfo& info : integratorRegistry()) types.push_back(info.type);
    return types;
  }();
  return all;
}

const std::string& integratorName(IntegratorType type) { return integratorInfo(type).name; }

std::string integratorNameList() {
  std::string list;
  for (const IntegratorInfo& info : integratorRegistry()) list += (list.empty() ? "" : ", ") + info.name;
  return list;
}

IntegratorType integratorFromName(const std::string& name) {
  for (const IntegratorInfo& info : integratorRegistry()) {
    if (name == info.name) return info.type;
  }
  throw std::invalid_argument("unknown integrator '" + name + "', valid names are: " + integratorNameList());
}

int nominalOrder(IntegratorType type) { return integratorInfo(type).order; }

bool Integrator::acceptable(const State& next) {
  // The batched steps' rule, for one lane: the same test whether a body steps alone or in a batch.
  integrators::LaneState<double> y;
  integrators::loadState(y, 0, next);
  bool ok = false;
  integrators::acceptableLanes(y, 1, &ok);
  return ok;
}

namespace {
// A lone body's step by its lane kernel: with `wide`, compiled for AVX-512 (stepOneBodyAvx512, the same bits).
template <IntegratorType kType>
StepStatus loneStep(bool wide, const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                    State& state) {
#ifdef RIGID_BODY_WIDE_LONE_STEPS
  if (wide) return stepOneBodyAvx512<kType>(model, terms, input, h, state) ? StepStatus::kOk : StepStatus::kNonFinite;
#endif
  (void)wide;
  return stepOneBody<kType>(model, terms, input, h, state) ? StepStatus::kOk : StepStatus::kNonFinite;
}
}  // namespace

void Integrator::countSteps(std::uint64_t steps) {
  statistics_.steps += steps;
  statistics_.rhs_evaluations += steps * static_cast<std::uint64_t>(info_->rhs_evaluations);
}

Integrator::Integrator(IntegratorType type, const IntegratorSettings& settings)
    : type_(type), info_(&integratorInfo(type)), settings_(settings), wide_(settings.wide_instructions && wideLoneStepsAvailable()) {}

StepStatus Integrator::step(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                            State& state) {
  if (!std::isfinite(h) || h < 0.0) return StepStatus::kInvalidStep;
  if (h == 0.0) return StepStatus::kOk;
  if (info_->lane_kernel) {  // these commit in place, and only a step that passes acceptable()'s test
    const StepStatus status = doStep(model, terms, input, h, state);
    if (status == StepStatus::kOk) ++statistics_.steps;
    return status;
  }
  State next = state;
  const StepStatus status = doStep(model, terms, input, h, next);
  if (status != StepStatus::kOk) return status;
  if (!acceptable(next)) return StepStatus::kNonFinite;
  state = next;
  ++statistics_.steps;
  return StepStatus::kOk;
}

StepStatus Integrator::doStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                              State& state) {
  if (!info_->adaptive) statistics_.rhs_evaluations += info_->rhs_evaluations;
  switch (type_) {
    case IntegratorType::kExplicitEuler:
    case IntegratorType::kSemiImplicitEuler:
    case IntegratorType::kRk4:
      return withMethod(type_, [&](auto method) {
        return loneStep<decltype(method)::value>(wide_, model, terms, input, h, state);
      });
    case IntegratorType::kRkmk4: {
      Stages<4> stages;
      state = normalised(rungeKutta(kRk4Tableau, OrientationUpdate::kLieGroup, model, terms, input, h, state, stages));
      return StepStatus::kOk;
    }
    case IntegratorType::kBuss:
      state = bussStep(model, terms, input, h, state);
      return StepStatus::kOk;
    case IntegratorType::kSymplecticSplitting:  // f's equivalent: two kicks
      return symplecticSplittingStep(model, terms, input, h, state);
    case IntegratorType::kImplicitMidpoint:
      return implicitMidpointStep(model, terms, input, h, settings_, statistics_.newton_iterations, state);
    case IntegratorType::kDopri5:
      return dopri5Step(model, terms, input, h, state);
  }
  throw std::logic_error("unhandled integrator type");
}

}  // namespace rigid_body
