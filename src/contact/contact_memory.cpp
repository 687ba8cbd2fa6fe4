// What a contact carries from one step to the next (docs/contact.md, steps 5 and 6): a solver contact made
// from a detected point with the impulses of the point it matches from the last step (warm starting) and
// the anchors of a sticking point, and, after the solve, the points remembered for the next step and the
// contact reports.
#include "contact_step.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <tuple>

namespace rigid_body {
namespace contact {

namespace {

// A point found this close to where a point of the same pair was last step (on the body) inherits its
// impulses as the solver's first guess [m].
constexpr double kWarmStartMatch = 2e-3;
// A contact sticks (and keeps its anchors) only if its slip in the solve's last sweep would move it by less
// than this fraction of the penetration slop in the step: a sliding box's corner can end a solve with its
// friction impulse inside the disc, and anchored it would be held back (its stop distance 10 % short).
constexpr double kStickingSlip = 0.1;
// A point starts to stick only with its friction impulse within this fraction of the disc's radius μ fₙ: a
// block starting to slide from rest has a slow slip for its first steps, and the corners an unconverged solve
// leaves just inside the disc were anchored (its travel down an incline 4.7e-4 short at h = 0.25 ms with 5
// sweeps, against 1.4e-5).
constexpr double kStartingFriction = 0.5;

}  // namespace

void ContactStep::addContact(const ContactPoint& point, const SceneBodies& bodies) {
  SolverContact c;
  c.a = solverIndex(bodies, point.a);
  c.b = solverIndex(bodies, point.b);
  restoreWokenPairs();  // solverIndex may have woken a sleeping body
  std::pair<Eigen::Vector3d, Eigen::Vector3d> anchors;
  PairLookup lookup;
  makeContact(point, bodies, false, 0.0, lookup, c, anchors, nullptr);
  solver_contacts_.push_back(c);
  solver_points_.push_back(&point);
  solver_anchors_.push_back(anchors);
}

void ContactStep::makeContact(const ContactPoint& point, const SceneBodies& bodies, bool touching, double h,
                              PairLookup& lookup, SolverContact& c,
                              std::pair<Eigen::Vector3d, Eigen::Vector3d>& anchors, Eigen::Vector3d* local) const {
  const std::size_t a = c.a, b = c.b;
  // Default-initialised in place: its members' own initialisers. `c = SolverContact()` zeroed a whole
  // temporary (the products prepareContactRows writes too) and copied it over.
  c.~SolverContact();
  ::new (static_cast<void*>(&c)) SolverContact;
  c.a = a, c.b = b;
  if (c.a != kEnvironment) c.r_a = point.on_a - bodies.states[colliders_[point.a]].p_WB;
  if (c.b != kEnvironment) c.r_b = point.on_b - bodies.states[colliders_[point.b]].p_WB;
  c.n = point.normal;
  // The basis is a function of the normal's bits: a face's points, which share them, share it.
  if (std::memcmp(c.n.data(), lookup.basis_normal.data(), sizeof(double) * 3) != 0) {
    CollisionWorld::tangentBasis(c.n, lookup.basis_t1, lookup.basis_t2);
    lookup.basis_normal = c.n;
  }
  c.t1 = lookup.basis_t1, c.t2 = lookup.basis_t2;
  c.separation = point.distance;
  const ContactMaterial material = combined(point.a, point.b);
  c.friction = material.friction;
  // A pair that was already touching rests or slides: it does not bounce again. A speculative point is not
  // touching: its impulse stops an arrival, so the step does not move its body on by c h Δv (solver_islands).
  c.sustained = touching && !point.speculative;
  c.restitution = c.sustained ? 0.0 : material.restitution;
  // Where the point sits on its body (a half-space pair's matches by its feature instead): the warm start's
  // match now, the warm point's place for the next step.
  if (local != nullptr) *local = point.feature >= 0 ? Eigen::Vector3d::Zero() : localPoint(point, bodies);
  const WarmPoint* last = touching && local != nullptr ? warmStart(c, point, *local, h, lookup) : nullptr;
  // A point that stuck last step keeps the anchors where it began to stick, unless one of them has left the
  // point by more than the warm-start match.
  anchors = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (last == nullptr || !last->anchored || point.speculative) return;
  const bool lower_a = point.a < point.b;
  const Eigen::Vector3d& on_a = lower_a ? last->anchor_lo : last->anchor_hi;
  const Eigen::Vector3d& on_b = lower_a ? last->anchor_hi : last->anchor_lo;
  const Eigen::Vector3d A = inWorld(point.a, on_a, bodies), B = inWorld(point.b, on_b, bodies);
  if ((A - point.on_a).squaredNorm() < kWarmStartMatch * kWarmStartMatch &&
      (B - point.on_b).squaredNorm() < kWarmStartMatch * kWarmStartMatch) {
    c.anchored = true;
    c.anchor_gap = Eigen::Vector2d(c.t1.dot(A - B), c.t2.dot(A - B));
    anchors = {on_a, on_b};
  }
}

Eigen::Vector3d ContactStep::inObjectFrame(std::size_t object, const Eigen::Vector3d& p_W,
                                           const SceneBodies& bodies) const {
  if (!world_->isBody(object)) return p_W;
  const State& state = bodies.states[colliders_[object]];
  return state.q_WB.conjugate() * (p_W - state.p_WB);
}

Eigen::Vector3d ContactStep::inWorld(std::size_t object, const Eigen::Vector3d& local, const SceneBodies& bodies) const {
  if (!world_->isBody(object)) return local;
  const State& state = bodies.states[colliders_[object]];
  return state.p_WB + state.q_WB * local;
}

Eigen::Vector3d ContactStep::localPoint(const ContactPoint& point, const SceneBodies& bodies) const {
  return world_->isBody(point.a) ? inObjectFrame(point.a, point.on_a, bodies) : inObjectFrame(point.b, point.on_b, bodies);
}

const ContactStep::WarmPoint* ContactStep::warmStart(SolverContact& c, const ContactPoint& point,
                                                     const Eigen::Vector3d& local, double h,
                                                     PairLookup& lookup) const {
  const std::uint64_t key = pairKey(point.a, point.b);
  if (key != lookup.warm_key) {
    // The pairs come mostly in last step's order: a pair's run often begins where the one looked up before
    // it ended (a run's first entry: the one before it is another pair's). Else the index's hash table.
    std::size_t begin = lookup.warm_end, end = begin;
    while (end < warm_.size() && warm_[end].key == key) ++end;
    if (end == begin || (begin > 0 && warm_[begin - 1].key == key)) std::tie(begin, end) = warm_runs_.find(key);
    lookup.warm_key = key;
    lookup.warm_begin = begin;
    lookup.warm_end = end;
  }
  const auto range = std::make_pair(warm_.begin() + static_cast<std::ptrdiff_t>(lookup.warm_begin),
                                    warm_.begin() + static_cast<std::ptrdiff_t>(lookup.warm_end));
  if (range.first == range.second) return nullptr;
  const WarmPoint* best = nullptr;
  if (point.feature >= 0) {  // a half-space contact: the same corner of the same body
    for (auto it = range.first; it != range.second && best == nullptr; ++it) {
      if (it->feature == point.feature) best = &*it;
    }
  } else {
    double best_squared = kWarmStartMatch * kWarmStartMatch;
    for (auto it = range.first; it != range.second; ++it) {
      const double squared = (it->local - local).squaredNorm();
      if (squared < best_squared) best = &*it, best_squared = squared;
    }
  }
  if (best == nullptr) return nullptr;
  // The impulses stood for a force over last step's h: a step of another length (one of a step split for a
  // fast body, docs/contact.md "No tunnelling") starts from that force, h / h_last of them (Box2D's dtRatio).
  // Taken whole into a shorter step, an unconverged solve (a heavy body on a light one) kept the excess, and
  // the force that pushed the bodies apart had done more work than it could.
  const double scale = best->step == h ? 1.0 : h / best->step;
  // The pair's order may differ from last step's: impulses are stored as acting on the pair's lower object.
  const double friction_scale = point.a < point.b ? scale : -scale;
  c.normal_impulse = scale * best->normal_impulse;
  c.friction_impulse =
      friction_scale * Eigen::Vector2d(c.t1.dot(best->friction_impulse_W), c.t2.dot(best->friction_impulse_W));
  return best;
}

ContactStep::WarmPoint ContactStep::warmPointOf(std::size_t i, const SceneBodies& bodies, double h) const {
  const SolverContact& c = solver_contacts_[i];
  const ContactPoint& point = *solver_points_[i];
  const Eigen::Vector3d friction = c.friction_impulse.x() * c.t1 + c.friction_impulse.y() * c.t2;
  // Anchored next step (docs/contact.md, step 6), only after a solve that did not converge and only for a
  // point that does not slide (its slip in the solve's last sweep moves it by less than kStickingSlip of
  // the slop in the step). One that was anchored keeps its anchors while its friction stays inside the disc
  // (or it is not pressed for a step); one that starts to stick (pressed, its friction within
  // kStartingFriction of the disc's radius) anchors where it is now, on each body as the body now stands
  // (the anchors then coincide in the tangent plane). Never on a curved surface: a rolling body's contact
  // point moves over its surface while its material points do not slip, and anchors left behind would hold
  // it back (a sphere rolling down an incline lost 1.5e-6 of its distance in 1 s at h = 0.25 ms).
  const double slip_limit = kStickingSlip * settings_.penetration_slop / h;
  const bool slow = c.slip_squared < slip_limit * slip_limit;
  const double limit = c.friction * c.normal_impulse, f2 = c.friction_impulse.squaredNorm();
  const bool starts = !c.anchored && !point.speculative && !curved_[point.a] && !curved_[point.b] &&
                      c.normal_impulse > 0.0 && f2 < kStartingFriction * kStartingFriction * limit * limit;
  const bool keeps = c.anchored && (c.normal_impulse == 0.0 || f2 < limit * limit);
  const bool sticking = !islands_.converged(i) && slow && (starts || keeps);
  std::pair<Eigen::Vector3d, Eigen::Vector3d> anchors = solver_anchors_[i];
  if (sticking && starts) {
    anchors = {inObjectFrame(point.a, point.on_a, bodies), inObjectFrame(point.b, point.on_b, bodies)};
  }
  // Only a sustained contact's impulses stand for a force that goes on: an arrival's (a landing, a speculative
  // point's stop) are mostly the momentum it stopped. Repeated next step, that impact pushed the bodies apart
  // again, and where the solve cannot take it back within its sweeps (a heavy body landing on a light one:
  // each sweep changes the impulse by the light body's share only) the bodies gained the impact's energy.
  const double carried = c.sustained ? 1.0 : 0.0;
  const bool lower_a = point.a < point.b;
  return {pairKey(point.a, point.b), point.feature, sticking, solver_local_[i], carried * c.normal_impulse,
          (lower_a ? carried : -carried) * friction, lower_a ? anchors.first : anchors.second,
          lower_a ? anchors.second : anchors.first, h};
}

void ContactStep::reportContact(std::size_t i) {
  const SolverContact& c = solver_contacts_[i];
  const ContactPoint& point = *solver_points_[i];
  if (point.speculative) return;  // a report lists what touches
  const Eigen::Vector3d friction = c.friction_impulse.x() * c.t1 + c.friction_impulse.y() * c.t2;
  const double depth = std::max(0.0, -point.distance);
  if (world_->isBody(point.a)) {
    contacts_[point.a].push_back({partner(point.b), point.on_a, c.n, depth, c.normal_impulse, friction});
  }
  if (world_->isBody(point.b)) {
    contacts_[point.b].push_back({partner(point.a), point.on_b, -c.n, depth, c.normal_impulse, -friction});
  }
}

void ContactStep::rememberContacts() {
  if (recording_) {
    for (std::size_t i = 0; i < solver_contacts_.size(); ++i) reportContact(i);
  }
  warm_.swap(warm_next_);  // a sleeping island's are set aside (asleep_warm_)
  indexWarmPoints();
}

void ContactStep::indexWarmPoints() {
  // Each pair's points follow each other as the solve made them (a pair's points are consecutive in the
  // detection and in its island), so they are indexed where they lie. Should a pair's points ever not be
  // consecutive, they are sorted by pair first, each pair's in their order (as (key, position) pairs and
  // gathered: a warm point is 16 doubles): the lookups find the same points in the same order either way.
  const auto keyOf = [&](std::size_t i) { return warm_[i].key; };
  if (warm_runs_.build(warm_.size(), keyOf)) return;
  warm_order_.clear();
  for (std::size_t i = 0; i < warm_.size(); ++i) warm_order_.emplace_back(warm_[i].key, i);
  std::sort(warm_order_.begin(), warm_order_.end());
  warm_next_.clear();
  for (const auto& [key, i] : warm_order_) warm_next_.push_back(warm_[i]);
  warm_.swap(warm_next_);
  warm_runs_.build(warm_.size(), keyOf);
}

}  // namespace contact
}  // namespace rigid_body
