// One body's semi-implicit Euler step (the lone instantiations of its lane kernel: Integrator::step's, in the
// build's instructions and in AVX-512's, and a Scene's lone body's loop), in a file of its own so that it
// compiles without GCC's straight-line (SLP) vectoriser: its pairing of the Cayley turns' scalar arithmetic
// into two-lane operations cost the lone step more in shuffles than it saved (see docs/performance.md). The
// batched kernels and the other methods' lone steps keep it.
#include "lane_dispatch.hpp"

namespace rigid_body {
namespace integrators {

template bool stepOneBody<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                            const AppliedWrench& input, double h, State& state);
template void stepLanesOf<IntegratorType::kSemiImplicitEuler, double>(const LaneBody<double>& b,
                                                                     const StepTerms& terms, double h,
                                                                     std::int64_t steps, std::size_t count,
                                                                     LaneState<double>& y, std::int64_t* done,
                                                                     bool* running);
#ifdef RIGID_BODY_WIDE_LONE_STEPS
template bool stepOneBodyAvx512<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                                const AppliedWrench& input, double h, State& state);
template void stepLoneAvx512<IntegratorType::kSemiImplicitEuler>(const LaneBody<double>& b, const StepTerms& terms,
                                                              double h, std::int64_t steps, LaneState<double>& y,
                                                              std::int64_t* done, bool* running);
#endif

}  // namespace integrators
}  // namespace rigid_body
