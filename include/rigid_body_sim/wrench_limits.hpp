// Acceptance of a commanded wrench: finite, and within the magnitudes the scene allows.
#pragma once

#include <limits>

#include "rigid_body_sim/forces.hpp"

namespace rigid_body {

/// Largest accepted magnitudes of a commanded wrench. Infinity (the default) means no limit; the check
/// still runs, and non-finite components are always refused.
struct WrenchLimits {
  double max_force = std::numeric_limits<double>::infinity();   ///< |F| [N]
  double max_torque = std::numeric_limits<double>::infinity();  ///< |τ| [N m]
};

/// Why a wrench was refused, or kAccepted.
enum class WrenchVerdict { kAccepted, kNonFinite, kForceOverLimit, kTorqueOverLimit };

/// Judges a wrench given in any axes. The magnitudes are computed without overflow (hypot-style scaling), so
/// components of 1e308 give |F| ≈ 1.7e308, not Inf.
WrenchVerdict checkWrench(const Wrench& wrench, const WrenchLimits& limits);

/// A short name of the verdict for logs and diagnostics: "accepted", "non_finite", ...
const char* verdictName(WrenchVerdict verdict);

}  // namespace rigid_body
