// Explicit Euler, RK4 and semi-implicit Euler written once for a "lane" type T: T = double steps one body,
// T = Lanes (four doubles, a GCC/Clang vector) steps four bodies at once, one in each lane. Both
// instantiations run the same operations in the same order on each body, and vector arithmetic rounds
// element by element as scalar arithmetic does, so a body's step is the same bit for bit whether it runs
// alone or in a batch (tested). Internal to the integrators (not installed).
//
// The steps are those of the state-space form of dynamics.hpp: Y = (x, q, P, L), ẋ = P/M,
// q̇ = ½ [0, ω] ⊗ q, Ṗ = F, L̇ = τ, ω = R I_Bcm_B⁻¹ Rᵀ L. Explicit Euler and RK4 use the classic tableaux of
// runge_kutta.hpp, the quaternion added to like any other component and normalised after the step; what
// differs from the generic driver is the arrangement:
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
//   - a stage is built straight from the previous stage's rates (Y + a h k), with no copies of whole states.
// Semi-implicit Euler: see laneSemiImplicitEulerStep.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "methods.hpp"

// Lanes pass by value between inline functions of this header only: GCC's note that the calling convention of
// a 32-byte vector differs with and without AVX concerns no boundary here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

// The step's pieces, down to the vector operators and the loads and stores, are inlined into each other
// whatever the compiler's size heuristics say: left to them, GCC kept laneWrench and the semi-implicit step
// as calls (perf), each a stack frame of lane structs, and under link-time optimisation its choices for the
// small helpers followed its budget for the whole library, so that edits to other files moved the lone step
// (docs/performance_log.md#forced-inlining).
#define RIGID_BODY_LANE_INLINE inline __attribute__((always_inline))

namespace rigid_body {
namespace integrators {

/// Four doubles operated on element by element (GCC vector extension; 2 × SSE2 by default, one AVX register
/// where the build enables it).
typedef double Lanes __attribute__((vector_size(32)));
constexpr std::size_t kLanes = 4;
/// The bodies a lane type holds: 1 for double, kLanes for Lanes.
template <class T>
constexpr std::size_t kLaneCount = sizeof(T) / sizeof(double);

// v ← √v, lane by lane (the vector extension has no square root of its own). Inlined into each caller, so that
// it compiles with the caller's file's options (wide_lanes.cpp: one vector square root).
RIGID_BODY_LANE_INLINE void laneSqrt(double& v) { v = std::sqrt(v); }
RIGID_BODY_LANE_INLINE void laneSqrt(Lanes& v) {
  for (std::size_t i = 0; i < kLanes; ++i) v[i] = std::sqrt(v[i]);
}

template <class T>
struct Vec {
  T x, y, z;
};
template <class T>
RIGID_BODY_LANE_INLINE Vec<T> operator+(const Vec<T>& a, const Vec<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
RIGID_BODY_LANE_INLINE Vec<T> operator-(const Vec<T>& a, const Vec<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
RIGID_BODY_LANE_INLINE Vec<T> operator*(const T& s, const Vec<T>& a) { return {s * a.x, s * a.y, s * a.z}; }

template <class T>
struct Mat {
  T m[3][3];
  RIGID_BODY_LANE_INLINE Vec<T> operator*(const Vec<T>& a) const {  // M a
    return {m[0][0] * a.x + m[0][1] * a.y + m[0][2] * a.z, m[1][0] * a.x + m[1][1] * a.y + m[1][2] * a.z,
            m[2][0] * a.x + m[2][1] * a.y + m[2][2] * a.z};
  }
  RIGID_BODY_LANE_INLINE Vec<T> transposeTimes(const Vec<T>& a) const {  // Mᵀ a
    return {m[0][0] * a.x + m[1][0] * a.y + m[2][0] * a.z, m[0][1] * a.x + m[1][1] * a.y + m[2][1] * a.z,
            m[0][2] * a.x + m[1][2] * a.y + m[2][2] * a.z};
  }
};

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
  Mat<T> inverse_inertia;               // I_Bcm_B⁻¹
  Vec<T> weight;                        // M g
  T linear_damping, angular_damping;
  Vec<T> force_W, torque_W, force_B, torque_B;  // the applied wrench: world and body parts
  // Equal in every lane of a batch: whether any lane's input has a body force (a body torque, a world torque).
  // A lane without one then adds a turned zero, which changes no bit of a finite sum but a zero's sign.
  bool body_force = false, body_torque = false, world_torque = false;
  // Semi-implicit Euler's free rotation: the inverse principal moments and the principal axes R_BP.
  Vec<T> inverse_principal;
  Mat<T> principal_axes;
  // Equal in every lane of a batch (semiImplicitTurnKind): a symmetric top turns by its exact flow
  // (turnSymmetricTop); a body whose principal axes are its body axes (R_BP = 𝟙, a box) skips the turns into
  // and out of them.
  bool symmetric_top = false, principal_body = false;
  // A symmetric top's flow (SymmetricTopAxes): its odd principal axis in body axes, 1/I_r, 1/I_s − 1/I_r.
  Vec<T> top_axis;
  T top_inverse_pair, top_spin_coefficient;
  // The bodies' mass properties, for a symmetric top's lanes whose turns are beyond the series (the exact
  // flow's sines and cosines, one lane at a time). Null in a batch's lanes that hold no body (they repeat its
  // last one; their results are dropped), which then skip it.
  std::array<const MassProperties*, kLaneCount<T>> mass{};
};

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

// R_u = |q|² R(q/|q|): R's usual entries with 1 − 2(y² + z²) written as w² + x² − y² − z²; and s = 1/|q|².
template <class T>
struct LaneRotation {
  Mat<T> R;
  T s;
  LaneRotation() = default;  // zeros (as LaneRotation<T>{}): for a caller that forms it only on one branch
  explicit LaneRotation(const LaneState<T>& y) {
    const T x = y.qx, yq = y.qy, z = y.qz, w = y.qw;
    const T xx = x * x, yy = yq * yq, zz = z * z, ww = w * w;
    // 2(xy − wz) as (2x) y − (2w) z: doubling is exact, so the same bits (but for a product below 2.2e-308,
    // lost in the sum beside it either way) with three additions in place of six multiplications
    // (docs/performance_log.md#doubled-products).
    const T x2 = x + x, y2 = yq + yq, w2 = w + w;
    const T xy = x2 * yq, xz = x2 * z, yz = y2 * z, wx = w2 * x, wy = w2 * yq, wz = w2 * z;
    R.m[0][0] = ww + xx - yy - zz;
    R.m[1][1] = ww - xx + yy - zz;
    R.m[2][2] = ww - xx - yy + zz;
    R.m[0][1] = xy - wz;
    R.m[1][0] = xy + wz;
    R.m[0][2] = xz + wy;
    R.m[2][0] = xz - wy;
    R.m[1][2] = yz - wx;
    R.m[2][1] = yz + wx;
    s = 1.0 / (xx + yy + zz + ww);  // beside the products, not before them
  }
};

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

// 1/√n for n = |q|². Near 1, |n − 1| ≤ 2⁻²⁶, by one Newton step for n^(-1/2) from 1: (3 − n)/2, whose
// error 3ε²/8 (ε = n − 1) is under 2⁻⁵³, below the rounding of 1/√n itself; elsewhere 1/√n. The exact form's
// square root and division are ~30 cycles on the step's critical path (each step's q is the next one's
// start); RK4 keeps |q|² that near 1 at the usual steps (its norm error per step is ~θ⁶/72, θ = h|ω|/2).
// One lane: a branch; four: both forms and a select per lane, the same value in each lane as alone.
constexpr double kNearUnitNorm = 1.0 / (1 << 26);
RIGID_BODY_LANE_INLINE double inverseNorm(double n) {
  if (std::fabs(n - 1.0) <= kNearUnitNorm) return 1.5 - 0.5 * n;
  return 1.0 / std::sqrt(n);
}
RIGID_BODY_LANE_INLINE Lanes inverseNorm(Lanes n) {
  Lanes root = n;
  laneSqrt(root);
  const Lanes exact = 1.0 / root, newton = 1.5 - 0.5 * n, d = n - 1.0;
  return (d <= kNearUnitNorm) & (d >= -kNearUnitNorm) ? newton : exact;
}

// Whether every lane of a comparison of Lanes holds (each lane of the result is 0 or −1).
template <class Mask>
RIGID_BODY_LANE_INLINE bool allLanes(const Mask& holds) {
  return holds[0] & holds[1] & holds[2] & holds[3];
}
// Whether every lane's value is at most `limit` (a NaN is not).
RIGID_BODY_LANE_INLINE bool allAtMost(double v, double limit) { return v <= limit; }
RIGID_BODY_LANE_INLINE bool allAtMost(Lanes v, double limit) { return allLanes(v <= limit); }

// 1/√n for n = 1 + x near 1 by the series of (1 + x)^(-1/2), through x⁶, by Estrin's scheme (products of
// depth four where a square root and a division take ~30 cycles): for |x| ≤ 2⁻⁸ the first term left out,
// (429/2048)|x|⁷ ≤ 2⁻⁵⁸, is below the rounding of 1/√n itself; elsewhere 1/√n. For a step's rotation that
// is not near unit: semi-implicit Euler's product of three Cayley turns has |r|² = 1 + O(h²|ω|²) (x ~ 1e-5 at
// 1 ms and a few rad/s). Four lanes take the series alone when all four are in its range (the same value in
// each lane as alone), else both forms and a select per lane.
constexpr double kSeriesRange = 1.0 / (1 << 8);
template <class T>
RIGID_BODY_LANE_INLINE T inverseNormSeries(const T& x) {  // coefficients (−1)ᵏ C(2k, k)/4ᵏ, exact in binary
  const T x2 = x * x;
  return ((1.0 - 0.5 * x) + x2 * (0.375 - 0.3125 * x)) +
         (x2 * x2) * ((0.2734375 - 0.24609375 * x) + 0.2255859375 * x2);
}
RIGID_BODY_LANE_INLINE double inverseNormNear(double n) {
  const double x = n - 1.0;
  if (std::fabs(x) <= kSeriesRange) return inverseNormSeries(x);
  return 1.0 / std::sqrt(n);
}
RIGID_BODY_LANE_INLINE Lanes inverseNormNear(Lanes n) {
  const Lanes x = n - 1.0;
  const auto near = (x <= kSeriesRange) & (x >= -kSeriesRange);
  const Lanes series = inverseNormSeries(x);
  if (allLanes(near)) return series;
  Lanes root = n;
  laneSqrt(root);
  const Lanes exact = 1.0 / root;
  return near ? series : exact;
}

// |q|²
template <class T>
RIGID_BODY_LANE_INLINE T quaternionNorm2(const LaneState<T>& y) {
  return y.qx * y.qx + y.qy * y.qy + y.qz * y.qz + y.qw * y.qw;
}

// q ← q/|q|, given 1/|q| (a caller may know |q| sooner than q itself, or take its inverse another way).
template <class T>
RIGID_BODY_LANE_INLINE void scaleQuaternion(LaneState<T>& y, const T& inverse_norm) {
  y.qx = y.qx * inverse_norm;
  y.qy = y.qy * inverse_norm;
  y.qz = y.qz * inverse_norm;
  y.qw = y.qw * inverse_norm;
}

// q ← q/|q|
template <class T>
RIGID_BODY_LANE_INLINE void normaliseQuaternion(LaneState<T>& y) {
  scaleQuaternion(y, inverseNorm(quaternionNorm2(y)));
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

// ---------------------------------------------------------------------------------------------------------
// Loading bodies into lanes and back. For T = double there is one lane (lane index 0).

RIGID_BODY_LANE_INLINE void setLane(double& v, std::size_t, double value) { v = value; }
RIGID_BODY_LANE_INLINE void setLane(Lanes& v, std::size_t i, double value) { v[i] = value; }
RIGID_BODY_LANE_INLINE double laneValue(const double& v, std::size_t) { return v; }
RIGID_BODY_LANE_INLINE double laneValue(const Lanes& v, std::size_t i) { return v[i]; }

template <class T>
RIGID_BODY_LANE_INLINE void setLane(Vec<T>& to, std::size_t i, const Eigen::Vector3d& from) {
  setLane(to.x, i, from.x());
  setLane(to.y, i, from.y());
  setLane(to.z, i, from.z());
}

// Entry by entry, no loop: an entry indexed by loop variables (m[r][c]) made GCC's early scalar replacement
// of aggregates give up on the whole LaneBody, which a lone step then copied into memory and loaded back
// (~60 constants).
template <class T>
RIGID_BODY_LANE_INLINE void setLane(Mat<T>& to, std::size_t i, const Eigen::Matrix3d& from) {
  setLane(to.m[0][0], i, from(0, 0));
  setLane(to.m[0][1], i, from(0, 1));
  setLane(to.m[0][2], i, from(0, 2));
  setLane(to.m[1][0], i, from(1, 0));
  setLane(to.m[1][1], i, from(1, 1));
  setLane(to.m[1][2], i, from(1, 2));
  setLane(to.m[2][0], i, from(2, 0));
  setLane(to.m[2][1], i, from(2, 1));
  setLane(to.m[2][2], i, from(2, 2));
}

// Whether any component of v is other than ±0 (a NaN too), without branches, on the bits: a double is ±0
// exactly when its bits but the sign are all zero. Eigen's any() took ~20 instructions a call here, three
// floating-point comparisons (each with its unordered case) ~14.
RIGID_BODY_LANE_INLINE bool nonZero(const Eigen::Vector3d& v) {
  std::uint64_t x, y, z;
  std::memcpy(&x, &v.x(), sizeof x);
  std::memcpy(&y, &v.y(), sizeof y);
  std::memcpy(&z, &v.z(), sizeof z);
  return ((x | y | z) << 1) != 0;
}

/// Which branch of semi-implicit Euler's rotation turns a body (the bodies of a batch take one).
enum class SemiImplicitTurn {
  kPrincipalAxes,  ///< the Cayley turns about its principal axes (and every body under another method)
  kBodyAxes,       ///< the same with R_BP = 𝟙: no turn into and out of the principal axes
  kSymmetricTop,   ///< a symmetric top's exact flow
};
inline SemiImplicitTurn semiImplicitTurnKind(IntegratorType type, const MassProperties& mass) {
  if (type != IntegratorType::kSemiImplicitEuler) return SemiImplicitTurn::kPrincipalAxes;
  if (isSymmetricTop(mass)) return SemiImplicitTurn::kSymmetricTop;
  return mass.principalAxesAreBodyAxes() ? SemiImplicitTurn::kBodyAxes : SemiImplicitTurn::kPrincipalAxes;
}

// Lane i of b from a body, only what a step of `type` with these terms reads (a lone body's step loads it at
// every call: a step that needs little loads little).
template <class T>
RIGID_BODY_LANE_INLINE void loadBody(LaneBody<T>& b, std::size_t i, IntegratorType type, const StepTerms& terms,
                                     const Model& model, const AppliedWrench& input) {
  setLane(b.inverse_mass, i, model.mass.inverseMass());
  const bool rotation = terms.rotation || (type == IntegratorType::kSemiImplicitEuler && terms.angular_damping);
  if (rotation && terms.world_inertia) {
    setLane(b.inverse_inertia, i, model.mass.inverseInertia());
  }
  if (rotation) setLane(b.j0, i, model.mass.inverseInertia()(0, 0));
  if (terms.gravity) setLane(b.weight, i, model.mass.mass() * model.forces.gravity_W);
  if (terms.linear_damping) setLane(b.linear_damping, i, model.forces.linear_damping);
  if (terms.angular_damping) setLane(b.angular_damping, i, model.forces.angular_damping);
  if (terms.input) {
    setLane(b.force_W, i, input.world.force);
    setLane(b.torque_W, i, input.world.torque);
    b.body_force = b.body_force || nonZero(input.body.force);  // exactly zero, not nearly
    b.body_torque = b.body_torque || nonZero(input.body.torque);
    // A batch's lanes all hold their values (another lane's may be read); one lane's only where the step
    // reads it (its flag).
    if (kLaneCount<T> > 1 || b.body_force) setLane(b.force_B, i, input.body.force);
    if (kLaneCount<T> > 1 || b.body_torque) setLane(b.torque_B, i, input.body.torque);
    b.world_torque = b.world_torque || nonZero(input.world.torque);
  }
  if (type != IntegratorType::kSemiImplicitEuler || !terms.rotation || !terms.world_inertia) return;
  b.mass[i] = &model.mass;
  const SemiImplicitTurn kind = semiImplicitTurnKind(type, model.mass);  // the same for every body of a batch
  b.symmetric_top = kind == SemiImplicitTurn::kSymmetricTop;
  if (b.symmetric_top) {
    const SymmetricTopAxes top = symmetricTopAxes(model.mass);
    setLane(b.top_axis, i, top.axis);
    setLane(b.top_inverse_pair, i, top.inverse_pair);
    setLane(b.top_spin_coefficient, i, top.spin_coefficient);
    return;
  }
  b.principal_body = kind == SemiImplicitTurn::kBodyAxes;
  setLane(b.inverse_principal, i, model.mass.inversePrincipalMoments());
  setLane(b.principal_axes, i, model.mass.principalAxes());
}

template <class T>
RIGID_BODY_LANE_INLINE void loadState(LaneState<T>& y, std::size_t i, const State& state) {
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
RIGID_BODY_LANE_INLINE void storeState(const LaneState<T>& y, std::size_t i, State& state) {
  // Component by component: Eigen's temporaries and comma initialiser cost a lone step ~15 instructions more.
  state.t = laneValue(y.t, i);
  state.p_WB.x() = laneValue(y.p.x, i);
  state.p_WB.y() = laneValue(y.p.y, i);
  state.p_WB.z() = laneValue(y.p.z, i);
  state.P_W.x() = laneValue(y.P.x, i);
  state.P_W.y() = laneValue(y.P.y, i);
  state.P_W.z() = laneValue(y.P.z, i);
  state.L_W.x() = laneValue(y.L.x, i);
  state.L_W.y() = laneValue(y.L.y, i);
  state.L_W.z() = laneValue(y.L.z, i);
  state.q_WB.x() = laneValue(y.qx, i);
  state.q_WB.y() = laneValue(y.qy, i);
  state.q_WB.z() = laneValue(y.qz, i);
  state.q_WB.w() = laneValue(y.qw, i);
}

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

/// Whether each lane of a step's result may be committed (Integrator::acceptable is this rule for one lane):
/// every component finite and |q| within the tolerance of 1 (|q|² compared). x, P, L and t are probed: 0·c
/// is 0 for a finite c and NaN for ±∞ or NaN, and the sum of those products is 0 only if every one is (the
/// components themselves are not summed, which could overflow). q needs no probe: a NaN or ±∞ in it makes
/// |q|² NaN or +∞, which fails the comparison. Writes one flag per lane into ok[0 … lanes).
template <class T>
RIGID_BODY_LANE_INLINE void acceptableLanes(const LaneState<T>& y, std::size_t lanes, bool* ok) {
  const T zero{};
  const T probe = (zero * y.p.x + zero * y.p.y + zero * y.p.z) + (zero * y.P.x + zero * y.P.y + zero * y.P.z) +
                  (zero * y.L.x + zero * y.L.y + zero * y.L.z) + zero * y.t;
  const T norm2 = quaternionNorm2(y);
  constexpr double kTolerance = Integrator::kUnitQuaternionTolerance;
  constexpr double kLow = (1.0 - kTolerance) * (1.0 - kTolerance), kHigh = (1.0 + kTolerance) * (1.0 + kTolerance);
  for (std::size_t i = 0; i < lanes; ++i) {
    const double n2 = laneValue(norm2, i);
    ok[i] = laneValue(probe, i) == 0.0 && n2 >= kLow && n2 <= kHigh;
  }
}

/// Whether a method steps by these kernels.
inline bool hasLaneStep(IntegratorType type) { return integratorInfo(type).lane_kernel; }

/// f(std::integral_constant<IntegratorType, kType>{}) for the method with a lane kernel that `type` names
/// (hasLaneStep), and what f returns: each method's code a compile-time choice, the switch once.
template <class F>
decltype(auto) withMethod(IntegratorType type, F&& f) {
  switch (type) {
    case IntegratorType::kRk4:
      return f(std::integral_constant<IntegratorType, IntegratorType::kRk4>{});
    case IntegratorType::kSemiImplicitEuler:
      return f(std::integral_constant<IntegratorType, IntegratorType::kSemiImplicitEuler>{});
    default:
      return f(std::integral_constant<IntegratorType, IntegratorType::kExplicitEuler>{});
  }
}

/// One step of a method with a lane kernel (hasLaneStep), for the lanes as T holds them.
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneStep(IntegratorType type, const LaneBody<T>& b, const StepTerms& terms, double h,
                             const LaneState<T>& y) {
  switch (type) {
    case IntegratorType::kRk4:
      return laneRk4Step(b, terms, h, y);
    case IntegratorType::kSemiImplicitEuler:
      return laneSemiImplicitEulerStep(b, terms, h, y);
    default:
      return laneEulerStep(b, terms, h, y);
  }
}

/// Up to `steps` steps of the lanes of y, of which the first `count` hold bodies. A lane stops at its first
/// step that acceptableLanes refuses: running[i] turns false and done[i] is the steps it took; it computes on
/// unread (y's lane is then not its state). A lane that never stops has done[i] = steps.
template <class T>
RIGID_BODY_LANE_INLINE void runLanes(IntegratorType type, const LaneBody<T>& b, const StepTerms& terms, double h,
                                     std::int64_t steps, std::size_t count, LaneState<T>& y, std::int64_t* done,
                                     bool* running) {
  std::size_t still_running = count;
  for (std::size_t i = 0; i < count; ++i) {
    done[i] = steps;
    running[i] = true;
  }
  bool ok[kLaneCount<T>];
  // The loop on copies: through the references, every store of the state could change the body's constants
  // (both are doubles), so GCC stored the state and loaded the constants again at every step.
  const LaneBody<T> body = b;
  LaneState<T> state = y;
  for (std::int64_t k = 0; k < steps && still_running > 0; ++k) {
    const LaneState<T> next = laneStep(type, body, terms, h, state);
    acceptableLanes(next, count, ok);
    for (std::size_t i = 0; i < count; ++i) {
      if (!running[i] || ok[i]) continue;
      running[i] = false;  // Integrator::step's refusal: the step is not taken, the body stops here
      done[i] = k;
      --still_running;
    }
    state = next;
  }
  y = state;
}

/// Every term assembled (StepTerms' defaults) as a compile-time constant: the lone kernels run a copy of their
/// step with it where a body's terms are all on (laneStepOf says why).
inline constexpr StepTerms kAllTerms{};

/// runLanes with the general terms as constants where they are all assembled, for one lane under semi-implicit
/// Euler, as laneStepOf runs its step (it says why); rk4's loop gains nothing by it and keeps the terms as they
/// come (docs/performance_log.md#constant-terms).
template <IntegratorType kType, class T>
RIGID_BODY_LANE_INLINE void runLanesWithTerms(const LaneBody<T>& b, const StepTerms& terms, double h,
                                              std::int64_t steps, std::size_t count, LaneState<T>& y,
                                              std::int64_t* done, bool* running) {
  if constexpr (kLaneCount<T> == 1 && kType == IntegratorType::kSemiImplicitEuler) {
    if (terms == kAllTerms) {
      runLanes(kType, b, kAllTerms, h, steps, count, y, done, running);
      return;
    }
  }
  runLanes(kType, b, terms, h, steps, count, y, done, running);
}

/// runLanes for four bodies, compiled twice (wide_lanes.cpp): for the baseline instruction set (x86-64: SSE2,
/// two 128-bit halves per operation) and for AVX (one 256-bit operation), which `wide` picks. The same IEEE
/// operations in the same order, no contraction: the same bits either way (tested).
void runBatch(bool wide, IntegratorType type, const LaneBody<Lanes>& b, const StepTerms& terms, double h,
              std::int64_t steps, std::size_t count, LaneState<Lanes>& y, std::int64_t* done, bool* running);
/// Whether this CPU (and its operating system) runs AVX: checked once.
bool wideLanesAvailable();
/// runLanes for one body (a Scene's body without a batch to share), each method a function of its own; with
/// `wide` (and wideLoneStepsAvailable()) in AVX-512's instructions: the same bits.
void runLone(bool wide, IntegratorType type, const LaneBody<double>& b, const StepTerms& terms, double h,
             std::int64_t steps, LaneState<double>& y, std::int64_t* done, bool* running);

// One body's step by its lane kernel, T = double: load, step, test, store. Only `inline`: GCC compiles it as a
// function of its own, which laneStep calls. Forced into laneStep (always_inline), the same code came out with
// more instructions and slower, from GCC's register allocation (docs/performance_log.md#lone-step-inlining).
template <IntegratorType kType>
inline bool laneStepOf(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                       State& state) {
  LaneBody<double> b;
  loadBody(b, 0, kType, terms, model, input);
  LaneState<double> y;
  loadState(y, 0, state);
  LaneState<double> next;
  if constexpr (kType == IntegratorType::kRk4 || kType == IntegratorType::kSemiImplicitEuler) {
    // The general terms as constants, a copy of the step of its own: GCC then allocates the registers of RK4's
    // four stages (~50 live values) for the general body alone, free of the terms' branches, and of
    // semi-implicit Euler's ~60 body constants. Explicit Euler loses by it: it takes the terms as they come
    // (docs/performance_log.md#constant-terms).
    next = terms == kAllTerms ? laneStep(kType, b, kAllTerms, h, y) : laneStep(kType, b, terms, h, y);
  } else {
    next = laneStep(kType, b, terms, h, y);
  }
  bool ok = false;
  acceptableLanes(next, 1, &ok);
  if (ok) storeState(next, 0, state);
  return ok;
}

/// One body's step by its lane kernel, T = double: what Integrator::step runs for these methods (one
/// instantiation per method, each a function of its own: inlined into one caller, each method's code moved
/// with edits to the others' (docs/performance_log.md#one-function-per-method). The result goes into
/// `state` only if acceptableLanes accepts it; returns whether it did.
template <IntegratorType kType>
__attribute__((noinline)) bool laneStep(const Model& model, const StepTerms& terms, const AppliedWrench& input,
                                        double h, State& state) {
  return laneStepOf<kType>(model, terms, input, h, state);
}

#if defined(__x86_64__) && !defined(__AVX512F__)
#define RIGID_BODY_WIDE_LONE_STEPS 1
/// laneStep compiled for AVX-512 (`flatten`: the whole step inlined into it, Eigen's loads and stores too),
/// picked at run time by Integrator where wideLoneStepsAvailable(): the same scalar IEEE operations in the same
/// order, so the same bits, in three-operand instructions with 32 registers instead of SSE2's two-operand
/// ones with 16: fewer copies and spills of RK4's ~50 live values; used for all three methods (explicit
/// Euler's too: docs/performance_log.md#wide-lone-steps). Without GCC's straight-line
/// vectoriser:
/// "avx512f" brings fused multiply-add instructions, and GCC 12's vectoriser fuses a product into a pair of a
/// sum and a difference (vfmaddsub) in spite of -ffp-contract=off (it did so in the native build), which
/// would round apart from the batched step (and the wide rk4 step is faster without it).
#define RIGID_BODY_LONE_WIDE_TARGET target("avx512f"), optimize("no-tree-slp-vectorize")
template <IntegratorType kType>
__attribute__((noinline, flatten, RIGID_BODY_LONE_WIDE_TARGET)) bool laneStepWide(const Model& model, const StepTerms& terms,
                                                                        const AppliedWrench& input, double h,
                                                                        State& state) {
  return laneStepOf<kType>(model, terms, input, h, state);
}
#endif
/// runLanes in the build's own instruction set, each method (and lane type) a function of its own: inlined
/// together into one, each method's register allocation followed the others' code
/// (docs/performance_log.md#one-function-per-method). runBatch and runLone (wide_lanes.cpp) call it. Here rather than there, so that
/// semi-implicit Euler's lone loop is compiled in lone_semi_implicit_euler.cpp, as its lone step is.
template <IntegratorType kType, class T>
__attribute__((noinline)) void runLanesOf(const LaneBody<T>& b, const StepTerms& terms, double h, std::int64_t steps,
                                          std::size_t count, LaneState<T>& y, std::int64_t* done, bool* running) {
  runLanesWithTerms<kType>(b, terms, h, steps, count, y, done, running);
}
#ifdef RIGID_BODY_WIDE_LONE_STEPS
/// runLanesOf for one body in AVX-512's instructions, as laneStepWide.
template <IntegratorType kType>
__attribute__((noinline, RIGID_BODY_LONE_WIDE_TARGET)) void runLoneWide(const LaneBody<double>& b, const StepTerms& terms,
                                                              double h, std::int64_t steps, LaneState<double>& y,
                                                              std::int64_t* done, bool* running) {
  runLanesWithTerms<kType>(b, terms, h, steps, 1, y, done, running);
}
#endif

/// Whether laneStepWide is compiled and this CPU (and its operating system) runs AVX-512F: checked once.
bool wideLoneStepsAvailable();

// Compiled in lone_semi_implicit_euler.cpp, with options of its own.
extern template bool laneStep<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                                   const AppliedWrench& input, double h, State& state);
extern template void runLanesOf<IntegratorType::kSemiImplicitEuler, double>(const LaneBody<double>& b,
                                                                            const StepTerms& terms, double h,
                                                                            std::int64_t steps, std::size_t count,
                                                                            LaneState<double>& y,
                                                                            std::int64_t* done, bool* running);
#ifdef RIGID_BODY_WIDE_LONE_STEPS
extern template bool laneStepWide<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                                       const AppliedWrench& input, double h,
                                                                       State& state);
extern template void runLoneWide<IntegratorType::kSemiImplicitEuler>(const LaneBody<double>& b,
                                                                     const StepTerms& terms, double h,
                                                                     std::int64_t steps, LaneState<double>& y,
                                                                     std::int64_t* done, bool* running);
#endif

}  // namespace integrators
}  // namespace rigid_body

#undef RIGID_BODY_LANE_INLINE
#undef RIGID_BODY_LONE_WIDE_TARGET
#pragma GCC diagnostic pop
