// Loading bodies into lanes and back: a kernel's constants (LaneBody) from a body's model, terms and input,
// and its state in and out. For T = double there is one lane (lane index 0). Internal to the integrators.
#pragma once

#include "lane_math.hpp"
#include "methods.hpp"

namespace rigid_body {
namespace integrators {

/// Which branch of semi-implicit Euler's rotation turns a body (the bodies of a batch take one).
enum class SemiImplicitTurn {
  kPrincipalAxes,  ///< the Cayley turns about its principal axes (and every body under another method)
  kBodyAxes,       ///< the same with R_BP = 𝟙: no turn into and out of the principal axes
  kSymmetricTop,   ///< a symmetric top's exact flow
};
inline SemiImplicitTurn semiImplicitTurnKind(IntegratorType type, const MassProperties& mass) {
  if (type != IntegratorType::kSemiImplicitEuler) return SemiImplicitTurn::kPrincipalAxes;
  if (isSymmetricTop(mass)) return SemiImplicitTurn::kSymmetricTop;
  return mass.principalAxesAreBodyAxes() ? SemiImplicitTurn::kBodyAxes : SemiImplicitTurn::kPrincipalAxes;
}

// Lane i of b from a body, only what a step of `type` with these terms reads (a lone body's step loads it at
// every call: a step that needs little loads little).
template <class T>
RIGID_BODY_LANE_INLINE void loadBody(LaneBody<T>& b, std::size_t i, IntegratorType type, const StepTerms& terms,
                                     const Model& model, const AppliedWrench& input) {
  setLane(b.inverse_mass, i, model.mass.inverseMass());
  const bool rotation = terms.rotation || (type == IntegratorType::kSemiImplicitEuler && terms.angular_damping);
  if (rotation && terms.world_inertia) {
    setLane(b.inverse_inertia, i, model.mass.inverseInertia());
  }
  if (rotation) setLane(b.j0, i, model.mass.inverseInertia()(0, 0));
  if (terms.gravity) setLane(b.weight, i, model.mass.mass() * model.forces.gravity_W);
  if (terms.linear_damping) setLane(b.linear_damping, i, model.forces.linear_damping);
  if (terms.angular_damping) setLane(b.angular_damping, i, model.forces.angular_damping);
  if (terms.input) {
    setLane(b.force_W, i, input.world.force);
    setLane(b.torque_W, i, input.world.torque);
    b.body_force = b.body_force || nonZero(input.body.force);  // exactly zero, not nearly
    b.body_torque = b.body_torque || nonZero(input.body.torque);
    // A batch's lanes all hold their values (another lane's may be read); one lane's only where the step
    // reads it (its flag).
    if (kLaneCount<T> > 1 || b.body_force) setLane(b.force_B, i, input.body.force);
    if (kLaneCount<T> > 1 || b.body_torque) setLane(b.torque_B, i, input.body.torque);
    b.world_torque = b.world_torque || nonZero(input.world.torque);
  }
  if (type != IntegratorType::kSemiImplicitEuler || !terms.rotation || !terms.world_inertia) return;
  b.mass[i] = &model.mass;
  const SemiImplicitTurn kind = semiImplicitTurnKind(type, model.mass);  // the same for every body of a batch
  b.symmetric_top = kind == SemiImplicitTurn::kSymmetricTop;
  if (b.symmetric_top) {
    const SymmetricTopAxes top = symmetricTopAxes(model.mass);
    setLane(b.top_axis, i, top.axis);
    setLane(b.top_inverse_pair, i, top.inverse_pair);
    setLane(b.top_spin_coefficient, i, top.spin_coefficient);
    return;
  }
  b.principal_body = kind == SemiImplicitTurn::kBodyAxes;
  setLane(b.inverse_principal, i, model.mass.inversePrincipalMoments());
  setLane(b.principal_axes, i, model.mass.principalAxes());
}

template <class T>
RIGID_BODY_LANE_INLINE void loadState(LaneState<T>& y, std::size_t i, const State& state) {
  setLane(y.p, i, state.p_WB);
  setLane(y.P, i, state.P_W);
  setLane(y.L, i, state.L_W);
  setLane(y.qx, i, state.q_WB.x());
  setLane(y.qy, i, state.q_WB.y());
  setLane(y.qz, i, state.q_WB.z());
  setLane(y.qw, i, state.q_WB.w());
  setLane(y.t, i, state.t);
}

/// Lane i of y into `state`.
template <class T>
RIGID_BODY_LANE_INLINE void storeState(const LaneState<T>& y, std::size_t i, State& state) {
  // Component by component: Eigen's temporaries and comma initialiser cost a lone step ~15 instructions more.
  state.t = laneValue(y.t, i);
  state.p_WB.x() = laneValue(y.p.x, i);
  state.p_WB.y() = laneValue(y.p.y, i);
  state.p_WB.z() = laneValue(y.p.z, i);
  state.P_W.x() = laneValue(y.P.x, i);
  state.P_W.y() = laneValue(y.P.y, i);
  state.P_W.z() = laneValue(y.P.z, i);
  state.L_W.x() = laneValue(y.L.x, i);
  state.L_W.y() = laneValue(y.L.y, i);
  state.L_W.z() = laneValue(y.L.z, i);
  state.q_WB.x() = laneValue(y.qx, i);
  state.q_WB.y() = laneValue(y.qy, i);
  state.q_WB.z() = laneValue(y.qz, i);
  state.q_WB.w() = laneValue(y.qw, i);
}

}  // namespace integrators
}  // namespace rigid_body

