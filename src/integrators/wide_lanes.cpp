// The batched step compiled for two instruction sets, chosen at run time: a portable build (x86-64's SSE2
// baseline) still runs four-body batches as single 256-bit operations on a CPU with AVX, and a lone body's
// steps in AVX-512's scalar instructions on a CPU with those. Only this file's loops are compiled so, with
// every piece of the step inlined into them; nothing of Eigen crosses into them (a whole translation unit
// built with -mavx would change Eigen's alignment and disagree with the rest).
#include "lane_dispatch.hpp"


namespace rigid_body {
namespace integrators {

namespace {

// Each method's loop a function of its own, as stepLanesOf (lane_dispatch.hpp) says why.
#if defined(__x86_64__) && !defined(__AVX__)
#define RIGID_BODY_WIDE_LANES 1
template <IntegratorType kType>
__attribute__((noinline, target("avx"))) void stepBatchAvx(const LaneBody<Lanes>& b, const StepTerms& terms, double h,
                                                          std::int64_t steps, std::size_t count, LaneState<Lanes>& y,
                                                          std::int64_t* done, bool* running) {
  stepLanesUntilRefused(kType, b, terms, h, steps, count, y, done, running);
}
#endif

template <IntegratorType kType>
void stepBatchOf(bool wide, const LaneBody<Lanes>& b, const StepTerms& terms, double h, std::int64_t steps,
                std::size_t count, LaneState<Lanes>& y, std::int64_t* done, bool* running) {
#ifdef RIGID_BODY_WIDE_LANES
  if (wide) {
    stepBatchAvx<kType>(b, terms, h, steps, count, y, done, running);
    return;
  }
#endif
  (void)wide;
  stepLanesOf<kType>(b, terms, h, steps, count, y, done, running);  // the build's own instruction set
}

template <IntegratorType kType>
void stepLoneOf(bool wide, const LaneBody<double>& b, const StepTerms& terms, double h, std::int64_t steps,
               LaneState<double>& y, std::int64_t* done, bool* running) {
#ifdef RIGID_BODY_WIDE_LONE_STEPS
  if (wide && wideLoneStepsAvailable()) {
    stepLoneAvx512<kType>(b, terms, h, steps, y, done, running);
    return;
  }
#endif
  (void)wide;
  stepLanesOf<kType>(b, terms, h, steps, 1, y, done, running);
}

}  // namespace

bool wideLanesAvailable() {
#ifdef RIGID_BODY_WIDE_LANES
  static const bool available = __builtin_cpu_supports("avx");
  return available;
#else
  return false;  // not x86-64, or the whole build already targets AVX (RIGID_BODY_SIM_NATIVE)
#endif
}

bool wideLoneStepsAvailable() {
#ifdef RIGID_BODY_WIDE_LONE_STEPS
  static const bool available = __builtin_cpu_supports("avx512f");
  return available;
#else
  return false;
#endif
}

void stepBatch(bool wide, IntegratorType type, const LaneBody<Lanes>& b, const StepTerms& terms, double h,
              std::int64_t steps, std::size_t count, LaneState<Lanes>& y, std::int64_t* done, bool* running) {
  withMethod(type, [&](auto method) {
    stepBatchOf<decltype(method)::value>(wide, b, terms, h, steps, count, y, done, running);
  });
}

void stepLone(bool wide, IntegratorType type, const LaneBody<double>& b, const StepTerms& terms, double h,
             std::int64_t steps, LaneState<double>& y, std::int64_t* done, bool* running) {
  withMethod(type, [&](auto method) { stepLoneOf<decltype(method)::value>(wide, b, terms, h, steps, y, done, running); });
}

}  // namespace integrators
}  // namespace rigid_body
