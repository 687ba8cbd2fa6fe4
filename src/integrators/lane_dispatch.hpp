// The lane kernels' entry points: the method chosen at run time once (withMethod), the loop that steps lanes
// until a step is refused, the one-body step Integrator::step runs, and the instruction-set variants
// (wide_lanes.cpp compiles the four-body loop for AVX, and the one-body step for AVX-512, picked at run time).
// Which function exists for what, and why each is a function of its own: docs/architecture.md ("lane").
// Internal to the integrators.
#pragma once

#include "lane_loading.hpp"
#include "lane_runge_kutta.hpp"
#include "lane_semi_implicit_euler.hpp"

namespace rigid_body {
namespace integrators {

/// Whether a method steps by these kernels.
inline bool hasLaneStep(IntegratorType type) { return integratorInfo(type).lane_kernel; }

/// f(std::integral_constant<IntegratorType, kType>{}) for the method with a lane kernel that `type` names
/// (hasLaneStep), and what f returns: each method's code a compile-time choice, the switch once.
template <class F>
decltype(auto) withMethod(IntegratorType type, F&& f) {
  switch (type) {
    case IntegratorType::kRk4:
      return f(std::integral_constant<IntegratorType, IntegratorType::kRk4>{});
    case IntegratorType::kSemiImplicitEuler:
      return f(std::integral_constant<IntegratorType, IntegratorType::kSemiImplicitEuler>{});
    default:
      return f(std::integral_constant<IntegratorType, IntegratorType::kExplicitEuler>{});
  }
}

/// One step of a method with a lane kernel (hasLaneStep), for the lanes as T holds them.
template <class T>
RIGID_BODY_LANE_INLINE LaneState<T> laneKernelStep(IntegratorType type, const LaneBody<T>& b, const StepTerms& terms, double h,
                             const LaneState<T>& y) {
  switch (type) {
    case IntegratorType::kRk4:
      return laneRk4Step(b, terms, h, y);
    case IntegratorType::kSemiImplicitEuler:
      return laneSemiImplicitEulerStep(b, terms, h, y);
    default:
      return laneEulerStep(b, terms, h, y);
  }
}

/// Up to `steps` steps of the lanes of y, of which the first `count` hold bodies. A lane stops at its first
/// step that acceptableLanes refuses: running[i] turns false and done[i] is the steps it took; it computes on
/// unread (y's lane is then not its state). A lane that never stops has done[i] = steps.
template <class T>
RIGID_BODY_LANE_INLINE void stepLanesUntilRefused(IntegratorType type, const LaneBody<T>& b, const StepTerms& terms, double h,
                                     std::int64_t steps, std::size_t count, LaneState<T>& y, std::int64_t* done,
                                     bool* running) {
  std::size_t still_running = count;
  for (std::size_t i = 0; i < count; ++i) {
    done[i] = steps;
    running[i] = true;
  }
  bool ok[kLaneCount<T>];
  // The loop on copies: through the references, every store of the state could change the body's constants
  // (both are doubles), so GCC stored the state and loaded the constants again at every step.
  const LaneBody<T> body = b;
  LaneState<T> state = y;
  for (std::int64_t k = 0; k < steps && still_running > 0; ++k) {
    const LaneState<T> next = laneKernelStep(type, body, terms, h, state);
    acceptableLanes(next, count, ok);
    for (std::size_t i = 0; i < count; ++i) {
      if (!running[i] || ok[i]) continue;
      running[i] = false;  // Integrator::step's refusal: the step is not taken, the body stops here
      done[i] = k;
      --still_running;
    }
    state = next;
  }
  y = state;
}

/// Every term assembled (StepTerms' defaults) as a compile-time constant: the lone kernels run a copy of their
/// step with it where a body's terms are all on (stepOneBodyInline says why).
inline constexpr StepTerms kAllTerms{};

/// stepLanesUntilRefused with the general terms as constants where they are all assembled, for one lane under semi-implicit
/// Euler, as stepOneBodyInline runs its step (it says why); rk4's loop gains nothing by it and keeps the terms as they
/// come (docs/performance_log.md#constant-terms).
template <IntegratorType kType, class T>
RIGID_BODY_LANE_INLINE void stepLanesWithConstantTerms(const LaneBody<T>& b, const StepTerms& terms, double h,
                                              std::int64_t steps, std::size_t count, LaneState<T>& y,
                                              std::int64_t* done, bool* running) {
  if constexpr (kLaneCount<T> == 1 && kType == IntegratorType::kSemiImplicitEuler) {
    if (terms == kAllTerms) {
      stepLanesUntilRefused(kType, b, kAllTerms, h, steps, count, y, done, running);
      return;
    }
  }
  stepLanesUntilRefused(kType, b, terms, h, steps, count, y, done, running);
}

/// stepLanesUntilRefused for four bodies, compiled twice (wide_lanes.cpp): for the baseline instruction set (x86-64: SSE2,
/// two 128-bit halves per operation) and for AVX (one 256-bit operation), which `wide` picks. The same IEEE
/// operations in the same order, no contraction: the same bits either way (tested).
void stepBatch(bool wide, IntegratorType type, const LaneBody<Lanes>& b, const StepTerms& terms, double h,
              std::int64_t steps, std::size_t count, LaneState<Lanes>& y, std::int64_t* done, bool* running);
/// Whether this CPU (and its operating system) runs AVX: checked once.
bool wideLanesAvailable();
/// stepLanesUntilRefused for one body (a Scene's body without a batch to share), each method a function of its own; with
/// `wide` (and wideLoneStepsAvailable()) in AVX-512's instructions: the same bits.
void stepLone(bool wide, IntegratorType type, const LaneBody<double>& b, const StepTerms& terms, double h,
             std::int64_t steps, LaneState<double>& y, std::int64_t* done, bool* running);

// One body's step by its lane kernel, T = double: load, step, test, store. Only `inline`: GCC compiles it as a
// function of its own, which stepOneBody calls. Forced into stepOneBody (always_inline), the same code came out with
// more instructions and slower, from GCC's register allocation (docs/performance_log.md#lone-step-inlining).
template <IntegratorType kType>
inline bool stepOneBodyInline(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                       State& state) {
  LaneBody<double> b;
  loadBody(b, 0, kType, terms, model, input);
  LaneState<double> y;
  loadState(y, 0, state);
  LaneState<double> next;
  if constexpr (kType == IntegratorType::kRk4 || kType == IntegratorType::kSemiImplicitEuler) {
    // The general terms as constants, a copy of the step of its own: GCC then allocates the registers of RK4's
    // four stages (~50 live values) for the general body alone, free of the terms' branches, and of
    // semi-implicit Euler's ~60 body constants. Explicit Euler loses by it: it takes the terms as they come
    // (docs/performance_log.md#constant-terms).
    next = terms == kAllTerms ? laneKernelStep(kType, b, kAllTerms, h, y) : laneKernelStep(kType, b, terms, h, y);
  } else {
    next = laneKernelStep(kType, b, terms, h, y);
  }
  bool ok = false;
  acceptableLanes(next, 1, &ok);
  if (ok) storeState(next, 0, state);
  return ok;
}

/// One body's step by its lane kernel, T = double: what Integrator::step runs for these methods (one
/// instantiation per method, each a function of its own: inlined into one caller, each method's code moved
/// with edits to the others' (docs/performance_log.md#one-function-per-method). The result goes into
/// `state` only if acceptableLanes accepts it; returns whether it did.
template <IntegratorType kType>
__attribute__((noinline)) bool stepOneBody(const Model& model, const StepTerms& terms, const AppliedWrench& input,
                                        double h, State& state) {
  return stepOneBodyInline<kType>(model, terms, input, h, state);
}

#if defined(__x86_64__) && !defined(__AVX512F__)
#define RIGID_BODY_WIDE_LONE_STEPS 1
/// stepOneBody compiled for AVX-512 (`flatten`: the whole step inlined into it, Eigen's loads and stores too),
/// picked at run time by Integrator where wideLoneStepsAvailable(): the same scalar IEEE operations in the same
/// order, so the same bits, in three-operand instructions with 32 registers instead of SSE2's two-operand
/// ones with 16: fewer copies and spills of RK4's ~50 live values; used for all three methods (explicit
/// Euler's too: docs/performance_log.md#wide-lone-steps). Without GCC's straight-line
/// vectoriser:
/// "avx512f" brings fused multiply-add instructions, and GCC 12's vectoriser fuses a product into a pair of a
/// sum and a difference (vfmaddsub) in spite of -ffp-contract=off (it did so in the native build), which
/// would round apart from the batched step (and the wide rk4 step is faster without it).
#define RIGID_BODY_LONE_WIDE_TARGET target("avx512f"), optimize("no-tree-slp-vectorize")
template <IntegratorType kType>
__attribute__((noinline, flatten, RIGID_BODY_LONE_WIDE_TARGET)) bool stepOneBodyAvx512(const Model& model, const StepTerms& terms,
                                                                        const AppliedWrench& input, double h,
                                                                        State& state) {
  return stepOneBodyInline<kType>(model, terms, input, h, state);
}
#endif
/// stepLanesUntilRefused in the build's own instruction set, each method (and lane type) a function of its own: inlined
/// together into one, each method's register allocation followed the others' code
/// (docs/performance_log.md#one-function-per-method). stepBatch and stepLone (wide_lanes.cpp) call it. Here rather than there, so that
/// semi-implicit Euler's lone loop is compiled in lone_semi_implicit_euler.cpp, as its lone step is.
template <IntegratorType kType, class T>
__attribute__((noinline)) void stepLanesOf(const LaneBody<T>& b, const StepTerms& terms, double h, std::int64_t steps,
                                          std::size_t count, LaneState<T>& y, std::int64_t* done, bool* running) {
  stepLanesWithConstantTerms<kType>(b, terms, h, steps, count, y, done, running);
}
#ifdef RIGID_BODY_WIDE_LONE_STEPS
/// stepLanesOf for one body in AVX-512's instructions, as stepOneBodyAvx512.
template <IntegratorType kType>
__attribute__((noinline, RIGID_BODY_LONE_WIDE_TARGET)) void stepLoneAvx512(const LaneBody<double>& b, const StepTerms& terms,
                                                              double h, std::int64_t steps, LaneState<double>& y,
                                                              std::int64_t* done, bool* running) {
  stepLanesWithConstantTerms<kType>(b, terms, h, steps, 1, y, done, running);
}
#endif

/// Whether stepOneBodyAvx512 is compiled and this CPU (and its operating system) runs AVX-512F: checked once.
bool wideLoneStepsAvailable();

// Compiled in lone_semi_implicit_euler.cpp, with options of its own.
extern template bool stepOneBody<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                                   const AppliedWrench& input, double h, State& state);
extern template void stepLanesOf<IntegratorType::kSemiImplicitEuler, double>(const LaneBody<double>& b,
                                                                            const StepTerms& terms, double h,
                                                                            std::int64_t steps, std::size_t count,
                                                                            LaneState<double>& y,
                                                                            std::int64_t* done, bool* running);
#ifdef RIGID_BODY_WIDE_LONE_STEPS
extern template bool stepOneBodyAvx512<IntegratorType::kSemiImplicitEuler>(const Model& model, const StepTerms& terms,
                                                                       const AppliedWrench& input, double h,
                                                                       State& state);
extern template void stepLoneAvx512<IntegratorType::kSemiImplicitEuler>(const LaneBody<double>& b,
                                                                     const StepTerms& terms, double h,
                                                                     std::int64_t steps, LaneState<double>& y,
                                                                     std::int64_t* done, bool* running);
#endif

}  // namespace integrators
}  // namespace rigid_body

#undef RIGID_BODY_LONE_WIDE_TARGET
