// The lane solver's layout and kernel (docs/contact.md, "The solver's lanes"; lane: docs/architecture.md).
// A group holds up to kLaneCount<T> manifolds of one colour, one per lane, point by point (structure of
// arrays: a point slot's field is one T across the lanes); the kernel sweeps a group once. T is double (one
// lane, the scalar form) or integrators::Lanes (four), and the kernel is written once for both with the
// lanes' own arithmetic (src/integrators/lane_math.hpp), so each lane rounds as one lane alone does.
// Internal to the contact solver.
#pragma once

#include <cstddef>
#include <cstdint>

#include "contact_solver.hpp"
#include "integrators/lane_math.hpp"
#include "manifold_colouring.hpp"

namespace rigid_body {
namespace contact {

using integrators::kLaneCount;
using integrators::Lanes;
using integrators::Vec;

/// A comparison's result: bool for one lane, a vector of 0 / −1 for Lanes.
template <class T>
using LaneMask = decltype(T() < T());

/// A solver body's velocities and inverse mass, as the lanes gather and scatter them.
struct LaneBodyVelocity {
  double v[3], w[3], inverse_mass;
};

/// One point slot of a group: the prepared quantities of SolverContact, a T across the lanes. Aligned for
/// the wide instructions: a baseline (SSE2) build aligns four lanes to 16 bytes only, and the AVX code loads
/// them as aligned 32-byte vectors.
template <class T>
struct alignas(32) PointLanes {
  Vec<T> n, t1, t2;
  Vec<T> cross_a[3], cross_b[3];        // r × d for d = n, t1, t2
  Vec<T> response_a[3], response_b[3];  // I⁻¹ (r × d)
  T normal_mass, tangent_mass00, tangent_mass01, tangent_mass11;
  T friction, target_speed, normal_floor;
  T present;  // 1 where the lane's manifold has a point in this slot, else 0 (and every other field 0)
  T normal_impulse, friction1, friction2, slip_squared;
};

/// Up to kLaneCount<T> manifolds of one colour (no two share a body but the environment).
template <class T>
struct alignas(32) ManifoldLanes {
  static constexpr std::size_t kWidth = kLaneCount<T>;
  PointLanes<T> point[kMaxManifoldPoints];
  std::uint32_t body_a[kWidth], body_b[kWidth];  // indices into the block's LaneBodyVelocity (0: environment)
  std::uint32_t island[kWidth];
  std::size_t first_contact[kWidth];
  std::uint32_t lanes, slots;  // lanes in use; the most points of any of them
};

template <class T>
RIGID_BODY_LANE_INLINE T dot(const Vec<T>& a, const Vec<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
// std::max's and a sign test's semantics, lane by lane (the same in one lane as in four).
RIGID_BODY_LANE_INLINE double laneSelect(bool m, double a, double b) { return m ? a : b; }
RIGID_BODY_LANE_INLINE Lanes laneSelect(LaneMask<Lanes> m, Lanes a, Lanes b) { return m ? a : b; }
template <class T>
RIGID_BODY_LANE_INLINE T laneMax(T a, T b) {
  return laneSelect(a < b, b, a);
}
template <class T>
RIGID_BODY_LANE_INLINE T laneAbs(T a) {
  return laneSelect(a < 0.0, -a, a);
}
RIGID_BODY_LANE_INLINE bool laneOn(bool m, std::size_t) { return m; }
RIGID_BODY_LANE_INLINE bool laneOn(LaneMask<Lanes> m, std::size_t i) { return m[i] != 0; }
RIGID_BODY_LANE_INLINE bool anyLane(bool m) { return m; }
RIGID_BODY_LANE_INLINE bool anyLane(LaneMask<Lanes> m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
RIGID_BODY_LANE_INLINE void setMaskLane(bool& m, std::size_t, bool on) { m = on; }
RIGID_BODY_LANE_INLINE void setMaskLane(LaneMask<Lanes>& m, std::size_t i, bool on) { m[i] = on ? -1 : 0; }

/// The friction impulse on the disc of radius `limit` for a point whose sticking impulse (f1, f2) lies
/// outside it (friction_disc.hpp), written to f1, f2. Out of line: it is scalar code with Eigen, and the
/// kernel may be compiled for another instruction set.
void frictionOntoDisc(const SolverContact& contact, double limit, double& f1, double& f2);

template <class T>
RIGID_BODY_LANE_INLINE void gatherVelocity(Vec<T>& v, Vec<T>& w, T& inverse_mass, const LaneBodyVelocity& body,
                                           std::size_t lane) {
  integrators::setLane(v.x, lane, body.v[0]), integrators::setLane(v.y, lane, body.v[1]);
  integrators::setLane(v.z, lane, body.v[2]);
  integrators::setLane(w.x, lane, body.w[0]), integrators::setLane(w.y, lane, body.w[1]);
  integrators::setLane(w.z, lane, body.w[2]);
  integrators::setLane(inverse_mass, lane, body.inverse_mass);
}
template <class T>
RIGID_BODY_LANE_INLINE void scatterVelocity(const Vec<T>& v, const Vec<T>& w, LaneBodyVelocity& body, std::size_t lane) {
  body.v[0] = integrators::laneValue(v.x, lane), body.v[1] = integrators::laneValue(v.y, lane);
  body.v[2] = integrators::laneValue(v.z, lane);
  body.w[0] = integrators::laneValue(w.x, lane), body.w[1] = integrators::laneValue(w.y, lane);
  body.w[2] = integrators::laneValue(w.z, lane);
}

/// One sweep of a group's points, slot by slot: in each lane solveVelocities' update of one point (normal,
/// then friction). Lanes off in `live` (their island converged, or no manifold) change nothing that is
/// written back. Raises `change` and `impulse` lane by lane to the largest impulse change and impulse.
template <class T>
RIGID_BODY_LANE_INLINE void sweepGroup(ManifoldLanes<T>& g, LaneBodyVelocity* bodies, LaneMask<T> live,
                                       const SolverContact* contacts, T& change, T& impulse) {
  Vec<T> va{}, wa{}, vb{}, wb{};
  T ma{}, mb{};
  for (std::size_t l = 0; l < g.lanes; ++l) {
    gatherVelocity(va, wa, ma, bodies[g.body_a[l]], l);
    gatherVelocity(vb, wb, mb, bodies[g.body_b[l]], l);
  }
  for (std::size_t p = 0; p < g.slots; ++p) {
    PointLanes<T>& s = g.point[p];
    const LaneMask<T> on = live & (s.present > 0.0);
    // Normal: v_n ≥ target, impulse ≥ the floor (a contact pushes, never pulls).
    const T v_n = dot(s.n, va - vb) + dot(s.cross_a[0], wa) - dot(s.cross_b[0], wb);
    const T normal = laneSelect(on, laneMax(s.normal_floor, s.normal_impulse - s.normal_mass * (v_n - s.target_speed)),
                                s.normal_impulse);
    const T dn = normal - s.normal_impulse;
    s.normal_impulse = normal;
    va = va + (ma * dn) * s.n, wa = wa + dn * s.response_a[0];
    vb = vb - (mb * dn) * s.n, wb = wb - dn * s.response_b[0];
    // Friction: the sticking impulse if the disc |f| ≤ μ f_n holds it, else its projection onto the disc.
    const Vec<T> dv = va - vb;
    const T s1 = dot(s.t1, dv) + dot(s.cross_a[1], wa) - dot(s.cross_b[1], wb);
    const T s2 = dot(s.t2, dv) + dot(s.cross_a[2], wa) - dot(s.cross_b[2], wb);
    s.slip_squared = laneSelect(on, s1 * s1 + s2 * s2, s.slip_squared);
    T f1 = s.friction1 - (s.tangent_mass00 * s1 + s.tangent_mass01 * s2);
    T f2 = s.friction2 - (s.tangent_mass01 * s1 + s.tangent_mass11 * s2);
    const T limit = s.friction * normal;
    const LaneMask<T> outside = on & (f1 * f1 + f2 * f2 > limit * limit);
    if (anyLane(outside)) {
      for (std::size_t l = 0; l < g.lanes; ++l) {
        if (!laneOn(outside, l)) continue;
        double d1 = integrators::laneValue(f1, l), d2 = integrators::laneValue(f2, l);
        frictionOntoDisc(contacts[g.first_contact[l] + p], integrators::laneValue(limit, l), d1, d2);
        integrators::setLane(f1, l, d1), integrators::setLane(f2, l, d2);
      }
    }
    f1 = laneSelect(on, f1, s.friction1), f2 = laneSelect(on, f2, s.friction2);
    const T df1 = f1 - s.friction1, df2 = f2 - s.friction2;
    s.friction1 = f1, s.friction2 = f2;
    const Vec<T> linear = df1 * s.t1 + df2 * s.t2;
    va = va + ma * linear, wa = wa + (df1 * s.response_a[1] + df2 * s.response_a[2]);
    vb = vb - mb * linear, wb = wb - (df1 * s.response_b[1] + df2 * s.response_b[2]);
    change = laneMax(change, laneMax(laneAbs(dn), laneMax(laneAbs(df1), laneAbs(df2))));
    impulse = laneMax(impulse, laneMax(normal, laneMax(laneAbs(f1), laneAbs(f2))));
  }
  for (std::size_t l = 0; l < g.lanes; ++l) {
    if (!laneOn(live, l)) continue;
    // The environment's entry (0) is the block's own copy, never read back: writing it is harmless.
    scatterVelocity(va, wa, bodies[g.body_a[l]], l);
    scatterVelocity(vb, wb, bodies[g.body_b[l]], l);
  }
}

}  // namespace contact
}  // namespace rigid_body
