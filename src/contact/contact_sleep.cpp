// Sleeping in the contact step (docs/contact.md, "Sleeping"). An island of bodies linked by touching
// contacts sleeps once every body of it has been quiet for the sleep time: no point of it faster than the
// slop per sleep time (so that at that speed it would not have moved by the slop over the whole wait), no
// pair of it at its friction limit (a body that slides or is about to keeps its island awake, however
// slowly it creeps), and at least one contact (a body that floats is exact without sleep and stays awake).
// A sleeping body keeps its pose, at rest, and costs neither a free step, nor a narrow phase, nor a solve.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contact_step.hpp"

namespace rigid_body {
namespace contact {

namespace {

// A pressed pair whose friction impulse reaches this share of the disc's radius μ fₙ counts as at its
// limit: it slides, or the smallest push would make it.
constexpr double kFrictionLimitShare = 0.999;

// Moves the entries of `from` for which `moves` holds to the end of `to`; both keep their order.
template <class Entry, class Predicate>
void moveWhere(std::vector<Entry>& from, std::vector<Entry>& to, Predicate moves) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (moves(from[i])) {
      to.push_back(from[i]);
    } else {
      if (kept != i) from[kept] = from[i];
      ++kept;
    }
  }
  from.resize(kept);
}

}  // namespace

void ContactStep::wake(std::size_t k, std::vector<std::size_t>* woken) {
  if (!sleep_.asleep(k)) return;
  sleep_.wake(k, woken);
  woken_ = true;
  ++statistics_.wakes;
  statistics_.sleeping_bodies = static_cast<std::int64_t>(sleep_.sleepingBodies());
}

void ContactStep::setRecording(bool recording) {
  if (recording && !recording_) {
    for (std::size_t k = 0; k < colliders_.size(); ++k) wake(k);
    syncSleep();
  }
  recording_ = recording;
}

bool ContactStep::sleepingPair(std::uint64_t key) const {
  const std::size_t a = static_cast<std::size_t>(key / materials_.size());
  const std::size_t b = static_cast<std::size_t>(key % materials_.size());
  return (world_->isBody(a) && sleep_.asleep(a)) || (world_->isBody(b) && sleep_.asleep(b));
}

void ContactStep::syncSleep() {
  for (std::size_t k = 0; k < colliders_.size(); ++k) world_->setAsleep(k, sleep_.asleep(k));
  statistics_.sleeping_bodies = static_cast<std::int64_t>(sleep_.sleepingBodies());
}

void ContactStep::wakeReachedIslands(const SceneBodies& bodies, const std::vector<char>& running, double h) {
  // Every awake body's bounding box, widened by how far any point of it can move in the step (reachBound)
  // and by the slop, against the broad phase: a sleeping body it meets wakes with its island, and the
  // woken bodies are checked in turn (they start at rest, but a neighbour may lie within their reach).
  to_check_.clear();
  for (std::size_t k = 0; k < colliders_.size(); ++k) {
    if (running[k] && !sleep_.asleep(k)) to_check_.push_back(k);
  }
  for (std::size_t i = 0; i < to_check_.size(); ++i) {
    const std::size_t k = to_check_[i];
    if (outside_[k] || !isFinite(bodies.states[colliders_[k]])) continue;
    Eigen::Vector3d low, high;
    world_->bounds(k, low, high);
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(reachBound(bodies, k, h) + settings_.penetration_slop);
    world_->objectsNear(k, low - margin, high + margin, near_);
    for (std::size_t object : near_) {
      if (world_->isBody(object)) wake(object, &to_check_);
    }
  }
}

void ContactStep::updateSleep(SceneBodies& bodies, double h) {
  const std::size_t n = colliders_.size();
  const double speed_limit = settings_.penetration_slop / settings_.sleep_time;
  quiet_.assign(n, 0);
  supported_.assign(n, 0);
  links_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (!awake_[k] || outside_[k]) continue;
    const std::size_t body = colliders_[k];
    const MassProperties& mass = bodies.models[body].mass;
    const State& state = bodies.states[body];
    // No point moves faster than |v| + |ω| R, with |ω| ≤ |L| / I_min.
    const double speed = state.P_W.norm() * mass.inverseMass() +
                         state.L_W.norm() * mass.inversePrincipalMoments().maxCoeff() * outer_radius_[k];
    quiet_[k] = speed <= speed_limit;
  }
  // Per pair (its points come together): supported, linked, and whether its friction as a whole is at the
  // limit. Summed, the corners' friction of a box at rest cancels (its corners may hold opposed impulses at
  // their own limits, an indeterminate share of no net force); a sliding pair's sum is μ times its load.
  for (std::size_t first = 0; first < solver_contacts_.size();) {
    const SolverContact& c = solver_contacts_[first];
    std::size_t end = first;
    double load = 0.0;
    Eigen::Vector3d friction = Eigen::Vector3d::Zero();
    for (; end < solver_contacts_.size() && solver_contacts_[end].a == c.a && solver_contacts_[end].b == c.b; ++end) {
      const SolverContact& p = solver_contacts_[end];
      load += p.normal_impulse;
      friction += p.friction_impulse.x() * p.t1 + p.friction_impulse.y() * p.t2;
    }
    first = end;
    const double limit = kFrictionLimitShare * c.friction * load;
    const bool at_limit = load > 0.0 && !(friction.squaredNorm() < limit * limit);
    const std::size_t a = c.a == kEnvironment ? kUnassigned : solver_body_of_[c.a];
    const std::size_t b = c.b == kEnvironment ? kUnassigned : solver_body_of_[c.b];
    for (std::size_t k : {a, b}) {
      if (k == kUnassigned) continue;
      supported_[k] = 1;
      if (at_limit) quiet_[k] = 0;
    }
    if (a != kUnassigned && b != kUnassigned) links_.emplace_back(a, b);
  }
  sleep_.update(links_, quiet_, supported_, h, settings_.sleep_time);
  bool fell_asleep = false;
  for (std::size_t k = 0; k < n; ++k) {
    if (!awake_[k] || !sleep_.asleep(k)) continue;
    // Fallen asleep now: at rest, as it will stay (its pose is what it was).
    State& state = bodies.states[colliders_[k]];
    state.P_W.setZero();
    state.L_W.setZero();
    fell_asleep = true;
  }
  if (fell_asleep) setAsideSleepingPairs();
  syncSleep();
}

void ContactStep::setAsideSleepingPairs() {
  restoreWokenPairs();  // a pair stays in one place or the other
  moveWhere(touching_, asleep_touching_, [&](std::uint64_t key) { return sleepingPair(key); });
  indexTouching();
  moveWhere(warm_, asleep_warm_, [&](const WarmPoint& w) { return sleepingPair(w.key); });
  indexWarmPoints();
}

bool ContactStep::restoreWokenPairs() {
  if (!woken_) return false;
  woken_ = false;
  moveWhere(asleep_touching_, touching_, [&](std::uint64_t key) { return !sleepingPair(key); });
  std::sort(touching_.begin(), touching_.end());
  touching_.erase(std::unique(touching_.begin(), touching_.end()), touching_.end());
  indexTouching();
  moveWhere(asleep_warm_, warm_, [&](const WarmPoint& w) { return !sleepingPair(w.key); });
  indexWarmPoints();
  return true;
}

}  // namespace contact
}  // namespace rigid_body
