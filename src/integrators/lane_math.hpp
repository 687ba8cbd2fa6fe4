// The lanes' arithmetic: a "lane" type T is double (one body) or Lanes (four doubles, a GCC/Clang vector:
// four bodies at once, one in each lane), and everything here is written once for both. Vector arithmetic
// rounds element by element as scalar arithmetic does, so a body's step is the same bit for bit whether it
// runs alone or in a batch (tested). Vectors and matrices of lanes, the state and constants a kernel steps,
// the rotation it forms, norms, lane access and the test of a step's result. Internal to the integrators.
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

// Lanes pass by value between inline functions of these headers only: GCC's note that the calling convention
// of a 32-byte vector differs with and without AVX concerns no boundary here (-Wno-psabi, CMakeLists.txt).

#ifndef RIGID_BODY_LANE_INLINE
// The step's pieces, down to the vector operators and the loads and stores, are inlined into each other
// whatever the compiler's size heuristics say: left to them, GCC kept laneWrench and the semi-implicit step
// as calls (perf), each a stack frame of lane structs, and under link-time optimisation its choices for the
// small helpers followed its budget for the whole library, so that edits to other files moved the lone step
// (docs/performance_log.md#forced-inlining).
#define RIGID_BODY_LANE_INLINE inline __attribute__((always_inline))
#endif

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
// Any vector of doubles (Lanes, or the contact solver's eight).
RIGID_BODY_LANE_INLINE void laneSqrt(double& v) { v = std::sqrt(v); }
template <class V>
RIGID_BODY_LANE_INLINE void laneSqrt(V& v) {
  for (std::size_t i = 0; i < kLaneCount<V>; ++i) v[i] = std::sqrt(v[i]);
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

// ---------------------------------------------------------------------------------------------------------
// Loading bodies into lanes and back. For T = double there is one lane (lane index 0).

// A vector of lanes is any vector type with an element per lane: Lanes here, the contact solver's eight
// lanes (src/contact/contact_lanes.hpp) too.
RIGID_BODY_LANE_INLINE void setLane(double& v, std::size_t, double value) { v = value; }
template <class V>
RIGID_BODY_LANE_INLINE auto setLane(V& v, std::size_t i, double value) -> decltype(void(v[i] = value)) {
  v[i] = value;
}
RIGID_BODY_LANE_INLINE double laneValue(const double& v, std::size_t) { return v; }
template <class V>
RIGID_BODY_LANE_INLINE auto laneValue(const V& v, std::size_t i) -> decltype(double(v[i])) {
  return v[i];
}

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

}  // namespace integrators
}  // namespace rigid_body

