// The terms one body's step is assembled from, decided once at start-up from what the scene declares,
// so that cost follows the scene: a zero-g scene has no gravity term, a body that cannot spin no rotation.
#pragma once

#include <string>

#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// Which terms of Ẏ = f(Y, u) a body's step evaluates. all() is the general step (every term, whatever its
/// value); assembleTerms leaves out the ones the scene makes zero. Both give the same trajectory (to rounding:
/// a left-out term would have added exactly zero, or, for world_inertia, the same ω by another product).
struct StepTerms {
  bool input = true;            ///< the applied wrench u (world and body parts): the body takes wrench commands
  bool gravity = true;          ///< F += M g
  bool linear_damping = true;   ///< F −= c v
  bool angular_damping = true;  ///< τ −= c_ω ω
  bool rotation = true;         ///< q and L are integrated; off, q and L stay as they are (L = 0, no torque)
  bool world_inertia = true;    ///< ω = R I_Bcm_B⁻¹ Rᵀ L; off (isotropic body), ω = L/I₀ with no rotation

  static StepTerms all() { return StepTerms(); }
  bool operator==(const StepTerms& other) const {
    return input == other.input && gravity == other.gravity && linear_damping == other.linear_damping &&
           angular_damping == other.angular_damping && rotation == other.rotation &&
           world_inertia == other.world_inertia;
  }
  bool operator!=(const StepTerms& other) const { return !(*this == other); }
};

/// The terms a body needs: gravity if g ≠ 0, each damping if its coefficient is > 0, the input if the body
/// takes wrench commands, rotation if it can spin (it takes input, which may carry a torque, it collides,
/// and a contact off its centre of mass makes a torque, or L ≠ 0: no other term makes a torque about the
/// centre of mass while ω = 0), and with rotation the world-inertia rotation unless the inertia is
/// isotropic and the angular damping if its coefficient is > 0.
StepTerms assembleTerms(const MassProperties& mass, const ForceModel& forces, const State& state, bool takes_input,
                        bool collides = false);

/// "translation, rotation (isotropic: w = L/I0), wrench input, gravity": the assembled terms, for the start-up
/// log (ASCII: roslaunch prints other characters as "?" under a C locale).
std::string describeTerms(const StepTerms& terms);

}  // namespace rigid_body
