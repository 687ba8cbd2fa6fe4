#include "rigid_body_sim/wrench_limits.hpp"

namespace rigid_body {

WrenchVerdict checkWrench(const Wrench& wrench, const WrenchLimits& limits) {
  if (!wrench.isFinite()) return WrenchVerdict::kNonFinite;
  // stableNorm scales before squaring: no overflow for components near DBL_MAX.
  if (wrench.force.stableNorm() > limits.max_force) return WrenchVerdict::kForceOverLimit;
  if (wrench.torque.stableNorm() > limits.max_torque) return WrenchVerdict::kTorqueOverLimit;
  return WrenchVerdict::kAccepted;
}

const char* verdictName(WrenchVerdict verdict) {
  switch (verdict) {
    case WrenchVerdict::kAccepted:
      return "accepted";
    case WrenchVerdict::kNonFinite:
      return "non_finite";
    case WrenchVerdict::kForceOverLimit:
      return "force_over_limit";
    case WrenchVerdict::kTorqueOverLimit:
      return "torque_over_limit";
  }
  return "unknown";
}

}  // namespace rigid_body
