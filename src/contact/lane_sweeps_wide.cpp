// The lane solver's sweeps in AVX and AVX-512 operations, for a build whose baseline (SSE2) splits each
// into 128-bit ones (lane_contact_solver.cpp picks them at run time, as the free bodies' wide_lanes.cpp
// does). The kernel (lane_kernel.hpp) is compiled here once per instruction set under a target pragma, so
// that its helpers' comparisons and selections are that set's own (lane_kernel.hpp says why). The layout
// and everything holding Eigen are included first, under the build's options: Eigen's alignment must not
// change with the pragma.
#include "contact_lanes.hpp"

#ifdef RIGID_BODY_WIDE_CONTACT_LANES

// Everything lane_kernel.hpp includes, here, so that nothing but the kernel itself is compiled under the
// pragmas (an inline function of a header compiled for AVX here could be the copy the linker keeps).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "lane_contact_solver.hpp"

// The pragma does not define __AVX__ in C++: the kernel is told that its instructions may be AVX ones.
#define RIGID_BODY_CONTACT_LANES_AVX 1
#pragma GCC push_options
#pragma GCC target("avx")
#define RIGID_BODY_CONTACT_LANES_ISA avx
#include "lane_kernel.hpp"
#undef RIGID_BODY_CONTACT_LANES_ISA
namespace rigid_body::contact {
void runSweepsAvx(std::vector<ManifoldLanes<Lanes>>& groups, LaneBodyVelocity* bodies, const SolverContact* contacts,
                  IslandSweeps& islands, char* converged, int iterations) {
  avx::runSweeps(groups, bodies, contacts, islands, converged, iterations);
}
void runSweepsAvx(std::vector<ManifoldLanes<EightLanes>>& groups, LaneBodyVelocity* bodies,
                  const SolverContact* contacts, IslandSweeps& islands, char* converged, int iterations) {
  avx::runSweeps(groups, bodies, contacts, islands, converged, iterations);
}
}  // namespace rigid_body::contact
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
#define RIGID_BODY_CONTACT_LANES_ISA avx512
#include "lane_kernel.hpp"
#undef RIGID_BODY_CONTACT_LANES_ISA
void rigid_body::contact::runSweepsAvx512(std::vector<ManifoldLanes<EightLanes>>& groups, LaneBodyVelocity* bodies,
                                          const SolverContact* contacts, IslandSweeps& islands, char* converged,
                                          int iterations) {
  avx512::runSweeps(groups, bodies, contacts, islands, converged, iterations);
}
#pragma GCC pop_options

#undef RIGID_BODY_CONTACT_LANES_AVX
#endif  // RIGID_BODY_WIDE_CONTACT_LANES
