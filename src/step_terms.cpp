#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

StepTerms assembleTerms(const MassProperties& mass, const ForceModel& forces, const State& state, bool takes_input,
                        bool collides) {
  StepTerms terms;
  terms.input = takes_input;
  terms.gravity = !forces.gravity_W.isZero(0.0);
  terms.linear_damping = forces.linear_damping > 0.0;
  terms.rotation = takes_input || collides || !state.L_W.isZero(0.0);
  // With no rotation ω stays 0, so the angular damping torque −c_ω ω is 0 as well.
  terms.angular_damping = terms.rotation && forces.angular_damping > 0.0;
  terms.world_inertia = terms.rotation && !mass.isIsotropic();
  return terms;
}

std::string describeTerms(const StepTerms& terms) {
  std::string text = "translation";
  if (terms.rotation) text += terms.world_inertia ? ", rotation (w = R I^-1 R^T L)" : ", rotation (isotropic: w = L/I0)";
  if (terms.input) text += ", wrench input";
  if (terms.gravity) text += ", gravity";
  if (terms.linear_damping) text += ", linear damping";
  if (terms.angular_damping) text += ", angular damping";
  return text;
}

}  // namespace rigid_body
