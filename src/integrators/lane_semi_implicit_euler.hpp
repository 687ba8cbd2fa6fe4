// Semi-implicit (symplectic) Euler as a lane kernel: the kick, the drift and the three rotation branches
// (Cayley turns about the principal axes, a symmetric top's exact flow, an isotropic body's exact turn).
// reference_steps.cpp writes the same method plainly, the version this is tested against. Internal to the
// integrators.
#pragma once

#include "lane_loading.hpp"
#include "lane_rates.hpp"

namespace rigid_body {
namespace integrators {

// ---------------------------------------------------------------------------------------------------------

// A quaternion's lanes (x, y, z, w). The turns compiled out of line (turnLanesBeyondSeries) take copies of
// what they read and write (by reference: a Lanes argument by value is passed one way in an AVX file and
// another in an SSE2 one, and both files instantiate these). A reference to the step's own state or body
// would let it escape, and GCC then kept every field of both in memory for the whole step, on every path
// (docs/performance_log.md#quaternion-copies).
template <class T>
struct LaneQuaternion {
  T x, y, z, w;
};
template <class T>
RIGID_BODY_LANE_INLINE LaneQuaternion<T> quaternionOf(const LaneState<T>& y) {
  return {y.qx, y.qy, y.qz, y.qw};
}
template <class T>
RIGID_BODY_LANE_INLINE void setQuaternion(LaneState<T>& y, const LaneQuaternion<T>& q) {
  y.qx = q.x;
  y.qy = q.y;
  y.qz = q.z;
  y.qw = q.w;
}

// The lanes of a turn whose angles are beyond halfAngleSeries's range (either of two, or not finite), one lane
// at a time: turned(i) = exact(i, unturned q) by the library's sines and cosines; the other lanes of `turned`
// (the series' turn) stay.
template <class T, class Exact>
__attribute__((noinline)) void turnLanesBeyondSeries(const T& theta2, const T& other_theta2,
                                                     const LaneQuaternion<T>& unturned, LaneQuaternion<T>& turned,
                                                     const Exact& exact) {
  for (std::size_t i = 0; i < kLaneCount<T>; ++i) {
    if (laneValue(theta2, i) <= kHalfAngleSeriesLimit && laneValue(other_theta2, i) <= kHalfAngleSeriesLimit) continue;
    const Eigen::Quaterniond q(laneValue(unturned.w, i), laneValue(unturned.x, i), laneValue(unturned.y, i),
                               laneValue(unturned.z, i));
    const Eigen::Quaterniond e = exact(i, q);
    setLane(turned.x, i, e.x());
    setLane(turned.y, i, e.y());
    setLane(turned.z, i, e.z());
    setLane(turned.w, i, e.w());
  }
}

// (c, e) ⊗ q = (c q_w − e·q_v, c q_v + q_w e + e × q_v): q turned by (c, e) in world axes.
template <class T>
RIGID_BODY_LANE_INLINE LaneQuaternion<T> turnedInWorld(const T& c, const Vec<T>& e, const LaneQuaternion<T>& q) {
  return {c * q.x + q.w * e.x + (e.y * q.z - e.z * q.y), c * q.y + q.w * e.y + (e.z * q.x - e.x * q.z),
          c * q.z + q.w * e.z + (e.x * q.y - e.y * q.x), c * q.w - (e.x * q.x + e.y * q.y + e.z * q.z)};
}
// q ⊗ (c, e) = (c q_w − q_v·e, c q_v + q_w e + q_v × e): q turned by (c, e) in body axes.
template <class T>
RIGID_BODY_LANE_INLINE LaneQuaternion<T> turnedInBody(const LaneQuaternion<T>& q, const T& c, const Vec<T>& e) {
  return {c * q.x + q.w * e.x + (q.y * e.z - q.z * e.y), c * q.y + q.w * e.y + (q.z * e.x - q.x * e.z),
          c * q.z + q.w * e.z + (q.x * e.y - q.y * e.x), c * q.w - (q.x * e.x + q.y * e.y + q.z * e.z)};
}

// Semi-implicit Euler's rotation of an isotropic body, q ← exp(h L/I₀) ⊗ q (exact: ω = L/I₀ is constant over
// the flow), in the lanes: by halfAngleSeries where a lane's angle is within its range (θ ≤ 0.25 rad), else
// by quaternionExp's sine and cosine. Each lane's choice is its own, so that a body gets the same bits in any
// batch as alone.
template <class T>
RIGID_BODY_LANE_INLINE void turnIsotropic(const LaneBody<T>& b, double h, LaneState<T>& next) {
  const Vec<T> v = ((T{} + h) * b.j0) * next.L;  // the rotation vector
  const T theta2 = v.x * v.x + v.y * v.y + v.z * v.z;
  T c, sinc;
  halfAngleSeries(theta2, c, sinc);
  const LaneQuaternion<T> unturned = quaternionOf(next);
  LaneQuaternion<T> turned = turnedInWorld(c, sinc * v, unturned);
  if (!allAtMost(theta2, kHalfAngleSeriesLimit)) {
    turnLanesBeyondSeries(theta2, T{}, unturned, turned, [v](std::size_t i, const Eigen::Quaterniond& q) {
      return quaternionExp(Eigen::Vector3d(laneValue(v.x, i), laneValue(v.y, i), laneValue(v.z, i))) * q;
    });
  }
  setQuaternion(next, turned);
}

// Semi-implicit Euler's rotation of a symmetric top by its exact flow over h at L_{n+1} (its two flows
// commute): q ← exp(h L/I_r) ⊗ q ⊗ exp(h (1/I_s − 1/I_r) m_s u), u its odd principal axis in body axes and
// m_s = u · Rᵀ L (docs/references.md), R that of q (`R`, formed for the kick too). In the lanes, by
// halfAngleSeries where both of a lane's angles are within its range, else by symmetricTopFlow's sines and
// cosines (one lane at a time, each lane's choice its own).
template <class T>
RIGID_BODY_LANE_INLINE void turnSymmetricTop(const LaneBody<T>& b, double h, const LaneRotation<T>& R,
                                             LaneState<T>& next) {
  const LaneQuaternion<T> unturned = quaternionOf(next);
  const Vec<T>& L = next.L;
  const Vec<T> m = R.s * R.R.transposeTimes(L);
  const Vec<T>& u = b.top_axis;
  const T spin = ((T{} + h) * b.top_spin_coefficient) * (u.x * m.x + u.y * m.y + u.z * m.z);  // the body turn's angle
  const T spin2 = spin * spin;
  const Vec<T> v = ((T{} + h) * b.top_inverse_pair) * L;  // the world turn's rotation vector
  const T theta2 = v.x * v.x + v.y * v.y + v.z * v.z;
  T c_spin, sinc_spin, c, sinc;
  halfAngleSeries(spin2, c_spin, sinc_spin);
  halfAngleSeries(theta2, c, sinc);
  LaneQuaternion<T> turned = turnedInWorld(c, sinc * v, turnedInBody(unturned, c_spin, (sinc_spin * spin) * u));
  if (!(allAtMost(spin2, kHalfAngleSeriesLimit) && allAtMost(theta2, kHalfAngleSeriesLimit))) {
    const std::array<const MassProperties*, kLaneCount<T>> mass = b.mass;
    const Vec<T> L_copy = L;
    turnLanesBeyondSeries(spin2, theta2, unturned, turned, [mass, L_copy, h](std::size_t i, const Eigen::Quaterniond& q) {
      if (mass[i] == nullptr) return q;  // a lane that holds no body (LaneBody::mass)
      Eigen::Quaterniond exact = q;
      symmetricTopFlow(*mass[i], h, Eigen::Vector3d(laneValue(L_copy.x, i), laneValue(L_copy.y, i), laneValue(L_copy.z, i)), exact);
      return exact;
    });
  }
  setQuaternion(next, turned);
}

/// Semi-implicit (symplectic) Euler: the momenta take the wrench of Y_n, then the configuration moves with
/// the new momenta: x += h P_{n+1}/M, and the body turns by the free rotation at L_{n+1} over h, to first
/// order, without trigonometry: about its principal axes a, b, c in turn (smallest moment first), each by the
/// Cayley rotation (1, t e_i), t = h m_i/(2 I_i), an angle 2 atan(t) = h m_i/I_i + O(h³). Each turn keeps m_i
/// and R m = L, so world L stays exact and the map is a Poisson map of the free body (a first-order splitting
/// of H = Σ m_i²/(2 I_i) into flows of functions of one m_i each): the energy error stays bounded. Turning
/// instead by exp(h ω) with ω = I⁻¹(q_n) L_{n+1} frozen over the step puts all of the error into the energy,
/// which drifts and moves the flip times (0.46 rad off on the T handle I = (1, 2, 3), ω_B = (0.01, 10, 0.01)
/// at h = 1e-5 over 20 s, against 4e-5 rad with the turns). A symmetric top turns by its exact flow
/// (turnSymmetricTop) and an isotropic body by exp(h L/I₀), which is exact (turnIsotropic).
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneSemiImplicitEulerStep(const LaneBody<T>& b, const StepTerms& terms, double h,
                                              const LaneState<T>& y) {
  // The kick needs ω only for angular damping. R of q_n, which the Cayley turns and a symmetric top's flow
  // need, is formed once for the kick and the turn.
  const bool turn_by_R = terms.rotation && terms.world_inertia;
  const LaneRotation<T> R = turn_by_R ? LaneRotation<T>(y) : LaneRotation<T>{};
  const Vec<T> v = b.inverse_mass * y.P;
  Vec<T> force, torque, w;  // w = ½ω
  laneWrench(b, terms, terms.angular_damping, y, v, turn_by_R ? &R : nullptr, force, torque, w);
  const T step = T{} + h;
  LaneState<T> next = y;
  next.P = y.P + step * force;
  next.p = y.p + (h * b.inverse_mass) * next.P;
  next.t = y.t + h;
  if (!terms.rotation) return next;
  next.L = y.L + step * torque;
  if (!terms.world_inertia || b.symmetric_top) {
    if (terms.world_inertia) {
      turnSymmetricTop(b, h, R, next);
    } else {
      turnIsotropic(b, h, next);
    }
    normaliseQuaternion(next);
    return next;
  }
  // The body momentum in principal axes, m = R_BPᵀ R_WBᵀ L_{n+1}, with R of q_n, kicked in body axes:
  // Rᵀ L_{n+1} = Rᵀ L_n + h (u_τB − c ω_B + Rᵀ u_τW). Equal to turning the world L_{n+1} above (to rounding),
  // but it does not wait for it: the world torque's turn into world axes and back leaves the critical path.
  Vec<T> torque_B = terms.input && b.body_torque ? b.torque_B : Vec<T>{T{}, T{}, T{}};
  if (terms.angular_damping) torque_B = torque_B - (b.angular_damping + b.angular_damping) * w;  // w = ½ω_B
  if (terms.input && b.world_torque) torque_B = torque_B + R.s * R.R.transposeTimes(b.torque_W);
  const Vec<T> kicked = R.s * R.R.transposeTimes(y.L) + step * torque_B;
  const Vec<T> m = b.principal_body ? kicked : b.principal_axes.transposeTimes(kicked);
  // Turn a about e₀ by t₀ = a₀ m₀ (a_i = h/(2 I_i)); it turns m by the rational rotation of D₀ = 1 + t₀²,
  // so t₁ = a₁ N₁/D₀; turn b moves m₂ by the rotation of 1 + t₁², so t₂ = C/E. The three turns' product
  // (1 + t₀ i)(1 + t₁ j)(1 + t₂ k) = (1 − t₀t₁t₂, t₀ + t₁t₂, t₁ − t₀t₂, t₂ + t₀t₁) (ik = −j, jk = i, k² = −1),
  // times the common denominator D₀ E, needs no division at all: the normalisation is the one square root
  // and division of the whole rotation, and near 1 not even those (inverseNormNear).
  const Vec<T> a = (T{} + 0.5 * h) * b.inverse_principal;
  const T t0 = a.x * m.x;
  const T D0 = 1.0 + t0 * t0, c0 = 1.0 - t0 * t0, s0 = 2.0 * t0;
  const T N1 = c0 * m.y + s0 * m.z;   // D₀ m₁ after turn a
  const T N2 = c0 * m.z - s0 * m.y;   // D₀ m₂ after turn a
  const T A = a.y * N1;               // t₁ = A/D₀
  const T D0sq = D0 * D0, Asq = A * A;
  const T E = D0 * (D0sq + Asq);      // t₂ = C/E
  const T C = a.z * ((D0sq - Asq) * N2 + 2.0 * A * D0sq * m.x);
  const T rw = D0 * E - t0 * A * C;
  const Vec<T> r_P{t0 * D0 * E + A * C, A * E - t0 * D0 * C, C * D0 + t0 * A * E};
  const Vec<T> r = b.principal_body ? r_P : b.principal_axes * r_P;  // r_B = R_BP r_P
  setQuaternion(next, turnedInBody(quaternionOf(y), rw, r));  // q ← q ⊗ (rw, r)
  // |q ⊗ r|² = |q|² |r|², r = (1 + t₀ i)(D₀ + A j)(E + C k) (multiplied out above), so |r|² = D₀ (D₀² + A²)
  // (E² + C²) = E (E² + C²): three operations after C, where rw² + |r_P|² waited for r itself.
  scaleQuaternion(next, inverseNormNear((quaternionNorm2(y) * E) * (E * E + C * C)));
  return next;
}

}  // namespace integrators
}  // namespace rigid_body

