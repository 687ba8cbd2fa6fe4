// The lane solver's layout (docs/contact.md, "The solver's lanes"; lane: docs/architecture.md): a group
// holds up to kLaneCount<T> manifolds of one colour, one per lane, point by point (structure of arrays: a
// point slot's field is one T across the lanes). T is double (one lane, the scalar form), integrators::Lanes
// (four) or EightLanes. The kernel that sweeps a group is lane_kernel.hpp. Internal to the contact solver.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "contact_solver.hpp"
#include "integrators/lane_math.hpp"
#include "joint_normals.hpp"
#include "manifold_colouring.hpp"

namespace rigid_body {
namespace contact {

using integrators::kLaneCount;
using integrators::Lanes;
using integrators::Vec;

/// Eight doubles: two groups' worth of AVX lanes in one type, so that two manifolds' chains of dependent
/// updates run side by side (one AVX-512 operation, or two AVX ones).
typedef double EightLanes __attribute__((vector_size(64)));

/// A comparison's result: bool for one lane, a vector of 0 / −1 for several.
template <class T>
using LaneMask = decltype(T() < T());

/// A solver body's velocities and inverse mass, as the lanes gather and scatter them: eight doubles, two
/// rows of four that the kernel transposes into four lanes (lane_kernel.hpp, gatherSide).
struct alignas(64) LaneBodyVelocity {
  double v[3], w[3], inverse_mass;
  double unused = 0.0;
};
static_assert(sizeof(LaneBodyVelocity) == 8 * sizeof(double), "two rows of four doubles");

/// One point slot of a group: the prepared quantities of SolverContact, a T across the lanes. Aligned for
/// the widest instructions: a baseline (SSE2) build aligns a vector of lanes to 16 bytes only, and the AVX
/// and AVX-512 code loads them as aligned 32- and 64-byte vectors.
template <class T>
struct alignas(64) PointLanes {
  Vec<T> n, t1, t2;
  Vec<T> cross_a[3], cross_b[3];        // r × d for d = n, t1, t2
  Vec<T> response_a[3], response_b[3];  // I⁻¹ (r × d)
  T normal_mass, tangent_mass00, tangent_mass01, tangent_mass11;
  T tangent_response00, tangent_response01, tangent_response11;  // K of the tangents (01 symmetrised)
  T friction, target_speed, normal_floor;
  T present;  // 1 where the lane's manifold has a point in this slot, else 0 (and every other field 0)
  T normal_impulse, friction1, friction2, slip_squared;
};

/// Up to kLaneCount<T> manifolds of one colour (no two share a body but the environment).
template <class T>
struct alignas(64) ManifoldLanes {
  static constexpr std::size_t kWidth = kLaneCount<T>;
  PointLanes<T> point[kMaxManifoldPoints];
  std::uint32_t body_a[kWidth], body_b[kWidth];  // indices into the block's LaneBodyVelocity (0: environment)
  std::uint32_t island[kWidth];
  std::size_t first_contact[kWidth];
  std::uint32_t count[kWidth];  // the lane's manifold's points
  std::uint32_t lanes, slots;  // lanes in use; the most points of any of them
  T inverse[kJointEntries];  // K⁺ of the manifold's normal rows, its upper triangle (joint_normals.hpp)
  T inverted;  // 1 once K⁺ has been looked for (the first time the face was not at rest), else 0
  T joint;     // 1 where the lane's manifold has a K⁺ and its normals are solved together, else 0
};

/// Each island's progress through the sweeps (solveVelocities' rule, island by island).
struct IslandSweeps {
  std::vector<std::size_t> allowed;  // how many sweeps each island may take
  std::vector<char> live;            // sweeping in this sweep
  std::vector<double> change, impulse;
};

#if defined(__x86_64__) && !defined(__AVX__)
#define RIGID_BODY_WIDE_CONTACT_LANES 1
/// The sweeps (lane_kernel.hpp's runSweeps) in AVX and AVX-512 operations (lane_sweeps_wide.cpp), for a CPU
/// that has them in a build whose baseline (SSE2) splits each into 128-bit ones.
void runSweepsAvx(std::vector<ManifoldLanes<Lanes>>& groups, LaneBodyVelocity* bodies, const SolverContact* contacts,
                  IslandSweeps& islands, char* converged, int iterations);
void runSweepsAvx(std::vector<ManifoldLanes<EightLanes>>& groups, LaneBodyVelocity* bodies,
                  const SolverContact* contacts, IslandSweeps& islands, char* converged, int iterations);
void runSweepsAvx512(std::vector<ManifoldLanes<EightLanes>>& groups, LaneBodyVelocity* bodies,
                     const SolverContact* contacts, IslandSweeps& islands, char* converged, int iterations);
/// `count` ≥ 8 consecutive doubles from each of eight places, from[l] for lane l, into `count` consecutive
/// vectors of eight lanes (to[f] lane l = from[l][f]), in AVX-512 operations (lane_loads_wide.cpp): for a
/// CPU that has them. The same for four lanes (`count` ≥ 4) in AVX operations.
void transposeIntoLanes(EightLanes* to, const double* const* from, std::size_t count);
void transposeIntoLanes(Lanes* to, const double* const* from, std::size_t count);
#endif

/// Lane l of a point slot from contact c: every field of it (the other lanes' untouched).
template <class T>
void loadPoint(PointLanes<T>& s, std::size_t l, const SolverContact& c);

/// Whether a full point slot (every lane with a point) of lane type T may be loaded by transposes
/// (loadFullSlot): T has four lanes and the CPU AVX, or eight and AVX-512; the build splits them
/// (RIGID_BODY_WIDE_CONTACT_LANES); and the contact's and the slot's runs of fields lie as the transposes
/// read and write them.
template <class T>
bool slotLoadsTransposed();
/// A full point slot, lane l from *contacts[l], as loadPoint gives it lane by lane: the directions and the
/// Jacobian products by transposes, the rest lane by lane. Only where slotLoadsTransposed<T>().
template <class T>
void loadFullSlot(PointLanes<T>& s, const SolverContact* const* contacts);

}  // namespace contact
}  // namespace rigid_body
