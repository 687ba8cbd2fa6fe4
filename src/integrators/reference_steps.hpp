// The readable scalar versions of the methods whose Integrator step is a lane kernel (explicit Euler, rk4,
// semi-implicit Euler): each written as its equations read, on Eigen types, through dynamics.hpp's
// derivative(), with none of the kernels' arrangement (unnormalised R, body-axes ω, constants in lanes).
// They are what the kernels mean; test_integrators checks that every kernel matches its reference to
// rounding. Named by the registry row (IntegratorInfo::reference_step). Internal to the integrators.
#pragma once

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {
namespace integrators {

/// Y + h f(Y), q normalised: the generic Runge–Kutta driver with explicit Euler's tableau.
State explicitEulerReference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                             const State& y);
/// Classic RK4 through the generic driver with its tableau (runge_kutta.hpp), q normalised.
State rk4Reference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, const State& y);
/// Semi-implicit Euler: kick by the wrench of Y_n, drift x with P_{n+1}, turn q by the free rotation at
/// L_{n+1} (three Cayley turns about the principal axes, a symmetric top's exact flow, or an isotropic
/// body's exact turn), each turn applied one after the other as the method states it.
State semiImplicitEulerReference(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                 const State& y);

}  // namespace integrators
}  // namespace rigid_body
