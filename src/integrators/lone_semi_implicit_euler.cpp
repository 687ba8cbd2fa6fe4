// One body's semi-implicit Euler step (the lone instantiation of its lane kernel), in a file of its own so that
// it compiles without GCC's straight-line (SLP) vectoriser: its pairing of the Cayley turns' scalar
// arithmetic into two-lane operations cost the lone step more in shuffles than it saved (see
// docs/performance.md). The batched kernels and the other methods' lone steps keep it.
#include "lane_steps.hpp"

namespace rigid_body {
namespace integrators {

template bool laneStep<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                            const AppliedWrench& input, double h, State& state);

}  // namespace integrators
}  // namespace rigid_body
