// The resting solve's velocity sweeps in vector lanes (docs/contact.md, "The solver's lanes"): the sequential
// impulses of contact_solver.hpp's solveVelocities, swept colour by colour over the manifolds of a block of
// islands (manifold_colouring.hpp), four manifolds side by side in the lanes of a vector, each lane solving
// its manifold's points one after another. A lane computes what one manifold solved alone computes, with
// the same operations in the same order, so the results are the same bits in four lanes as in one
// (`lanes = 1`, the scalar form, a double per lane), and the same whatever islands share the block. The
// readable solver swept over the same contacts in the same order (colour by colour) agrees to rounding.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "contact_solver.hpp"
#include "manifold_colouring.hpp"

namespace rigid_body {
namespace contact {

/// How the lane solver runs.
struct LaneSettings {
  /// Manifolds per vector: 1 (one double per lane, the scalar form), 4, 8 (one AVX-512 vector, two AVX
  /// ones), or 0: the most this CPU runs as whole vectors (bestLaneCount). The same bits with any.
  std::size_t lanes = 0;
  /// The lanes as AVX-512 or AVX operations where the CPU has them (the same bits as the baseline's).
  bool wide_instructions = true;
};

/// How an island's sweeps ended: converged to rounding (1e-14 of its impulses) within the sweeps asked
/// for, or only to the looser 1e-9 in the sweeps allowed beyond them (a chain of faces whose change crawls
/// one face a sweep meets that without holding: such an island is still solved at once, sticking_solve.hpp).
constexpr char kConvergedInSweeps = 1;
constexpr char kConvergedBeyond = 2;

/// Eight manifolds per vector where the lanes run as AVX-512 operations, four as AVX ones, else one: GCC
/// forms the masks of a vector wider than the instruction set's registers one lane at a time, with a branch
/// each, and such a sweep is slower than the scalar form's (docs/contact.md, "The solver's lanes").
std::size_t bestLaneCount(bool wide_instructions);

class LaneContactSolver {
 public:
  LaneContactSolver();
  ~LaneContactSolver();
  LaneContactSolver(LaneContactSolver&&) noexcept;
  LaneContactSolver& operator=(LaneContactSolver&&) noexcept;

  /// The velocity sweeps of `count` islands (ranges of the lists over disjoint runs of bodies, whose union
  /// is one run), their contacts prepared by prepareContacts: each island sweeps until its own impulses
  /// converge or its sweeps (as solveVelocities counts them) run out, colour by colour. Sets converged[i]
  /// (kConvergedInSweeps, kConvergedBeyond or 0; nonzero where solveVelocities returns true), each
  /// contact's impulses and slip_squared and each body's v and w (not dP and dL: sumImpulses).
  void solve(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options,
             const SolveRange* islands, std::size_t count, char* converged, const LaneSettings& lanes);

  /// The contacts of the islands of the last solve in the order it swept them (colour by colour): the order
  /// in which the readable solver gets the same impulses to rounding.
  std::vector<std::size_t> sweepOrder() const;

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
  ManifoldColouring colouring_;
};

}  // namespace contact
}  // namespace rigid_body
