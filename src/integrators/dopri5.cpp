// dopri5: Dormand–Prince 5(4) with error control and dense output, on the shared Runge–Kutta driver.
#include <algorithm>
#include <cmath>

#include "rigid_body_sim/integrators.hpp"
#include "runge_kutta.hpp"

namespace rigid_body {

using namespace integrators;

namespace {

// Dormand & Prince, "A family of embedded Runge–Kutta formulae", J. Comput. Appl. Math. 6 (1980): the
// 5th-order solution b equals the 7th stage's row (FSAL); b̂ is the embedded 4th-order one.
const Tableau<7> kDopri5Tableau = {
    {{{{0, 0, 0, 0, 0, 0, 0}},
      {{1.0 / 5, 0, 0, 0, 0, 0, 0}},
      {{3.0 / 40, 9.0 / 40, 0, 0, 0, 0, 0}},
      {{44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0, 0}},
      {{19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0, 0}},
      {{9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0, 0}},
      {{35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0}}}},
    {{35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0}}};
// b − b̂: the local error estimate is h Σ e_j k_j.
const std::array<double, 7> kDopri5ErrorWeights = {71.0 / 57600,      0, -71.0 / 16695, 71.0 / 1920,
                                                   -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
// Hairer's continuous extension of order 4 (dopri5.f, CONTD5).
const std::array<double, 7> kDopri5Dense = {-12715105075.0 / 11282082432.0, 0,
                                            87487479700.0 / 32700410799.0,  -10690763975.0 / 1880347072.0,
                                            701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                            69997945.0 / 29380423.0};

// Step-size control (Hairer, Nørsett & Wanner, Solving ODEs I, II.4): h_new = h·clamp(0.9·err^(−1/5)).
constexpr double kSafety = 0.9;
constexpr double kMinShrink = 0.2;
constexpr double kMaxGrowth = 5.0;
// dopri5 gives up (kNotConverged) after this many internal steps in one call, or below this step size
// relative to the requested one.
constexpr int kMaxInternalSteps = 100000;
constexpr double kMinRelativeStep = 1e-12;

using Vector13 = Eigen::Matrix<double, 13, 1>;

Vector13 pack(const State& s) {
  Vector13 v;
  v << s.p_WB, s.q_WB.coeffs(), s.P_W, s.L_W;
  return v;
}

Vector13 pack(const Derivative& d) {
  Vector13 v;
  v << d.p_dot, d.q_dot, d.P_dot, d.L_dot;
  return v;
}

State unpack(const Vector13& v, double t) {
  State s;
  s.p_WB = v.segment<3>(0);
  s.q_WB.coeffs() = v.segment<4>(3);
  s.P_W = v.segment<3>(7);
  s.L_W = v.segment<3>(10);
  s.t = t;
  return s;
}

bool sameState(const State& a, const State& b) {
  return a.p_WB == b.p_WB && a.q_WB.coeffs() == b.q_WB.coeffs() && a.P_W == b.P_W && a.L_W == b.L_W && a.t == b.t;
}

}  // namespace

// Adaptive Dormand–Prince 5(4) towards t + h. Internal steps follow the error control, not h; the result
// at t + h comes from the continuous extension of the internal step that contains it, so every requested
// instant is hit exactly without shortening internal steps. The internal solution (the "frontier") runs
// ahead and is continued while the caller hands back the state last returned and the same input;
// otherwise (first call, reset, a new wrench) integration restarts from the caller's state.
StepStatus Integrator::dopri5Step(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                  State& state) {
  DopriMemory& memory = dopri_;
  const double target = state.t + h;
  const bool continuing = memory.valid && sameState(state, memory.last_output) && input == memory.input;
  if (!continuing) {
    memory.valid = false;
    memory.coefficients.col(0) = pack(state);  // frontier y1 = rcont1 + rcont2 with rcont2 = 0
    memory.coefficients.col(1).setZero();
    memory.t0 = state.t;
    memory.h = 0.0;
    // A restart follows a jump in the state or the input (a new wrench, a contact impulse): the step size the
    // old trajectory allowed says nothing about the new one, so it starts again from the caller's step. (A
    // free fall lets the control grow the step without bound; taken across an impulse, the dense output of a
    // step thousands of times h loses digits to cancellation: millimetres on a box resting on the ground.)
    if (!(memory.next_h > 0.0) || memory.next_h > h) memory.next_h = h;
  }
  Stages<7> stages;
  Derivative fsal;
  bool have_fsal = false;
  int internal_steps = 0;
  // The cached step [t0, t0 + h] must contain the target.
  while (!(memory.valid && target <= memory.t0 + memory.h)) {
    const Vector13 y0_packed = memory.coefficients.col(0) + memory.coefficients.col(1);
    const State y0 = unpack(y0_packed, memory.t0 + memory.h);
    double step = memory.next_h;
    bool last_attempt_finite = true;
    for (;;) {
      if (++internal_steps > kMaxInternalSteps || step < kMinRelativeStep * h) {
        // Non-finite at every step size (a NaN input, an overflow): that is the state's problem, not the control's.
        return last_attempt_finite ? StepStatus::kNotConverged : StepStatus::kNonFinite;
      }
      const State y1 = rungeKutta(kDopri5Tableau, OrientationUpdate::kAdditive, model, terms, input, step, y0, stages,
                                  have_fsal ? &fsal : nullptr);
      statistics_.rhs_evaluations += have_fsal ? 6 : 7;
      have_fsal = true;
      fsal = stages.k[0];
      const Vector13 y1_packed = pack(y1);
      Eigen::Matrix<double, 13, 7> K;  // the stage derivatives k_1 … k_7 as columns
      for (int j = 0; j < 7; ++j) K.col(j) = pack(stages.k[j]);
      const Vector13 error = step * K * Eigen::Map<const Eigen::Matrix<double, 7, 1>>(kDopri5ErrorWeights.data());
      const Eigen::Array<double, 13, 1> scale =
          settings_.abs_tolerance + settings_.rel_tolerance * y0_packed.cwiseAbs().cwiseMax(y1_packed.cwiseAbs()).array();
      const double norm = std::sqrt((error.array() / scale).square().mean());
      last_attempt_finite = std::isfinite(norm);
      if (std::isfinite(norm) && norm <= 1.0) {
        Eigen::Matrix<double, 13, 5>& c = memory.coefficients;
        c.col(0) = y0_packed;
        c.col(1) = y1_packed - y0_packed;
        c.col(2) = step * K.col(0) - c.col(1);
        c.col(3) = c.col(1) - step * K.col(6) - c.col(2);
        c.col(4) = step * K * Eigen::Map<const Eigen::Matrix<double, 7, 1>>(kDopri5Dense.data());
        memory.t0 = y0.t;
        memory.h = step;
        memory.valid = true;
        ++statistics_.accepted_steps;
        const double growth = norm > 0.0 ? kSafety * std::pow(norm, -0.2) : kMaxGrowth;
        memory.next_h = step * std::min(kMaxGrowth, std::max(kMinShrink, growth));
        break;
      }
      ++statistics_.rejected_steps;  // k1 = f(y0), kept in fsal above, serves the retry
      const double shrink = std::isfinite(norm) ? kSafety * std::pow(norm, -0.2) : kMinShrink;
      step *= std::min(1.0, std::max(kMinShrink, shrink));
    }
    have_fsal = true;  // accepted: the frontier moved to y1, and k7 = f(y1) is the next step's k1
    fsal = stages.k[6];
  }
  // y(t0 + θh) = r1 + θ(r2 + (1 − θ)(r3 + θ(r4 + (1 − θ) r5))).
  const double theta = (target - memory.t0) / memory.h;
  const Eigen::Matrix<double, 13, 5>& c = memory.coefficients;
  const Vector13 y =
      c.col(0) + theta * (c.col(1) + (1.0 - theta) * (c.col(2) + theta * (c.col(3) + (1.0 - theta) * c.col(4))));
  state = normalised(unpack(y, target));
  memory.last_output = state;
  memory.input = input;
  return StepStatus::kOk;
}

}  // namespace rigid_body
