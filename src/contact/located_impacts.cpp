// Impacts located in time within a step (docs/contact.md, steps 3 and 4): the candidates, the root of a pair's
// distance along the integrated path, and the impact law applied there, to the pair alone or, where its bodies
// touch others, to the chain of touching contacts in the order the impulse travels.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact_step.hpp"

namespace rigid_body {
namespace contact {

namespace {

// The least reach of a located impact's patch beyond its deepest point [m] (the slop, where it is larger).
constexpr double kImpactPointTolerance = 1e-6;
// How much faster than any of its points moved before the impact a point of the pair may close after it: a
// body struck at one end turns about it, and its far side swings down (a uniform rod: as fast as its centre
// fell; a margin for the rest).
constexpr double kArrivalSpeedMargin = 2.0;
// The farthest apart a pair's distance is evaluated while an impact is located [m].
constexpr double kDistanceRange = 1e3;
// The root finder's most evaluations (regula falsi, Illinois variant: superlinear, bracketed).
constexpr int kMaxRootIterations = 80;
// What distanceAfter answers when the partial step fails.
constexpr double kNoDistance = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void ContactStep::findCandidates(SceneBodies& bodies, const std::vector<char>& running, double h) {
  candidates_.clear();
  engaged_.clear();
  body_points_indexed_ = false;
  std::fill(engagement_.begin(), engagement_.end(), 0);
  std::fill(reserved_.begin(), reserved_.end(), 0);
  // A body that moves far in the step is tested along its whole path against everything near it (the
  // continuous test); its impacts come first, and a body takes part in one located impact a step.
  if (settings_.continuous) findFastImpacts(bodies, running, h);
  for (const Candidate& c : candidates_) {
    for (std::size_t object : {c.a, c.b}) {
      if (world_->isBody(object)) engagement_[object] = 2;
    }
  }
  const std::size_t fast_impacts = candidates_.size();
  PairLookup lookup;
  for (const ContactPoint& point : points_) {
    const std::uint64_t key = pairKey(point.a, point.b);
    const bool touching = wasTouching(key, lookup);
    if (point.distance > (touching ? settings_.penetration_slop : 0.0)) continue;
    // A pair's points come together (one manifold per pair, one pass per body and half-space).
    if (!engaged_.empty() && engaged_.back() == key) continue;
    engaged_.push_back(key);
    if (touching) continue;  // resting or sliding since the last step: the solver's (or part of a chain)
    if (world_->isBody(point.a)) ++engagement_[point.a];
    if (world_->isBody(point.b)) ++engagement_[point.b];
    if (settings_.event_location) candidates_.push_back({point.a, point.b, 0.0, h, 0.0, 0.0, false});
  }
  // Only an impact alone on its bodies among the new contacts is located: several at once are the solver's.
  // (Contacts that were touching already may take part, as the chain the impact travels through.)
  candidates_.erase(std::remove_if(candidates_.begin() + static_cast<std::ptrdiff_t>(fast_impacts), candidates_.end(),
                                   [&](const Candidate& c) {
                                     return (world_->isBody(c.a) && engagement_[c.a] != 1) ||
                                            (world_->isBody(c.b) && engagement_[c.b] != 1);
                                   }),
                    candidates_.end());
  for (const Candidate& c : candidates_) {
    for (std::size_t object : {c.a, c.b}) {
      if (world_->isBody(object)) reserved_[object] = 1;
    }
  }
}

double ContactStep::distanceAfter(SceneBodies& bodies, std::size_t a, std::size_t b, double tau, bool keep_states,
                                  State* at) {
  for (std::size_t side = 0; side < 2; ++side) {
    const std::size_t object = side == 0 ? a : b;
    if (!world_->isBody(object)) continue;
    const std::size_t body = colliders_[object];
    State state = start_[object];
    if (tau > 0.0) {
      Integrator integrator = bodies.integrators[body];
      const StepStatus status = integrator.step(bodies.models[body], bodies.terms[body], bodies.inputs[body], tau, state);
      // A partial step the integrator cannot take leaves the impact to the solver at the step's end.
      if (status != StepStatus::kOk || !(state.p_WB.norm() <= kContactRange)) return kNoDistance;
    }
    world_->setPose(object, state.p_WB, state.q_WB);
    if (keep_states) bodies.states[body] = state;
    if (at != nullptr) at[side] = state;
  }
  return world_->pairDistance(a, b, kDistanceRange, nullptr);
}

bool ContactStep::resolveImpact(SceneBodies& bodies, Candidate c, double h) {
  if (!c.swept) {
    // Bracket the first touch: apart at the start, touching at the end.
    c.f_lo = distanceAfter(bodies, c.a, c.b, c.lo, false);
    if (!(c.f_lo > 0.0) || std::isnan(c.f_lo)) return false;  // already touching at the start: the solver's
    c.f_hi = distanceAfter(bodies, c.a, c.b, c.hi, false);
    if (!(c.f_hi <= 0.0)) return restoreAfterFailedLocation(bodies, c);
  }
  double lo = c.lo, hi = c.hi, f_lo = c.f_lo, f_hi = c.f_hi;
  // Regula falsi, Illinois variant: keeps the bracket, converges superlinearly on a smooth distance. A swept
  // impact's bracket may already end within reach (conservative advancement stops short of the touch).
  int side = 0;
  for (int i = 0; i < kMaxRootIterations && f_hi < 0.0 && hi - lo > settings_.event_tolerance; ++i) {
    double tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    if (!(tau > lo && tau < hi)) tau = 0.5 * (lo + hi);
    const double f = distanceAfter(bodies, c.a, c.b, tau, false);
    if (std::isnan(f)) return restoreAfterFailedLocation(bodies, c);
    if (f > 0.0) {
      lo = tau, f_lo = f;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    } else {
      hi = tau, f_hi = f;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
  }
  // At the touch (the bracket's touching end): the points of first contact and the impact.
  State at[2];
  distanceAfter(bodies, c.a, c.b, hi, true, at);
  // The patch that meets: every point within the slop of the deepest (a face landing on a face meets at all
  // its corners at once; the narrow phase's perturbed points of a face lie up to ~1e-5 m apart in distance).
  // Beyond it, the points that may arrive within the rest of the step (arrival: how far a point can close in
  // it): the rest of a face landing almost flat, whose first corner is the impact.
  const double patch = std::max(kImpactPointTolerance, settings_.penetration_slop);
  const double rest = h - hi;
  const double arrival = kArrivalSpeedMargin * rest *
                         (closingSpeedBound(bodies, c.a, at[0]) + closingSpeedBound(bodies, c.b, at[1]));
  const double deepest = world_->pairDistance(c.a, c.b, std::max(0.0, f_hi) + patch + arrival, &pair_points_);
  solver_contacts_.clear();
  solver_points_.clear();
  solver_anchors_.clear();
  startSolverLists();
  for (const ContactPoint& point : pair_points_) {
    if (point.distance <= deepest + patch) addContact(point, bodies);
  }
  chain_groups_.assign(1, {0, solver_contacts_.size()});
  if (!solver_contacts_.empty()) gatherChain(bodies, c, hi);
  // With restitution the chain's impacts follow each other (solveChain); without, every touching point of
  // the chain is stopped at once, the arrivals kept from passing the surface with them.
  const bool sequential = chain_groups_.size() > 1 && combined(c.a, c.b).restitution > 0.0;
  const std::size_t first_arrival = solver_contacts_.size();
  if (!sequential && first_arrival > 0 && rest > 0.0) {
    for (const ContactPoint& point : pair_points_) {
      if (point.distance > deepest + patch) addContact(point, bodies);
    }
  }
  if (solver_contacts_.empty()) {  // nothing within reach after all: the rest of the step is free motion
    for (std::size_t object : {c.a, c.b}) {
      if (!world_->isBody(object)) continue;
      const std::size_t body = colliders_[object];
      bodies.integrators[body].step(bodies.models[body], bodies.terms[body], bodies.inputs[body], h - hi,
                                    bodies.states[body]);
    }
    return true;
  }
  applyImpact(bodies, c, hi, h, sequential, first_arrival);
  return true;
}

void ContactStep::applyImpact(SceneBodies& bodies, const Candidate& c, double tau, double h, bool sequential,
                              std::size_t first_arrival) {
  SolveOptions options;
  options.iterations = settings_.iterations;
  options.restitution_threshold = settings_.restitution_threshold;
  const double approach = -solver_contacts_.front().n.dot(relativeVelocity(solver_contacts_.front(), solver_bodies_));
  if (!sequential) {
    prepareContacts(solver_contacts_, solver_bodies_, options);
    // A point still apart by d may close it within the rest of the step, and no faster (a speculative
    // point's target, kept through both phases of the impact): the rest of the face then reaches the surface
    // by the step's end instead of passing it by up to a step's travel.
    for (std::size_t k = first_arrival; k < solver_contacts_.size(); ++k) {
      solver_contacts_[k].target_speed = -solver_contacts_[k].separation / (h - tau);
    }
    solveImpact(solver_contacts_, solver_bodies_, options);
  } else {
    solveChain(options);
  }
  // Momenta change by the impulses; the rest of the step is free motion again.
  for (std::size_t s = 1; s < solver_bodies_.size(); ++s) {  // 0 is the environment
    const std::size_t k = solver_body_of_[s], body = colliders_[k];
    State& state = bodies.states[body];
    state.P_W += solver_bodies_[s].dP;
    state.L_W += solver_bodies_[s].dL;
    bodies.integrators[body].step(bodies.models[body], bodies.terms[body], bodies.inputs[body], h - tau, state);
    solver_of_[k] = kUnassigned;
    reserved_[k] = 1;
  }
  ++(c.swept ? statistics_.swept_impacts : statistics_.located_impacts);
  if (impacts_.size() == kImpactLog) impacts_.erase(impacts_.begin());
  const std::size_t body_object = world_->isBody(c.a) ? c.a : c.b;
  impacts_.push_back({start_[body_object].t + tau, colliders_[body_object], partner(body_object == c.a ? c.b : c.a),
                      approach});
}

bool ContactStep::restoreAfterFailedLocation(SceneBodies& bodies, const Candidate& c) {
  // The pair's objects go back to the end-of-step poses the detection saw.
  for (std::size_t object : {c.a, c.b}) {
    if (!world_->isBody(object)) continue;
    const State& state = bodies.states[colliders_[object]];
    world_->setPose(object, state.p_WB, state.q_WB);
  }
  return false;
}

void ContactStep::gatherChain(SceneBodies& bodies, const Candidate& c, double tau) {
  // Breadth first from the pair's bodies through the pairs that were touching: each body reached is taken to
  // the impact's time along its own path, and its touching pairs' points there join the impact, a group each.
  chain_.clear();
  chain_pairs_.assign(1, pairKey(c.a, c.b));
  for (std::size_t object : {c.a, c.b}) {
    if (world_->isBody(object)) chain_.push_back(object);
  }
  if (!body_points_indexed_) indexPointsByBody();
  for (std::size_t next = 0; next < chain_.size() && chain_.size() < kMaxChainBodies; ++next) {
    const std::size_t body = chain_[next];
    for (std::size_t n = body_point_start_[body]; n < body_point_start_[body + 1]; ++n) {
      const std::size_t i = body_point_index_[n];
      const ContactPoint& point = points_[i];
      if (i > 0 && pairKey(points_[i - 1].a, points_[i - 1].b) == pairKey(point.a, point.b)) continue;
      const std::size_t other = point.a == body ? point.b : point.a;
      const std::uint64_t key = pairKey(point.a, point.b);
      if (!wasTouching(key) || std::find(chain_pairs_.begin(), chain_pairs_.end(), key) != chain_pairs_.end()) continue;
      const bool other_is_body = world_->isBody(other);
      if (other_is_body && std::find(chain_.begin(), chain_.end(), other) == chain_.end()) {
        if (reserved_[other] || outside_[other] || chain_.size() >= kMaxChainBodies) continue;
        State state = start_[other];
        Integrator integrator = bodies.integrators[colliders_[other]];
        if (integrator.step(bodies.models[colliders_[other]], bodies.terms[colliders_[other]],
                            bodies.inputs[colliders_[other]], tau, state) != StepStatus::kOk) {
          continue;
        }
        bodies.states[colliders_[other]] = state;
        world_->setPose(other, state.p_WB, state.q_WB);
        reserved_[other] = 1;
        chain_.push_back(other);
      }
      chain_pairs_.push_back(key);
      world_->pairDistance(body, other, settings_.penetration_slop, &chain_points_);
      const std::size_t begin = solver_contacts_.size();
      for (const ContactPoint& touching : chain_points_) addContact(touching, bodies);
      if (solver_contacts_.size() > begin) chain_groups_.push_back({begin, solver_contacts_.size()});
    }
  }
}

double ContactStep::fastestApproach(std::size_t& group) const {
  double approach = 0.0;
  for (std::size_t g = 0; g < chain_groups_.size(); ++g) {
    for (std::size_t i = chain_groups_[g].first; i < chain_groups_[g].second; ++i) {
      const double speed = -solver_contacts_[i].n.dot(relativeVelocity(solver_contacts_[i], solver_bodies_));
      if (speed > approach) approach = speed, group = g;
    }
  }
  return approach;
}

void ContactStep::indexPointsByBody() {
  // Counting sort of the points' indices by each body they touch (an environment object is no body).
  const std::size_t n = colliders_.size();
  body_point_start_.assign(n + 2, 0);
  for (const ContactPoint& point : points_) {
    for (std::size_t object : {point.a, point.b}) {
      if (world_->isBody(object)) ++body_point_start_[object + 2];
    }
  }
  for (std::size_t k = 2; k < n + 2; ++k) body_point_start_[k] += body_point_start_[k - 1];
  body_point_index_.resize(body_point_start_[n + 1]);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    for (std::size_t object : {points_[i].a, points_[i].b}) {
      if (world_->isBody(object)) body_point_index_[body_point_start_[object + 1]++] = i;
    }
  }
  body_point_start_.pop_back();  // body k's points are [start[k], start[k + 1])
  body_points_indexed_ = true;
}

void ContactStep::solveChain(const SolveOptions& options) {
  // Sequential impacts (docs/contact.md, "Impacts in chains"): first the impact itself, then, while some pair
  // of the chain approaches faster than the restitution threshold, the pair that approaches fastest, each a
  // whole impact of its own (the impact law above) on the velocities the last one left. Each conserves
  // momentum and gains no energy, so neither does the sequence.
  chain_dP_.assign(solver_bodies_.size(), Eigen::Vector3d::Zero());
  chain_dL_.assign(solver_bodies_.size(), Eigen::Vector3d::Zero());
  const std::size_t most = kMaxChainImpacts * chain_groups_.size();
  const auto addImpulses = [&] {
    for (std::size_t s = 0; s < solver_bodies_.size(); ++s) {
      chain_dP_[s] += solver_bodies_[s].dP;
      chain_dL_[s] += solver_bodies_[s].dL;
    }
  };
  for (std::size_t round = 0; round < most; ++round) {
    std::size_t fastest = 0;
    const double approach = fastestApproach(fastest);
    if (round > 0 && !(approach > options.restitution_threshold)) break;
    if (round == 0) fastest = 0;  // the located pair itself, whatever its speed
    chain_contacts_.assign(solver_contacts_.begin() + static_cast<std::ptrdiff_t>(chain_groups_[fastest].first),
                           solver_contacts_.begin() + static_cast<std::ptrdiff_t>(chain_groups_[fastest].second));
    for (SolverContact& contact : chain_contacts_) contact.normal_impulse = 0.0, contact.friction_impulse.setZero();
    prepareContacts(chain_contacts_, solver_bodies_, options);
    solveImpact(chain_contacts_, solver_bodies_, options);
    addImpulses();
  }
  // Rounds spent with pairs still approaching (a heavy body on a light one on the ground: each round moves
  // the light body's share of the momentum, 10⁴ of them for a mass ratio of 10⁴): the rest of the impact is
  // the whole chain's at once (the impact law over all its points, each its own restitution), so that no
  // pair goes on approaching into the rest of the step.
  std::size_t fastest = 0;
  if (fastestApproach(fastest) > options.restitution_threshold) {
    for (SolverContact& contact : solver_contacts_) contact.normal_impulse = 0.0, contact.friction_impulse.setZero();
    prepareContacts(solver_contacts_, solver_bodies_, options);
    solveImpact(solver_contacts_, solver_bodies_, options);
    addImpulses();
  }
  for (std::size_t s = 0; s < solver_bodies_.size(); ++s) {
    solver_bodies_[s].dP = chain_dP_[s];
    solver_bodies_[s].dL = chain_dL_[s];
  }
}

}  // namespace contact
}  // namespace rigid_body
