#include "rigid_body_sim/state.hpp"

#include <cmath>

namespace rigid_body {

bool isFinite(const State& state) {
  return state.p_WB.allFinite() && state.q_WB.coeffs().allFinite() && state.P_W.allFinite() &&
         state.L_W.allFinite() && std::isfinite(state.t);
}

}  // namespace rigid_body
