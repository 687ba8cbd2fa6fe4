// The explicit Runge–Kutta driver and its tableaux, shared by rkmk4 and dopri5 (explicit_euler and rk4 have
// their own arrangement of the same steps, for one body or four at once: lane_runge_kutta.hpp; the plain
// versions through this driver are reference_steps.cpp).
// Internal to the integrators (not installed).
#pragma once

#include <array>
#include <cstddef>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {
namespace integrators {

// Explicit Runge–Kutta on the state, shared by rkmk4 and dopri5.
//
// Stage i: Y_i = Y + h Σ_{j<i} a_ij k_j, k_i = f(Y_i); the step: Y + h Σ b_j k_j.
// The orientation is either added to like any other component (kAdditive: classic RK on the quaternion's
// coefficients, q normalised after the step) or moved on the rotation group (kLieGroup: Munthe-Kaas,
// Hairer–Lubich–Wanner IV.8): q_i = exp(Θ_i) ⊗ q with Θ_i = h Σ a_ij K_j and K_i = dexp⁻¹_{Θ_i}(ω_i),
// dexp⁻¹_Θ(ω) = ω − ½ Θ×ω + 1/12 Θ×(Θ×ω) (truncated after the terms an order-4 method needs).

enum class OrientationUpdate { kAdditive, kLieGroup };

template <std::size_t S>
struct Tableau {
  std::array<std::array<double, S>, S> a;  // a[i][j], j < i
  std::array<double, S> b;
};

template <std::size_t S>
struct Stages {
  std::array<Derivative, S> k;
  std::array<Eigen::Vector3d, S> algebra;  // K_i (kLieGroup only)
};

inline Eigen::Vector3d dexpInverse(const Eigen::Vector3d& theta, const Eigen::Vector3d& w) {
  const Eigen::Vector3d theta_w = theta.cross(w);
  return w - 0.5 * theta_w + theta.cross(theta_w) / 12.0;
}

// Y + h Σ_{j<count} weights_j k_j; for kLieGroup also returns Θ. Without the rotation term q and L are
// left as they are (their rates are zero).
template <std::size_t S>
inline State combine(const State& y, const Stages<S>& stages, const std::array<double, S>& weights, std::size_t count, double h,
              OrientationUpdate mode, bool rotation, Eigen::Vector3d* theta) {
  State next = y;
  Eigen::Vector4d q_sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d algebra_sum = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < count; ++j) {
    const double w = h * weights[j];
    if (w == 0.0) continue;
    const Derivative& k = stages.k[j];
    next.p_WB += w * k.p_dot;
    next.P_W += w * k.P_dot;
    if (!rotation) continue;
    next.L_W += w * k.L_dot;
    if (mode == OrientationUpdate::kAdditive) {
      q_sum += w * k.q_dot;
    } else {
      algebra_sum += w * stages.algebra[j];
    }
  }
  if (!rotation) {
    if (theta) theta->setZero();
  } else if (mode == OrientationUpdate::kAdditive) {
    next.q_WB.coeffs() += q_sum;
  } else {
    next.q_WB = quaternionExp(algebra_sum) * y.q_WB;
    if (theta) *theta = algebra_sum;
  }
  return next;
}

// Runs the stages and returns Y_{n+1} (t advanced by h, q not normalised). `first`, if given, is f(Y)
// already known (FSAL).
template <std::size_t S>
inline State rungeKutta(const Tableau<S>& tableau, OrientationUpdate mode, const Model& model, const StepTerms& terms,
                 const AppliedWrench& input, double h, const State& y, Stages<S>& stages, const Derivative* first = nullptr) {
  for (std::size_t i = 0; i < S; ++i) {
    Eigen::Vector3d theta = Eigen::Vector3d::Zero();
    if (i == 0 && first) {
      stages.k[0] = *first;
    } else {
      const State stage = i == 0 ? y : combine(y, stages, tableau.a[i], i, h, mode, terms.rotation, &theta);
      stages.k[i] = derivative(model, terms, stage, input);
    }
    if (mode == OrientationUpdate::kLieGroup) stages.algebra[i] = dexpInverse(theta, stages.k[i].w_WB_W);
  }
  State next = combine(y, stages, tableau.b, S, h, mode, terms.rotation, nullptr);
  next.t = y.t + h;
  return next;
}

// Classic RK4: c = (0, ½, ½, 1), b = (1/6, 1/3, 1/3, 1/6).
inline const Tableau<4> kRk4Tableau = {{{{{0, 0, 0, 0}}, {{0.5, 0, 0, 0}}, {{0, 0.5, 0, 0}}, {{0, 0, 1, 0}}}},
                                {{1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6}}};


/// Every method ends a step with a unit quaternion: those that move q off the unit sphere project back.
inline State normalised(State state) {
  state.q_WB.normalize();
  return state;
}

}  // namespace integrators
}  // namespace rigid_body
