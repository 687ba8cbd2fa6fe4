// Explicit Euler and classic RK4 as lane kernels: the tableaux of runge_kutta.hpp, the quaternion added to
// like any other component and normalised after the step, each stage built straight from the previous
// stage's rates (Y + a h k), with no copies of whole states. reference_steps.cpp is the same method
// through the generic driver, the readable version these are tested against. Internal to the integrators.
#pragma once

#include "lane_rates.hpp"

namespace rigid_body {
namespace integrators {

// Y + c k, every component (q, L only with the rotation term: without it their rates are zero).
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> advanced(const LaneState<T>& y, const T& c, const LaneRates<T>& k, bool rotation) {
  LaneState<T> s = y;
  s.p = y.p + c * k.p;
  s.P = y.P + c * k.P;
  if (rotation) {
    s.L = y.L + c * k.L;
    s.qx = y.qx + c * k.qx;
    s.qy = y.qy + c * k.qy;
    s.qz = y.qz + c * k.qz;
    s.qw = y.qw + c * k.qw;
  }
  return s;
}

/// Explicit Euler: Y + h f(Y), q normalised.
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneEulerStep(const LaneBody<T>& b, const StepTerms& terms, double h, const LaneState<T>& y) {
  LaneState<T> next = advanced(y, T{} + h, laneRates(b, terms, y), terms.rotation);
  if (terms.rotation) normaliseQuaternion(next);  // without it q is y's, untouched
  next.t = y.t + h;
  return next;
}

// RK4's last touch: q normalised (without the rotation term q is y's, untouched) and the time set.
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneRk4End(LaneState<T> next, bool rotation, const T& t) {
  if (rotation) normaliseQuaternion(next);
  next.t = t;
  return next;
}

/// Classic RK4: k1 = f(Y), k2 = f(Y + h/2 k1), k3 = f(Y + h/2 k2), k4 = f(Y + h k3),
/// Y + h/6 k1 + h/3 k2 + h/3 k3 + h/6 k4, q normalised.
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneRk4Step(const LaneBody<T>& b, const StepTerms& terms, double h, const LaneState<T>& y) {
  const bool rotation = terms.rotation;
  const T half = T{} + 0.5 * h, whole = T{} + h, sixth = T{} + h / 6.0;
  // Y + h/6 k1 + h/3 k2 + h/3 k3 + h/6 k4, each rate scaled before the sum: rates near the largest double
  // (a wrench of 1e308 N) then overflow no sooner than the state they move. The same sums in the same order
  // (so the same bits) either way, but one lane adds each rate as it arrives and four lanes add them after
  // the last stage: GCC's registers follow the code as written, and each order is the faster one for its
  // lane count (docs/performance_log.md#rk4-sums).
  if constexpr (kLaneCount<T> == 1) {
    const T third = T{} + h / 3.0;
    LaneRates<T> k = laneRates(b, terms, y);
    LaneState<T> sum = advanced(y, sixth, k, rotation);
    k = laneRates(b, terms, advanced(y, half, k, rotation));
    sum = advanced(sum, third, k, rotation);
    k = laneRates(b, terms, advanced(y, half, k, rotation));
    sum = advanced(sum, third, k, rotation);
    k = laneRates(b, terms, advanced(y, whole, k, rotation));
    return laneRk4End(advanced(sum, sixth, k, rotation), rotation, y.t + h);
  } else {
    const LaneRates<T> k1 = laneRates(b, terms, y);
    const LaneRates<T> k2 = laneRates(b, terms, advanced(y, half, k1, rotation));
    const LaneRates<T> k3 = laneRates(b, terms, advanced(y, half, k2, rotation));
    const LaneRates<T> k4 = laneRates(b, terms, advanced(y, whole, k3, rotation));
    const T third = T{} + h / 3.0;
    return laneRk4End(
        advanced(advanced(advanced(advanced(y, sixth, k1, rotation), third, k2, rotation), third, k3, rotation),
                 sixth, k4, rotation),
        rotation, y.t + h);
  }
}

}  // namespace integrators
}  // namespace rigid_body

