// f(Y) in the lanes: the wrench of a body's assembled terms and the state's rates, for the kernels of
// lane_runge_kutta.hpp and lane_semi_implicit_euler.hpp. Internal to the integrators.
//
// The rates are those of the state-space form of dynamics.hpp: Y = (x, q, P, L), ẋ = P/M,
// q̇ = ½ [0, ω] ⊗ q, Ṗ = F, L̇ = τ, ω = R I_Bcm_B⁻¹ Rᵀ L, arranged for speed (same values to rounding as
// dynamics.hpp's derivative(), which reference_steps.cpp uses):
//   - R is formed from the stage's q without dividing by |q|² (R_u = |q|² R, since every entry is quadratic
//     in q), and 1/|q|² is applied at the end of each product that uses R. The division then runs beside the
//     products instead of before them.
//   - a body with a full inertia tensor turns with its angular velocity in body axes, ω_B = I_Bcm_B⁻¹ Rᵀ L,
//     and q̇ = ½ q ⊗ [0, ω_B], which is ½ [0, R ω_B] ⊗ q for any q ≠ 0 (R v = q v q*/|q|², so
//     (R v) ⊗ q = q v (q* q)/|q|² = q ⊗ v): the same f, without turning ω back into world axes. A stage
//     is then the chain q → R → Rᵀ L → I⁻¹ → q̇, one matrix product shorter; the angular damping torque
//     −c ω = R (−c ω_B) is turned into world axes together with the input's body torque, in one product.
//   - the input's body force and body torque are turned into world axes only if some lane has one (b.body_force,
//     b.body_torque): a wrench sent in the world frame costs no rotation (and semi-implicit Euler turns the
//     input's world torque into body axes only if some lane has one, b.world_torque).
#pragma once

#include "lane_math.hpp"

namespace rigid_body {
namespace integrators {

// The wrench of the assembled terms at y, and ½ω if `need_w` (else ω stays zero and so does the angular
// damping): force = u_F + M g − c v, torque = u_τ − c_ω ω. ω is in body axes (ω_B = I⁻¹ Rᵀ L) with
// terms.world_inertia and in world axes (ω = L/I₀) without it; half of it, as q̇ needs it (halving is exact:
// the same bits as halving q̇). `rotation` is y's, if the caller has formed it already; otherwise it is formed
// here when a term needs it.
template <class T>
RIGID_BODY_LANE_INLINE void laneWrench(const LaneBody<T>& b, const StepTerms& terms, bool need_w, const LaneState<T>& y,
                                       const Vec<T>& v, const LaneRotation<T>* rotation, Vec<T>& force,
                                       Vec<T>& torque, Vec<T>& half_w) {
  const Vec<T> zero{T{}, T{}, T{}};
  force = torque = half_w = zero;
  const bool body_w = need_w && terms.world_inertia;
  const bool body_force = terms.input && b.body_force;
  // The torque with a part in body axes: the input's and, with ω_B, the angular damping's.
  const bool body_torque = (terms.input && b.body_torque) || (body_w && terms.angular_damping);
  if (body_w || body_force || body_torque) {
    const LaneRotation<T> R = rotation != nullptr ? *rotation : LaneRotation<T>(y);
    // ω_B = I⁻¹ Rᵀ L = s X with X = I⁻¹ (R_uᵀ L); s is applied last, beside the chain.
    const Vec<T> X = body_w ? b.inverse_inertia * R.R.transposeTimes(y.L) : zero;
    if (body_w) half_w = (0.5 * R.s) * X;
    if (body_force) force = R.s * (R.R * b.force_B);
    if (body_torque) {  // s R_u (u_τB − c ω_B), as R_u (s u_τB − c s² X): s and c s² beside the chain
      Vec<T> torque_B = terms.input && b.body_torque ? R.s * b.torque_B : zero;
      if (body_w && terms.angular_damping) torque_B = torque_B - (b.angular_damping * (R.s * R.s)) * X;
      torque = R.R * torque_B;
    }
  }
  if (terms.input) {
    force = force + b.force_W;
    torque = torque + b.torque_W;
  }
  if (need_w && !terms.world_inertia) {
    const Vec<T> w = b.j0 * y.L;
    half_w = (T{} + 0.5) * w;
    if (terms.angular_damping) torque = torque - b.angular_damping * w;
  }
  if (terms.gravity) force = force + b.weight;
  if (terms.linear_damping) force = force - b.linear_damping * v;
}

/// Ẏ = f(Y, u) with the assembled terms only (uniform over the lanes).
template <class T>
RIGID_BODY_LANE_INLINE LaneRates<T> laneRates(const LaneBody<T>& b, const StepTerms& terms, const LaneState<T>& y) {
  LaneRates<T> k;
  const Vec<T> v = b.inverse_mass * y.P;
  k.p = v;
  Vec<T> w;  // ½ω
  laneWrench(b, terms, terms.rotation, y, v, static_cast<const LaneRotation<T>*>(nullptr), k.P, k.L, w);
  if (terms.rotation && terms.world_inertia) {
    // q̇ = q ⊗ [0, ½ω_B]
    k.qx = w.x * y.qw + w.z * y.qy - w.y * y.qz;
    k.qy = w.y * y.qw + w.x * y.qz - w.z * y.qx;
    k.qz = w.z * y.qw + w.y * y.qx - w.x * y.qy;
    k.qw = -(w.x * y.qx + w.y * y.qy + w.z * y.qz);
  } else if (terms.rotation) {
    // q̇ = [0, ½ω] ⊗ q, ω in world axes
    k.qx = w.x * y.qw + w.y * y.qz - w.z * y.qy;
    k.qy = w.y * y.qw + w.z * y.qx - w.x * y.qz;
    k.qz = w.z * y.qw + w.x * y.qy - w.y * y.qx;
    k.qw = -(w.x * y.qx + w.y * y.qy + w.z * y.qz);
  } else {
    k.qx = k.qy = k.qz = k.qw = T{};  // q and L keep their values without the rotation term
  }
  return k;
}

}  // namespace integrators
}  // namespace rigid_body

