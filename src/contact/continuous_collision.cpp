// The continuous test of the contact step (docs/contact.md, "No tunnelling"): a body that moves far in a step
// is advanced conservatively along the path its integrator takes, against every object whose bounding box
// meets the box its step sweeps, so that it cannot pass through anything, however thin.
//
// Conservative advancement (Mirtich, "Impulse-based Dynamic Simulation of Rigid Body Systems", 1996):
// if no two points of a pair close faster than u over [τ, h], a pair apart by d at τ cannot touch before
// τ + d/u. Each advance is taken along the integrated path itself (the integrator's step of τ from the step's
// start, as the located impacts use), not along a straight chord of it, so a curved path under gravity or a
// wrench is followed as it is. The speeds are bounded from the states at τ and at the step's end: no point of
// a body moves faster than |v| + |ω| R (R its outer radius about the centre of mass), |v| is at most the
// larger of its ends plus half their difference (exact for a constant force, whose v is linear in time) and
// |ω| ≤ |L| / I_min, with a quarter more for what varies within the step.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact_step.hpp"

#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

namespace {

// A body sweeps its motion when a point of it moves farther than this fraction of its inner radius in a step:
// below it the body's start and end overlap, so nothing thick enough to hold a contact fits between them.
constexpr double kSweepFraction = 0.5;
// Conservative advancement stops this close to a touch [m]: the located impact's own point tolerance.
constexpr double kTouchDistance = 1e-6;
// Advances per pair and step; a pair still apart after them is resolved where it stands (no impulse unless
// it approaches), which never lets it pass.
constexpr int kMaxAdvances = 200;
// The speed bound's margin for what varies within a step (a force turning with the body, damping).
constexpr double kSpeedMargin = 1.25;

// The rotation angle between two orientations [rad].
double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2.0 * std::asin(std::min(1.0, (a.conjugate() * b).vec().norm()));
}

}  // namespace

double ContactStep::reachBound(const SceneBodies& bodies, std::size_t k, double h) const {
  // How far a point of the body can move over h from its present motion and the forces it is under: |v| grows
  // by at most |F|/M + |g| per second, |L| by at most |τ| (the input's, about the centre of mass), and a point
  // moves at |v| + |ω| R with |ω| ≤ |L| / I_min. Damping only slows the body.
  const std::size_t body = colliders_[k];
  const State& state = bodies.states[body];
  const MassProperties& mass = bodies.models[body].mass;
  const AppliedWrench& input = bodies.inputs[body];
  const double acceleration = (input.world.force.norm() + input.body.force.norm()) * mass.inverseMass() +
                              bodies.models[body].forces.gravity_W.norm();
  const double torque = input.world.torque.norm() + input.body.torque.norm();
  const double v = state.P_W.norm() * mass.inverseMass() + 0.5 * acceleration * h;
  const double w = (state.L_W.norm() + 0.5 * torque * h) * mass.inversePrincipalMoments().maxCoeff();
  return kSpeedMargin * (v + w * outer_radius_[k]) * h;
}

bool ContactStep::needsShorterStep(const SceneBodies& bodies, const std::vector<char>& running, double h) {
  const std::size_t n = colliders_.size();
  // Each body's reach over the pool, each block's farthest kept apart (their largest is the same whatever
  // the blocks).
  const std::size_t per_block = scaledBlock(bodies_per_block_, kBoundBlocks);
  block_farthest_.assign(blockCount(n, per_block), 0.0);
  forEachRange(pool_, n, per_block, [&](std::size_t block, std::size_t first, std::size_t end) {
    for (std::size_t k = first; k < end; ++k) {
      fast_[k] = 0;
      const State& state = bodies.states[colliders_[k]];
      if (!running[k] || outside_[k] || !isFinite(state)) continue;
      const double reach = reachBound(bodies, k, h);
      block_farthest_[block] = std::max(block_farthest_[block], reach);
      fast_[k] = reach > kSweepFraction * inner_radius_[k];
    }
  });
  double farthest = 0.0;
  for (const double block : block_farthest_) farthest = std::max(farthest, block);
  for (std::size_t k = 0; k < n; ++k) {
    if (!fast_[k]) continue;
    const Eigen::Vector3d& p = bodies.states[colliders_[k]].p_WB;
    const Eigen::Vector3d reach = Eigen::Vector3d::Constant(outer_radius_[k] + 2.0 * farthest);
    world_->objectsNear(k, p - reach, p + reach, near_);
    if (!near_.empty()) return true;
  }
  return false;
}

bool ContactStep::movesFast(std::size_t k, const State& after) const {
  const State& before = start_[k];
  const double limit = kSweepFraction * inner_radius_[k];
  const double moved = (after.p_WB - before.p_WB).norm();
  if (moved > limit) return true;
  // The turn's reach from |q_v| alone first (2 asin x ≤ π x): the arcsine only where that bound is in doubt.
  const double x = (before.q_WB.conjugate() * after.q_WB).vec().norm();
  if (moved + 3.14159265358979323846 * x * outer_radius_[k] <= limit) return false;
  return moved + angleBetween(before.q_WB, after.q_WB) * outer_radius_[k] > limit;
}

void ContactStep::sweptBox(const SceneBodies& bodies, std::size_t k, double h, Eigen::Vector3d& low,
                           Eigen::Vector3d& high) const {
  const State& before = start_[k];
  const State& after = bodies.states[colliders_[k]];
  const double inverse_mass = bodies.models[colliders_[k]].mass.inverseMass();
  // The path leaves the chord between its ends by at most a h²/8 for a constant acceleration a; |Δv| h / 4
  // doubles that. The outer radius covers any orientation.
  const double reach = outer_radius_[k] + 0.25 * (after.P_W - before.P_W).norm() * inverse_mass * h;
  low = before.p_WB.cwiseMin(after.p_WB) - Eigen::Vector3d::Constant(reach);
  high = before.p_WB.cwiseMax(after.p_WB) + Eigen::Vector3d::Constant(reach);
}

double ContactStep::closingSpeedBound(const SceneBodies& bodies, std::size_t object, const State& at) const {
  if (!world_->isBody(object)) return 0.0;
  const State& end = bodies.states[colliders_[object]];
  const MassProperties& mass = bodies.models[colliders_[object]].mass;
  const double inverse_mass = mass.inverseMass();
  const double v = std::max(at.P_W.norm(), end.P_W.norm()) * inverse_mass + 0.5 * (end.P_W - at.P_W).norm() * inverse_mass;
  const double w = std::max(at.L_W.norm(), end.L_W.norm()) * mass.inversePrincipalMoments().maxCoeff();
  return kSpeedMargin * (v + w * outer_radius_[object]);
}

void ContactStep::findFastImpacts(SceneBodies& bodies, const std::vector<char>& running, double h) {
  const std::size_t n = colliders_.size();
  bool any = false;
  for (std::size_t k = 0; k < n; ++k) {
    fast_[k] = running[k] && !outside_[k] && movesFast(k, bodies.states[colliders_[k]]);
    any = any || fast_[k];
  }
  if (!any) return;
  double farthest = 0.0;  // the largest reach of any body's step beyond its end box
  for (std::size_t k = 0; k < n; ++k) {
    sweptBox(bodies, k, h, swept_low_[k], swept_high_[k]);
    if (running[k] && !outside_[k]) farthest = std::max(farthest, (swept_high_[k] - swept_low_[k]).maxCoeff());
  }
  std::vector<char> used(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    if (!fast_[k]) continue;
    // Other bodies move too: their boxes as of the last detection are within `farthest` of what they sweep.
    world_->objectsNear(k, swept_low_[k] - Eigen::Vector3d::Constant(farthest),
                        swept_high_[k] + Eigen::Vector3d::Constant(farthest), near_);
    Candidate first{k, k, 0.0, h, 0.0, 0.0, true};
    bool found = false;
    for (std::size_t object : near_) {
      if (world_->isBody(object)) {
        if (outside_[object] || (fast_[object] && object < k)) continue;  // a fast pair is tested once
        const bool apart = (swept_low_[k].array() > swept_high_[object].array()).any() ||
                           (swept_low_[object].array() > swept_high_[k].array()).any();
        if (apart) continue;
      }
      if (wasTouching(pairKey(k, object))) continue;  // in contact since the last step: the solver's
      Candidate hit{k, object, 0.0, h, 0.0, 0.0, true};
      if (advanceToImpact(bodies, k, object, found ? first.hi : h, hit) && (!found || hit.hi < first.hi)) {
        first = hit, found = true;
      }
    }
    // Every pose the advancement tried goes back to the step's end.
    for (std::size_t object : near_) {
      if (world_->isBody(object) && !outside_[object]) {
        world_->setPose(object, bodies.states[colliders_[object]].p_WB, bodies.states[colliders_[object]].q_WB);
      }
    }
    world_->setPose(k, bodies.states[colliders_[k]].p_WB, bodies.states[colliders_[k]].q_WB);
    if (!found) continue;
    const bool other_free = !world_->isBody(first.b) || !used[first.b];
    if (used[k] || !other_free) continue;  // one located impact per body and step; the rest are the solver's
    used[k] = 1;
    if (world_->isBody(first.b)) used[first.b] = 1;
    candidates_.push_back(first);
  }
}

bool ContactStep::advanceToImpact(SceneBodies& bodies, std::size_t a, std::size_t b, double until, Candidate& hit) {
  State at[2];
  double tau = 0.0;
  double d = distanceAfter(bodies, a, b, 0.0, false, at);
  if (!(d > 0.0)) return false;  // touching at the start, or no distance: the solver's
  for (int i = 0; i < kMaxAdvances; ++i) {
    const double left = until - tau;
    const double u = closingSpeedBound(bodies, a, at[0]) + closingSpeedBound(bodies, b, at[1]);
    if (!(u > 0.0) || d >= u * left) return false;  // cannot close the gap before `until`
    if (d <= kTouchDistance) break;
    const double next = tau + d / u;
    State next_at[2];
    const double f = distanceAfter(bodies, a, b, next, false, next_at);
    if (std::isnan(f)) return false;
    if (f <= 0.0) {  // the bound did not hold (or rounding): the touch is bracketed
      hit.lo = tau, hit.f_lo = d, hit.hi = next, hit.f_hi = f;
      return true;
    }
    tau = next, d = f, at[0] = next_at[0], at[1] = next_at[1];
  }
  hit.lo = tau, hit.f_lo = d, hit.hi = tau, hit.f_hi = d;
  return true;
}

}  // namespace contact
}  // namespace rigid_body
