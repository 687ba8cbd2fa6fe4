// The batched step compiled for two instruction sets, chosen at run time: a portable build (x86-64's SSE2
// baseline) still runs four-body batches as single 256-bit operations on a CPU with AVX. Only this file's
// runBatch is compiled for AVX, with every piece of the step inlined into it; nothing of Eigen crosses into
// it (a whole translation unit built with -mavx would change Eigen's alignment and disagree with the rest).
#include "lane_steps.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace rigid_body {
namespace integrators {

namespace {

#if defined(__x86_64__) && !defined(__AVX__)
#define RIGID_BODY_WIDE_LANES 1
__attribute__((target("avx"))) void runBatchAvx(IntegratorType type, const LaneBody<Lanes>& b, const StepTerms& terms,
                                                double h, std::int64_t steps, std::size_t count, LaneState<Lanes>& y,
                                                std::int64_t* done, bool* running) {
  runLanes(type, b, terms, h, steps, count, y, done, running);
}
#endif

}  // namespace

bool wideLanesAvailable() {
#ifdef RIGID_BODY_WIDE_LANES
  static const bool available = __builtin_cpu_supports("avx");
  return available;
#else
  return false;  // not x86-64, or the whole build already targets AVX (RIGID_BODY_SIM_NATIVE)
#endif
}

void runBatch(bool wide, IntegratorType type, const LaneBody<Lanes>& b, const StepTerms& terms, double h,
              std::int64_t steps, std::size_t count, LaneState<Lanes>& y, std::int64_t* done, bool* running) {
#ifdef RIGID_BODY_WIDE_LANES
  if (wide) {
    runBatchAvx(type, b, terms, h, steps, count, y, done, running);
    return;
  }
#endif
  (void)wide;
  runLanes(type, b, terms, h, steps, count, y, done, running);  // the build's own instruction set
}

}  // namespace integrators
}  // namespace rigid_body

#pragma GCC diagnostic pop
