// The lane solver's kernel (docs/contact.md, "The solver's lanes"): one sweep of a group of manifolds
// (contact_lanes.hpp), and the sweeps of a block's groups until each island converges. Written once for the
// lane types with the lanes' own arithmetic (src/integrators/lane_math.hpp), so each lane rounds as one lane
// alone does. Internal to the contact solver.
//
// Compiled once per instruction set: for the build's own (lane_contact_solver.cpp), and for AVX and AVX-512
// under a target pragma (lane_sweeps_wide.cpp), each copy in a namespace of its own
// (RIGID_BODY_CONTACT_LANES_ISA) so that no two share a symbol; hence no include guard. Every function of the
// kernel must itself be compiled with the wide instructions, not only be inlined into a function that is:
// GCC 12 types a comparison's mask by the instruction set of the function it is written in, and a baseline
// helper's masks of eight doubles, once combined (a & b) or selected by, became a scalar comparison and a
// branch per lane inside AVX and AVX-512 code.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "contact_lanes.hpp"
#include "lane_contact_solver.hpp"

#ifndef RIGID_BODY_CONTACT_LANES_ISA
#error "define RIGID_BODY_CONTACT_LANES_ISA, the namespace of this instruction set's copy"
#endif

namespace rigid_body {
namespace contact {
namespace RIGID_BODY_CONTACT_LANES_ISA {

// Lane access (lane_math.hpp's, for any vector of lanes), and the lanes' own std::max, sign test and
// selection, the same in one lane as in several.
using integrators::laneValue;
using integrators::setLane;
template <class M>
RIGID_BODY_LANE_INLINE bool laneOn(const M& m, std::size_t i) {
  if constexpr (std::is_same_v<M, bool>) {
    return (void)i, m;
  } else {
    return m[i] != 0;
  }
}
template <class M>
RIGID_BODY_LANE_INLINE void setMaskLane(M& m, std::size_t i, bool on) {
  if constexpr (std::is_same_v<M, bool>) {
    (void)i, m = on;
  } else {
    m[i] = on ? -1 : 0;
  }
}
// Whether any lane of a mask is set. Tested lane by lane, GCC moved the friction disc's iteration mask into
// general registers to test it, and then formed its selections from them lane by lane, with a branch each;
// AVX tests four lanes in one instruction (their sign bits), and the mask stays a vector.
template <class M>
RIGID_BODY_LANE_INLINE bool anyLane(const M& m) {
  if constexpr (std::is_same_v<M, bool>) {
    return m;
  } else {
#ifdef RIGID_BODY_CONTACT_LANES_AVX  // this copy is compiled for AVX or wider (lane_sweeps_wide.cpp)
    if constexpr (sizeof(M) == 32) {
      typedef double Four __attribute__((vector_size(32)));
      return __builtin_ia32_movmskpd256(reinterpret_cast<Four>(m)) != 0;
    }
#endif
    bool any = false;
    for (std::size_t i = 0; i < sizeof(M) / sizeof(m[0]); ++i) any = any || m[i] != 0;
    return any;
  }
}
template <class T>
RIGID_BODY_LANE_INLINE T laneSelect(const LaneMask<T>& m, const T& a, const T& b) {
#ifdef RIGID_BODY_CONTACT_LANES_AVX
  // By the mask's sign bits (every lane of a mask is all ones or zero). `m ? a : b` asks m != 0, a compare
  // of 64-bit integers that AVX without AVX2 lacks: GCC took the mask apart and rebuilt it lane by lane.
  if constexpr (sizeof(T) == 32) return __builtin_ia32_blendvpd256(b, a, reinterpret_cast<T>(m));
#endif
  return m ? a : b;
}

template <class T>
RIGID_BODY_LANE_INLINE T dot(const Vec<T>& a, const Vec<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
RIGID_BODY_LANE_INLINE T laneMax(T a, T b) {
  return laneSelect<T>(a < b, b, a);
}
template <class T>
RIGID_BODY_LANE_INLINE T laneAbs(T a) {
  return laneSelect<T>(a < 0.0, -a, a);
}

/// √v lane by lane (lane_math.hpp's laneSqrt, each lane's the scalar std::sqrt, correctly rounded).
template <class T>
RIGID_BODY_LANE_INLINE T laneRoot(T v) {
#ifdef RIGID_BODY_CONTACT_LANES_AVX
  // One AVX instruction (correctly rounded, as std::sqrt): the lane-by-lane form, once selected by a mask,
  // was selected lane by lane with a branch each (and the mask taken apart for it).
  if constexpr (sizeof(T) == 32) return __builtin_ia32_sqrtpd256(v);
#endif
  integrators::laneSqrt(v);
  return v;
}

/// ontoFrictionDisc (friction_disc.cpp) in lanes, operation for operation, so that each lane rounds as the
/// scalar function does: in the lanes set in `outside`, the sticking impulse (f1, f2) is replaced by its
/// projection onto the disc |f| ≤ limit in the metric of K = [k00 k01; k01 k11] (the slip change per
/// friction impulse, k01 its symmetrised off-diagonal); the other lanes keep theirs. Newton's iterations on
/// the secular equation run while any lane still iterates, each lane stopping where the scalar loop would.
template <class T>
RIGID_BODY_LANE_INLINE void frictionOntoDiscLanes(LaneMask<T> outside, const T& k00, const T& k01, const T& k11,
                                                  const T& limit, T& f1, T& f2) {
  LaneMask<T> active = outside & (limit > 0.0);
  if (!anyLane(active)) {  // no normal impulse in any lane outside: their discs are points
    f1 = laneSelect<T>(outside, T{}, f1), f2 = laneSelect<T>(outside, T{}, f2);
    return;
  }
  const T half_trace = 0.5 * (k00 + k11), half_gap = 0.5 * (k00 - k11);
  const T k_min = half_trace - laneRoot<T>(half_gap * half_gap + k01 * k01);
  const T kf1 = k00 * f1 + k01 * f2, kf2 = k01 * f1 + k11 * f2;
  const T norm = laneRoot<T>(f1 * f1 + f2 * f2);
  T lambda = laneSelect<T>(k_min > 0.0, laneMax<T>(T{}, k_min * (norm / limit - 1.0)), 1e-12 * half_trace);
  T g1{}, g2{}, r{};
  for (int i = 0; i < 40 && anyLane(active); ++i) {
    const T m00 = k00 + lambda, m11 = k11 + lambda, det = m00 * m11 - k01 * k01;
    active = active & (det > 0.0);  // K is zero: no friction can act
    const T inverse = 1.0 / det;
    g1 = laneSelect<T>(active, (m11 * kf1 - k01 * kf2) * inverse, g1);
    g2 = laneSelect<T>(active, (m00 * kf2 - k01 * kf1) * inverse, g2);
    const T squared = g1 * g1 + g2 * g2;
    r = laneSelect<T>(active, laneRoot<T>(squared), r);
    const T q = m11 * g1 * g1 - 2.0 * k01 * g1 * g2 + m00 * g2 * g2;
    active = active & (r > limit * (1.0 + 1e-15)) & (q > 0.0);
    lambda = laneSelect<T>(active, lambda + (r - limit) * squared * det / (limit * q), lambda);
  }
  const LaneMask<T> on_circle = outside & (limit > 0.0) & (r > 0.0);
  f1 = laneSelect<T>(on_circle, g1 * (limit / r), laneSelect<T>(outside, T{}, f1));
  f2 = laneSelect<T>(on_circle, g2 * (limit / r), laneSelect<T>(outside, T{}, f2));
}

template <class T>
RIGID_BODY_LANE_INLINE void gatherVelocity(Vec<T>& v, Vec<T>& w, T& inverse_mass, const LaneBodyVelocity& body,
                                           std::size_t lane) {
  setLane(v.x, lane, body.v[0]), setLane(v.y, lane, body.v[1]);
  setLane(v.z, lane, body.v[2]);
  setLane(w.x, lane, body.w[0]), setLane(w.y, lane, body.w[1]);
  setLane(w.z, lane, body.w[2]);
  setLane(inverse_mass, lane, body.inverse_mass);
}
template <class T>
RIGID_BODY_LANE_INLINE void scatterVelocity(const Vec<T>& v, const Vec<T>& w, LaneBodyVelocity& body, std::size_t lane) {
  body.v[0] = laneValue(v.x, lane), body.v[1] = laneValue(v.y, lane);
  body.v[2] = laneValue(v.z, lane);
  body.w[0] = laneValue(w.x, lane), body.w[1] = laneValue(w.y, lane);
  body.w[2] = laneValue(w.z, lane);
}

// Four lanes of a body row (LaneBodyVelocity: v, w₀ in the first four doubles; w₁, w₂, 1/m and a zero in
// the last four).
using Row = integrators::Lanes;
typedef long long RowShuffle __attribute__((vector_size(32)));

/// Columns of four rows (a 4 × 4 transpose, its own inverse): c[f] lane k = r[k] lane f. Setting lanes one
/// by one goes through memory (a scalar store per lane, then a vector load that cannot take them from the
/// store buffer); shuffles keep them in registers.
RIGID_BODY_LANE_INLINE void transposeRows(const Row (&r)[4], Row (&c)[4]) {
  const Row t0 = __builtin_shuffle(r[0], r[1], RowShuffle{0, 4, 2, 6});
  const Row t1 = __builtin_shuffle(r[0], r[1], RowShuffle{1, 5, 3, 7});
  const Row t2 = __builtin_shuffle(r[2], r[3], RowShuffle{0, 4, 2, 6});
  const Row t3 = __builtin_shuffle(r[2], r[3], RowShuffle{1, 5, 3, 7});
  c[0] = __builtin_shuffle(t0, t2, RowShuffle{0, 1, 4, 5}), c[1] = __builtin_shuffle(t1, t3, RowShuffle{0, 1, 4, 5});
  c[2] = __builtin_shuffle(t0, t2, RowShuffle{2, 3, 6, 7}), c[3] = __builtin_shuffle(t1, t3, RowShuffle{2, 3, 6, 7});
}

/// A vector of lanes from its four-lane parts, and part `chunk` of one.
template <class T>
RIGID_BODY_LANE_INLINE T joinRows(const Row (&part)[kLaneCount<T> / 4]) {
  if constexpr (kLaneCount<T> == 4) {
    return part[0];
  } else {
    static_assert(kLaneCount<T> == 8, "four or eight lanes");
    return __builtin_shufflevector(part[0], part[1], 0, 1, 2, 3, 4, 5, 6, 7);
  }
}
template <class T>
RIGID_BODY_LANE_INLINE Row rowPart(const T& x, std::size_t chunk) {
  if constexpr (kLaneCount<T> == 4) {
    return (void)chunk, x;
  } else {
    return chunk == 0 ? __builtin_shufflevector(x, x, 0, 1, 2, 3) : __builtin_shufflevector(x, x, 4, 5, 6, 7);
  }
}

/// One side's bodies (index[l] for lane l < lanes; the environment's zeros in the lanes beyond) into lanes:
/// gatherVelocity lane by lane, by transposes of the bodies' rows where a lane holds several doubles.
template <class T>
RIGID_BODY_LANE_INLINE void gatherSide(const LaneBodyVelocity* bodies, const std::uint32_t* index, std::size_t lanes,
                                       Vec<T>& v, Vec<T>& w, T& inverse_mass) {
  if constexpr (std::is_same_v<T, double>) {
    (void)lanes, gatherVelocity(v, w, inverse_mass, bodies[index[0]], 0);
  } else {
    constexpr std::size_t kChunks = kLaneCount<T> / 4;
    Row column[8][kChunks];
    for (std::size_t chunk = 0; chunk < kChunks; ++chunk) {
      Row low[4], high[4], low_columns[4], high_columns[4];
      for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t l = 4 * chunk + k;
        const auto* row = reinterpret_cast<const unsigned char*>(&bodies[l < lanes ? index[l] : 0]);
        std::memcpy(&low[k], row, sizeof(Row)), std::memcpy(&high[k], row + sizeof(Row), sizeof(Row));
      }
      transposeRows(low, low_columns), transposeRows(high, high_columns);
      for (std::size_t f = 0; f < 4; ++f) column[f][chunk] = low_columns[f], column[4 + f][chunk] = high_columns[f];
    }
    v = {joinRows<T>(column[0]), joinRows<T>(column[1]), joinRows<T>(column[2])};
    w = {joinRows<T>(column[3]), joinRows<T>(column[4]), joinRows<T>(column[5])};
    inverse_mass = joinRows<T>(column[6]);
  }
}

/// One side's velocities back into the bodies of the lanes set in `live` (scatterVelocity lane by lane; by
/// transposes where a lane holds several doubles, the row's 1/m written back as it was gathered).
template <class T>
RIGID_BODY_LANE_INLINE void scatterSide(const Vec<T>& v, const Vec<T>& w, const T& inverse_mass, LaneMask<T> live,
                                        LaneBodyVelocity* bodies, const std::uint32_t* index, std::size_t lanes) {
  if constexpr (std::is_same_v<T, double>) {
    if (lanes > 0 && live) scatterVelocity(v, w, bodies[index[0]], 0);
  } else {
    for (std::size_t chunk = 0; chunk < kLaneCount<T> / 4; ++chunk) {
      const Row low_columns[4] = {rowPart(v.x, chunk), rowPart(v.y, chunk), rowPart(v.z, chunk), rowPart(w.x, chunk)};
      const Row high_columns[4] = {rowPart(w.y, chunk), rowPart(w.z, chunk), rowPart(inverse_mass, chunk), Row{}};
      Row low[4], high[4];
      transposeRows(low_columns, low), transposeRows(high_columns, high);
      for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t l = 4 * chunk + k;
        if (l >= lanes || !laneOn(live, l)) continue;
        auto* row = reinterpret_cast<unsigned char*>(&bodies[index[l]]);
        std::memcpy(row, &low[k], sizeof(Row)), std::memcpy(row + sizeof(Row), &high[k], sizeof(Row));
      }
    }
  }
}

/// K⁺ of the manifolds in the lanes set in `lanes` (bit l for lane l), found once (invertJointManifolds'
/// rule, in solveJointNormals). Outside the lanes' instructions: Eigen's.
template <class T>
__attribute__((noinline)) void invertLanes(ManifoldLanes<T>& g, unsigned lanes, const LaneBodyVelocity* bodies,
                                           const SolverContact* contacts) {
  for (std::size_t l = 0; l < g.lanes; ++l) {
    if (((lanes >> l) & 1u) == 0) continue;
    JointInverse inverse = {};
    const bool joint = jointNormalInverse(&contacts[g.first_contact[l]], g.count[l], bodies[g.body_a[l]].inverse_mass,
                                          bodies[g.body_b[l]].inverse_mass, inverse);
    setLane(g.inverted, l, 1.0), setLane(g.joint, l, joint ? 1.0 : 0.0);
    for (std::size_t e = 0; e < kJointEntries; ++e) setLane(g.inverse[e], l, inverse[e]);
  }
}

/// A face's normal impulses together (solveJointNormals in lanes): in the lanes whose face is not at rest
/// (kFaceAtRest) and has a K⁺ (found here the first time), the increments K⁺ (target − v_n) for all its
/// points at once, kept where none of them would fall below its floor; the point-by-point update follows
/// either way.
template <class T>
RIGID_BODY_LANE_INLINE void jointNormals(ManifoldLanes<T>& g, LaneMask<T> live, const LaneBodyVelocity* bodies,
                                         const SolverContact* contacts, Vec<T>& va, Vec<T>& wa, const T& ma,
                                         Vec<T>& vb, Vec<T>& wb, const T& mb, T& change) {
  LaneMask<T> ok = live & ((g.inverted <= 0.0) | (g.joint > 0.0));
  if (!anyLane(ok)) return;
  T residual[kMaxManifoldPoints];  // read and written below g.slots only (zeroing them was a call to memset)
  LaneMask<T> moving = T{} < T{};  // some point's residual beyond kFaceAtRest
  for (std::size_t p = 0; p < g.slots; ++p) {
    const PointLanes<T>& s = g.point[p];
    const T v_n = dot(s.n, va - vb) + dot(s.cross_a[0], wa) - dot(s.cross_b[0], wb);
    residual[p] = laneSelect<T>(s.present > 0.0, s.target_speed - v_n, T{});
    moving = moving | ((s.present > 0.0) & (laneAbs(s.normal_mass * residual[p]) > kFaceAtRest * s.normal_impulse));
  }
  ok = ok & moving;
  const LaneMask<T> to_invert = ok & (g.inverted <= 0.0);
  if (anyLane(to_invert)) {
    unsigned lanes = 0;
    for (std::size_t l = 0; l < g.lanes; ++l) lanes |= laneOn(to_invert, l) ? 1u << l : 0u;
    invertLanes(g, lanes, bodies, contacts);
  }
  ok = ok & (g.joint > 0.0);
  if (!anyLane(ok)) return;
  T next[kMaxManifoldPoints];
  for (std::size_t p = 0; p < g.slots; ++p) {
    const PointLanes<T>& s = g.point[p];
    T d{};
    for (std::size_t q = 0; q < g.slots; ++q) d = d + g.inverse[jointEntry(p, q)] * residual[q];
    next[p] = s.normal_impulse + d;
    ok = ok & ((s.present <= 0.0) | (next[p] >= s.normal_floor));
  }
  if (!anyLane(ok)) return;
  for (std::size_t p = 0; p < g.slots; ++p) {
    PointLanes<T>& s = g.point[p];
    const LaneMask<T> taken = ok & (s.present > 0.0);
    const T dn = laneSelect<T>(taken, next[p] - s.normal_impulse, T{});
    s.normal_impulse = laneSelect<T>(taken, next[p], s.normal_impulse);
    va = va + (ma * dn) * s.n, wa = wa + dn * s.response_a[0];
    vb = vb - (mb * dn) * s.n, wb = wb - dn * s.response_b[0];
    change = laneMax(change, laneAbs(dn));
  }
}

/// One sweep of a group's points, slot by slot: in each lane solveVelocities' update of one point (normal,
/// then friction). Lanes off in `live` (their island converged, or no manifold) change nothing that is
/// written back. Raises `change` and `impulse` lane by lane to the largest impulse change and impulse.
template <class T>
RIGID_BODY_LANE_INLINE void sweepGroup(ManifoldLanes<T>& g, LaneBodyVelocity* bodies, LaneMask<T> live,
                                       const SolverContact* contacts, T& change, T& impulse) {
  Vec<T> va, wa, vb, wb;
  T ma, mb;
  gatherSide(bodies, g.body_a, g.lanes, va, wa, ma), gatherSide(bodies, g.body_b, g.lanes, vb, wb, mb);
  jointNormals(g, live, bodies, contacts, va, wa, ma, vb, wb, mb, change);
  for (std::size_t p = 0; p < g.slots; ++p) {
    PointLanes<T>& s = g.point[p];
    const LaneMask<T> on = live & (s.present > 0.0);
    // Normal: v_n ≥ target, impulse ≥ the floor (a contact pushes, never pulls).
    const T v_n = dot(s.n, va - vb) + dot(s.cross_a[0], wa) - dot(s.cross_b[0], wb);
    const T normal = laneSelect<T>(on, laneMax(s.normal_floor, s.normal_impulse - s.normal_mass * (v_n - s.target_speed)),
                                s.normal_impulse);
    const T dn = normal - s.normal_impulse;
    s.normal_impulse = normal;
    va = va + (ma * dn) * s.n, wa = wa + dn * s.response_a[0];
    vb = vb - (mb * dn) * s.n, wb = wb - dn * s.response_b[0];
    // Friction: the sticking impulse if the disc |f| ≤ μ f_n holds it, else its projection onto the disc.
    const Vec<T> dv = va - vb;
    const T s1 = dot(s.t1, dv) + dot(s.cross_a[1], wa) - dot(s.cross_b[1], wb);
    const T s2 = dot(s.t2, dv) + dot(s.cross_a[2], wa) - dot(s.cross_b[2], wb);
    s.slip_squared = laneSelect<T>(on, s1 * s1 + s2 * s2, s.slip_squared);
    T f1 = s.friction1 - (s.tangent_mass00 * s1 + s.tangent_mass01 * s2);
    T f2 = s.friction2 - (s.tangent_mass01 * s1 + s.tangent_mass11 * s2);
    const T limit = s.friction * normal;
    const LaneMask<T> outside = on & (f1 * f1 + f2 * f2 > limit * limit);
    if (anyLane(outside)) {
      frictionOntoDiscLanes<T>(outside, s.tangent_response00, s.tangent_response01, s.tangent_response11, limit, f1, f2);
    }
    f1 = laneSelect<T>(on, f1, s.friction1), f2 = laneSelect<T>(on, f2, s.friction2);
    const T df1 = f1 - s.friction1, df2 = f2 - s.friction2;
    s.friction1 = f1, s.friction2 = f2;
    const Vec<T> linear = df1 * s.t1 + df2 * s.t2;
    va = va + ma * linear, wa = wa + (df1 * s.response_a[1] + df2 * s.response_a[2]);
    vb = vb - mb * linear, wb = wb - (df1 * s.response_b[1] + df2 * s.response_b[2]);
    change = laneMax(change, laneMax(laneAbs(dn), laneMax(laneAbs(df1), laneAbs(df2))));
    impulse = laneMax(impulse, laneMax(normal, laneMax(laneAbs(f1), laneAbs(f2))));
  }
  // The environment's entry (0) is the block's own copy, never read back: writing it is harmless.
  scatterSide(va, wa, ma, live, bodies, g.body_a, g.lanes), scatterSide(vb, wb, mb, live, bodies, g.body_b, g.lanes);
}

// One sweep over every group in order, lanes of converged islands off; each island's largest change and
// impulse gathered from its lanes.
template <class T>
RIGID_BODY_LANE_INLINE void sweepGroups(std::vector<ManifoldLanes<T>>& groups, LaneBodyVelocity* bodies,
                                        const SolverContact* contacts, IslandSweeps& islands) {
  for (ManifoldLanes<T>& g : groups) {
    LaneMask<T> live{};
    bool any = false;
    for (std::size_t l = 0; l < g.lanes; ++l) {
      const bool on = islands.live[g.island[l]] != 0;
      setMaskLane(live, l, on);
      any = any || on;
    }
    if (!any) continue;
    T change{}, impulse{};
    sweepGroup(g, bodies, live, contacts, change, impulse);
    for (std::size_t l = 0; l < g.lanes; ++l) {
      const std::uint32_t i = g.island[l];
      islands.change[i] = std::max(islands.change[i], laneValue(change, l));
      islands.impulse[i] = std::max(islands.impulse[i], laneValue(impulse, l));
    }
  }
}

// Sweeps until every island has converged or run out of sweeps; converged[i] as solveVelocities has it.
template <class T>
RIGID_BODY_LANE_INLINE void runSweeps(std::vector<ManifoldLanes<T>>& groups, LaneBodyVelocity* bodies,
                                      const SolverContact* contacts, IslandSweeps& islands, char* converged,
                                      int iterations) {
  const std::size_t count = islands.allowed.size();
  for (std::size_t sweep = 0;; ++sweep) {
    bool any = false;
    for (std::size_t i = 0; i < count; ++i) {
      islands.live[i] = !converged[i] && sweep < islands.allowed[i];
      any = any || islands.live[i];
      islands.change[i] = 0.0, islands.impulse[i] = 0.0;
    }
    if (!any) return;
    sweepGroups(groups, bodies, contacts, islands);
    // To rounding within the sweeps asked for; beyond them, to a change of 1e-9 of the impulses.
    const double tolerance = sweep < static_cast<std::size_t>(iterations) ? 1e-14 : 1e-9;
    for (std::size_t i = 0; i < count; ++i) {
      if (!islands.live[i] || islands.change[i] > tolerance * islands.impulse[i]) continue;
      converged[i] = sweep < static_cast<std::size_t>(iterations) ? kConvergedInSweeps : kConvergedBeyond;
    }
  }
}

}  // namespace RIGID_BODY_CONTACT_LANES_ISA
}  // namespace contact
}  // namespace rigid_body
