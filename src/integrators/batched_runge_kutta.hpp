// Explicit Euler and RK4 written once for a "lane" type T: T = double steps one body, T = Lanes (four
// doubles, a GCC/Clang vector) steps four bodies at once, one in each lane. Both instantiations run the same
// operations in the same order on each body, and vector arithmetic rounds element by element as scalar
// arithmetic does, so a body's step is the same bit for bit whether it runs alone or in a batch (tested).
// Internal to the integrators (not installed).
//
// The step is the state-space form of dynamics.hpp with the classic tableaux of runge_kutta.hpp: Y = (x, q,
// P, L), ẋ = P/M, q̇ = ½ [0, ω] ⊗ q, Ṗ = F, L̇ = τ, ω = R I_Bcm_B⁻¹ Rᵀ L, the quaternion added to like any other
// component and normalised after the step. What differs from the generic driver is the arrangement:
//   - R is formed from the stage's q without dividing by |q|² (R_u = |q|² R, since every entry is quadratic
//     in q), and 1/|q|² is applied at the end of each product that uses R. The division then runs beside the
//     products instead of before them: a stage is a chain q → R → Rᵀ L → I⁻¹ → R → q̇, and the division no
//     longer sits at its head.
//   - a stage is built straight from the previous stage's rates (Y + a h k), with no copies of whole states.
#pragma once

#include <cmath>
#include <cstddef>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"

// Lanes pass by value between inline functions of this header only: GCC's note that the calling convention of
// a 32-byte vector differs with and without AVX concerns no boundary here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace rigid_body {
namespace integrators {

/// Four doubles operated on element by element (GCC vector extension; 2 × SSE2 by default, one AVX register
/// where the build enables it).
typedef double Lanes __attribute__((vector_size(32)));
constexpr std::size_t kLanes = 4;

// v ← √v, lane by lane (the vector extension has no square root of its own).
inline void laneSqrt(double& v) { v = std::sqrt(v); }
inline void laneSqrt(Lanes& v) {
  for (std::size_t i = 0; i < kLanes; ++i) v[i] = std::sqrt(v[i]);
}

template <class T>
struct Vec {
  T x, y, z;
};
template <class T>
inline Vec<T> operator+(const Vec<T>& a, const Vec<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
inline Vec<T> operator-(const Vec<T>& a, const Vec<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
inline Vec<T> operator*(const T& s, const Vec<T>& a) { return {s * a.x, s * a.y, s * a.z}; }

/// The mutable state of a lane: x, q (x, y, z, w), P, L and the time.
template <class T>
struct LaneState {
  Vec<T> p, P, L;
  T qx, qy, qz, qw;
  T t;
};

/// Ẏ of a lane.
template <class T>
struct LaneRates {
  Vec<T> p, P, L;
  T qx, qy, qz, qw;
};

/// The constants of a lane over a step: mass properties, force models and the input (held over the step).
template <class T>
struct LaneBody {
  T inverse_mass;
  T j0;                                 // I⁻¹(0, 0): ω = j0 L for an isotropic body (terms.world_inertia off)
  T jxx, jyy, jzz, jxy, jxz, jyz;       // I_Bcm_B⁻¹, symmetric
  Vec<T> weight;                        // M g
  T linear_damping, angular_damping;
  Vec<T> force_W, torque_W, force_B, torque_B;  // the applied wrench: world and body parts
};

// Y + c k, every component (q, L only with the rotation term: without it their rates are zero).
template <class T>
inline LaneState<T> advanced(const LaneState<T>& y, const T& c, const LaneRates<T>& k, bool rotation) {
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

/// Ẏ = f(Y, u) with the assembled terms only (uniform over the lanes).
template <class T>
inline LaneRates<T> laneRates(const LaneBody<T>& b, const StepTerms& terms, const LaneState<T>& y) {
  LaneRates<T> k;
  const Vec<T> v = b.inverse_mass * y.P;
  k.p = v;
  Vec<T> force = T{} * v;  // zeros of the lane type
  Vec<T> torque = force;
  Vec<T> w = force;
  const bool need_R = terms.input || (terms.rotation && terms.world_inertia);
  if (need_R) {
    const T x = y.qx, yq = y.qy, z = y.qz, q0 = y.qw;
    // R_u = |q|² R(q/|q|): R's usual entries with 1 − 2(y² + z²) written as w² + x² − y² − z².
    const T xx = x * x, yy = yq * yq, zz = z * z, ww = q0 * q0;
    const T xy = x * yq, xz = x * z, yz = yq * z, wx = q0 * x, wy = q0 * yq, wz = q0 * z;
    const T r00 = ww + xx - yy - zz, r11 = ww - xx + yy - zz, r22 = ww - xx - yy + zz;
    const T r01 = 2.0 * (xy - wz), r10 = 2.0 * (xy + wz);
    const T r02 = 2.0 * (xz + wy), r20 = 2.0 * (xz - wy);
    const T r12 = 2.0 * (yz - wx), r21 = 2.0 * (yz + wx);
    const T s = 1.0 / (xx + yy + zz + ww);  // beside the products, not before them
    const auto turn = [&](const Vec<T>& a) {  // R_u a
      return Vec<T>{r00 * a.x + r01 * a.y + r02 * a.z, r10 * a.x + r11 * a.y + r12 * a.z,
                    r20 * a.x + r21 * a.y + r22 * a.z};
    };
    if (terms.rotation && terms.world_inertia) {
      // ω = R I⁻¹ Rᵀ L = s² R_u (I⁻¹ (R_uᵀ L))
      const Vec<T> a{r00 * y.L.x + r10 * y.L.y + r20 * y.L.z, r01 * y.L.x + r11 * y.L.y + r21 * y.L.z,
                     r02 * y.L.x + r12 * y.L.y + r22 * y.L.z};
      const Vec<T> c{b.jxx * a.x + b.jxy * a.y + b.jxz * a.z, b.jxy * a.x + b.jyy * a.y + b.jyz * a.z,
                     b.jxz * a.x + b.jyz * a.y + b.jzz * a.z};
      w = (s * s) * turn(c);
    }
    if (terms.input) {
      force = b.force_W + s * turn(b.force_B);
      torque = b.torque_W + s * turn(b.torque_B);
    }
  }
  if (terms.rotation && !terms.world_inertia) w = b.j0 * y.L;
  if (terms.gravity) force = force + b.weight;
  if (terms.linear_damping) force = force - b.linear_damping * v;
  k.P = force;
  if (terms.rotation) {
    if (terms.angular_damping) torque = torque - b.angular_damping * w;
    k.L = torque;
    // q̇ = ½ [0, ω] ⊗ q
    k.qx = 0.5 * (w.x * y.qw + w.y * y.qz - w.z * y.qy);
    k.qy = 0.5 * (w.y * y.qw + w.z * y.qx - w.x * y.qz);
    k.qz = 0.5 * (w.z * y.qw + w.x * y.qy - w.y * y.qx);
    k.qw = -0.5 * (w.x * y.qx + w.y * y.qy + w.z * y.qz);
  } else {
    k.L = force;  // unused: q and L keep their values without the rotation term
    k.qx = k.qy = k.qz = k.qw = T{};
  }
  return k;
}

// q ← q/|q|
template <class T>
inline void normaliseQuaternion(LaneState<T>& y) {
  T norm = y.qx * y.qx + y.qy * y.qy + y.qz * y.qz + y.qw * y.qw;
  laneSqrt(norm);
  const T inverse_norm = 1.0 / norm;
  y.qx = y.qx * inverse_norm;
  y.qy = y.qy * inverse_norm;
  y.qz = y.qz * inverse_norm;
  y.qw = y.qw * inverse_norm;
}

/// Explicit Euler: Y + h f(Y), q normalised.
template <class T>
inline LaneState<T> laneEulerStep(const LaneBody<T>& b, const StepTerms& terms, double h, const LaneState<T>& y) {
  LaneState<T> next = advanced(y, T{} + h, laneRates(b, terms, y), terms.rotation);
  normaliseQuaternion(next);
  next.t = y.t + h;
  return next;
}

/// Classic RK4: k1 = f(Y), k2 = f(Y + h/2 k1), k3 = f(Y + h/2 k2), k4 = f(Y + h k3),
/// Y + h/6 k1 + h/3 k2 + h/3 k3 + h/6 k4, q normalised.
template <class T>
inline LaneState<T> laneRk4Step(const LaneBody<T>& b, const StepTerms& terms, double h, const LaneState<T>& y) {
  const bool rotation = terms.rotation;
  const T half = T{} + 0.5 * h, whole = T{} + h, sixth = T{} + h / 6.0;
  const LaneRates<T> k1 = laneRates(b, terms, y);
  const LaneRates<T> k2 = laneRates(b, terms, advanced(y, half, k1, rotation));
  const LaneRates<T> k3 = laneRates(b, terms, advanced(y, half, k2, rotation));
  const LaneRates<T> k4 = laneRates(b, terms, advanced(y, whole, k3, rotation));
  // Y + h/6 k1 + h/3 k2 + h/3 k3 + h/6 k4, each rate scaled before the sum: rates near the largest double
  // (a wrench of 1e308 N) then overflow no sooner than the state they move.
  const T third = T{} + h / 3.0;
  LaneState<T> next = advanced(advanced(advanced(advanced(y, sixth, k1, rotation), third, k2, rotation), third, k3, rotation),
                               sixth, k4, rotation);
  normaliseQuaternion(next);
  next.t = y.t + h;
  return next;
}

// ---------------------------------------------------------------------------------------------------------
// Loading bodies into lanes and back. For T = double there is one lane (lane index 0).

inline void setLane(double& v, std::size_t, double value) { v = value; }
inline void setLane(Lanes& v, std::size_t i, double value) { v[i] = value; }
inline double laneValue(const double& v, std::size_t) { return v; }
inline double laneValue(const Lanes& v, std::size_t i) { return v[i]; }

template <class T>
inline void setLane(Vec<T>& to, std::size_t i, const Eigen::Vector3d& from) {
  setLane(to.x, i, from.x());
  setLane(to.y, i, from.y());
  setLane(to.z, i, from.z());
}

template <class T>
inline void loadBody(LaneBody<T>& b, std::size_t i, const Model& model, const AppliedWrench& input) {
  const Eigen::Matrix3d& J = model.mass.inverseInertia();
  setLane(b.inverse_mass, i, model.mass.inverseMass());
  setLane(b.j0, i, J(0, 0));
  setLane(b.jxx, i, J(0, 0));
  setLane(b.jyy, i, J(1, 1));
  setLane(b.jzz, i, J(2, 2));
  setLane(b.jxy, i, J(0, 1));
  setLane(b.jxz, i, J(0, 2));
  setLane(b.jyz, i, J(1, 2));
  setLane(b.weight, i, model.mass.mass() * model.forces.gravity_W);
  setLane(b.linear_damping, i, model.forces.linear_damping);
  setLane(b.angular_damping, i, model.forces.angular_damping);
  setLane(b.force_W, i, input.world.force);
  setLane(b.torque_W, i, input.world.torque);
  setLane(b.force_B, i, input.body.force);
  setLane(b.torque_B, i, input.body.torque);
}

template <class T>
inline void loadState(LaneState<T>& y, std::size_t i, const State& state) {
  setLane(y.p, i, state.p_WB);
  setLane(y.P, i, state.P_W);
  setLane(y.L, i, state.L_W);
  setLane(y.qx, i, state.q_WB.x());
  setLane(y.qy, i, state.q_WB.y());
  setLane(y.qz, i, state.q_WB.z());
  setLane(y.qw, i, state.q_WB.w());
  setLane(y.t, i, state.t);
}

/// Lane i of y into `state`.
template <class T>
inline void storeState(const LaneState<T>& y, std::size_t i, State& state) {
  state.t = laneValue(y.t, i);
  state.p_WB = Eigen::Vector3d(laneValue(y.p.x, i), laneValue(y.p.y, i), laneValue(y.p.z, i));
  state.P_W = Eigen::Vector3d(laneValue(y.P.x, i), laneValue(y.P.y, i), laneValue(y.P.z, i));
  state.L_W = Eigen::Vector3d(laneValue(y.L.x, i), laneValue(y.L.y, i), laneValue(y.L.z, i));
  state.q_WB.coeffs() << laneValue(y.qx, i), laneValue(y.qy, i), laneValue(y.qz, i), laneValue(y.qw, i);
}

/// Whether each lane of a step's result may be committed, as Integrator::acceptable says of a State: every
/// component finite (their sum times zero is 0, not NaN) and |q| within 1e-6 of 1 (|q|² compared instead).
/// Writes one flag per lane into ok[0 … lanes).
template <class T>
inline void acceptableLanes(const LaneState<T>& y, std::size_t lanes, bool* ok) {
  const T zero{};
  const T probe = zero * (y.p.x + y.p.y + y.p.z + y.P.x + y.P.y + y.P.z + y.L.x + y.L.y + y.L.z + y.t) +
                  zero * (y.qx + y.qy + y.qz + y.qw);
  const T norm2 = y.qx * y.qx + y.qy * y.qy + y.qz * y.qz + y.qw * y.qw;
  constexpr double kLow = (1.0 - 1e-6) * (1.0 - 1e-6), kHigh = (1.0 + 1e-6) * (1.0 + 1e-6);
  for (std::size_t i = 0; i < lanes; ++i) {
    const double n2 = laneValue(norm2, i);
    ok[i] = laneValue(probe, i) == 0.0 && n2 >= kLow && n2 <= kHigh;
  }
}

/// Whether a method steps by these kernels.
inline bool hasLaneStep(IntegratorType type) {
  return type == IntegratorType::kRk4 || type == IntegratorType::kExplicitEuler;
}

/// One step of a method with a lane kernel (hasLaneStep), for the lanes as T holds them.
template <class T>
inline LaneState<T> laneStep(IntegratorType type, const LaneBody<T>& b, const StepTerms& terms, double h,
                             const LaneState<T>& y) {
  return type == IntegratorType::kRk4 ? laneRk4Step(b, terms, h, y) : laneEulerStep(b, terms, h, y);
}

/// One body's step by its lane kernel, T = double: what Integrator::step runs for these methods.
inline State laneStep(IntegratorType type, const Model& model, const StepTerms& terms, const AppliedWrench& input,
                      double h, const State& y) {
  LaneBody<double> b;
  loadBody(b, 0, model, input);
  LaneState<double> lanes;
  loadState(lanes, 0, y);
  State next;
  storeState(laneStep(type, b, terms, h, lanes), 0, next);
  return next;
}

}  // namespace integrators
}  // namespace rigid_body

#pragma GCC diagnostic pop
