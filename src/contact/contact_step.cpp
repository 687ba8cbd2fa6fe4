#include "contact_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/shape_registry.hpp"
#include "rigid_body_sim/thread_pool.hpp"

namespace rigid_body {
namespace contact {

namespace {

// The closing speed a touching pair's speculative points cover [m/s]: a point of a face farther apart than
// the slop, but near enough to arrive within the step at up to this speed, is solved with the rest (it can
// close its gap d at d/h, no faster). A body pivoting about a corner it landed on brings its far side down at
// its fall's speed and more; 20 m/s is a fall of 20 m. Faster arrivals are the continuous test's (step 0).
constexpr double kSpeculativeSpeed = 20.0;
// q turned by the rotation vector rotation_W (world axes).
void rotate(Eigen::Quaterniond& q, const Eigen::Vector3d& rotation_W) {
  const double angle = rotation_W.norm();
  if (angle == 0.0) return;
  q = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_W / angle)) * q).normalized();
}

}  // namespace

ContactStep::ContactStep(const std::vector<CollisionShape>& environment, const ContactSettings& settings,
                         const std::vector<std::optional<CollisionShape>>& body_shapes,
                         const std::vector<std::size_t>& colliders, IntegratorType integrator,
                         const std::vector<State>& states)
    : colliders_(colliders), settings_(settings), integrator_type_(integrator) {
  std::vector<CollisionShape> shapes;
  std::vector<Eigen::Isometry3d> poses;
  for (std::size_t body : colliders) {
    Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
    if (states[body].p_WB.norm() <= kContactRange) {  // else out of the contact world: placeAll keeps it out
      X_WB.linear() = states[body].q_WB.toRotationMatrix();
      X_WB.translation() = states[body].p_WB;
    }
    poses.push_back(X_WB);
    shapes.push_back(*body_shapes[body]);
    materials_.push_back(shapes.back().material);
    curved_.push_back(shapeInfo(shapes.back().type).curved);
    names_.push_back(shapes.back().name.empty() ? "body " + std::to_string(body) : shapes.back().name);
    inner_radius_.push_back(innerRadius(shapes.back()));
    outer_radius_.push_back(outerRadius(shapes.back()));
  }
  for (std::size_t i = 0; i < environment.size(); ++i) {
    materials_.push_back(environment[i].material);
    curved_.push_back(shapeInfo(environment[i].type).curved);
    names_.push_back(environment[i].name.empty() ? "environment shape " + std::to_string(i) : environment[i].name);
  }
  world_ = std::make_unique<CollisionWorld>(environment, shapes, poses);
  world_->setReusePoints(settings_.reuse_points);
  const std::size_t n = colliders.size();
  start_.resize(n);
  engagement_.assign(n, 0);
  solver_of_.assign(n, kUnassigned);
  contacts_.resize(n);
  outside_.assign(n, 0);
  fast_.assign(n, 0);
  reserved_.assign(n, 0);
  swept_low_.resize(n);
  swept_high_.resize(n);
  sleep_.reset(n);
}

std::uint64_t ContactStep::pairKey(std::size_t a, std::size_t b) const {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(a) * materials_.size() + b;
}

bool ContactStep::wasTouching(std::uint64_t key) const {
  const auto [begin, end] = touching_index_.find(key);
  return end > begin;
}

void ContactStep::indexTouching() {
  const auto keyOf = [&](std::size_t i) { return touching_[i]; };
  if (touching_index_.build(touching_.size(), keyOf)) return;
  std::sort(touching_.begin(), touching_.end());  // some pair came twice: each once
  touching_.erase(std::unique(touching_.begin(), touching_.end()), touching_.end());
  touching_index_.build(touching_.size(), keyOf);
}

bool ContactStep::wasTouching(std::uint64_t key, PairLookup& lookup) const {
  if (key != lookup.touching_key) {
    lookup.touching = wasTouching(key);
    lookup.touching_key = key;
  }
  return lookup.touching;
}

ContactPartner ContactStep::partner(std::size_t object) const {
  return world_->isBody(object) ? ContactPartner{true, colliders_[object]}
                                : ContactPartner{false, object - world_->bodyCount()};
}

ContactMaterial ContactStep::combined(std::size_t a, std::size_t b) const {
  return {std::max(materials_[a].restitution, materials_[b].restitution),
          std::sqrt(materials_[a].friction * materials_[b].friction)};
}

void ContactStep::placeRange(const std::vector<State>& states, std::size_t first, std::size_t end) {
  for (std::size_t k = first; k < end; ++k) {
    const State& state = states[colliders_[k]];
    outside_[k] = !(state.p_WB.norm() <= kContactRange) || !state.q_WB.coeffs().allFinite();
    // Outside, its object stays where it last was; its points are dropped (detectPoints).
    if (!outside_[k]) world_->setPose(k, state.p_WB, state.q_WB);
  }
}

void ContactStep::countOutside() {
  statistics_.out_of_range = static_cast<std::int64_t>(std::count(outside_.begin(), outside_.end(), char{1}));
}

void ContactStep::placeAll(const std::vector<State>& states) {
  placeRange(states, 0, colliders_.size());
  countOutside();
}

double ContactStep::speculativeDistance(double h) const {
  return settings_.penetration_slop + kSpeculativeSpeed * h;
}

void ContactStep::detectPoints(const SceneBodies* bodies, double h) {
  // A body whose points may move more than the slop in the next step may bring a touching pair's other
  // points to the surface (docs/contact.md, step 2).
  if (bodies == nullptr) {
    world_->detect(points_, settings_.penetration_slop);
  } else {
    moving_.resize(colliders_.size());
    const std::size_t per_block = scaledBlock(bodies_per_block_, kBoundBlocks);
    forEachRange(pool_, colliders_.size(), per_block, [&](std::size_t, std::size_t first, std::size_t end) {
      for (std::size_t k = first; k < end; ++k) {
        moving_[k] = !sleep_.asleep(k) && reachBound(*bodies, k, h) > settings_.penetration_slop ? 1 : 0;
      }
    });
    world_->detect(points_, settings_.penetration_slop, speculativeDistance(h), &moving_, pool_, bodies_per_block_);
  }
  if (statistics_.out_of_range == 0) return;
  points_.erase(std::remove_if(points_.begin(), points_.end(),
                               [&](const ContactPoint& p) {
                                 return (world_->isBody(p.a) && outside_[p.a]) || (world_->isBody(p.b) && outside_[p.b]);
                               }),
                points_.end());
}

void ContactStep::start(const std::vector<State>& states) {
  placeAll(states);
  // Body by body through the broad phase, stopping at the first conflict: N log N for a scene that starts
  // apart, at once for one that does not (every body at one point).
  for (std::size_t k = 0; k < colliders_.size(); ++k) {
    if (outside_[k]) continue;
    const std::string conflict = placementConflict(k, states[colliders_[k]], states, "starts inside");
    if (!conflict.empty()) throw std::invalid_argument(conflict + ": move one of them apart");
  }
  restart(states);
}

std::string ContactStep::placementConflict(std::size_t k, const State& state, const std::vector<State>& states,
                                           const char* verb) {
  if (!(state.p_WB.norm() <= kContactRange) || !isFinite(state)) return "";  // nothing to meet out there
  world_->setPose(k, state.p_WB, state.q_WB);
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(outer_radius_[k] + settings_.penetration_slop);
  world_->objectsNear(k, state.p_WB - reach, state.p_WB + reach, near_);
  std::string conflict;
  for (std::size_t object : near_) {
    if (world_->isBody(object) && outside_[object]) continue;
    const double distance = world_->pairDistance(k, object, 0.0, nullptr);
    std::ostringstream message;
    if (distance < -settings_.penetration_slop) {
      message << names_[k] << " " << verb << " " << names_[object] << " (penetration " << -distance
              << " m, more than the slop of " << settings_.penetration_slop << " m)";
    } else if (world_->insideClosedMesh(object, state.p_WB)) {
      message << names_[k] << " " << verb << " " << names_[object] << " (its centre is inside the closed mesh)";
    }
    conflict = message.str();
    if (!conflict.empty()) break;
  }
  const State& current = states[colliders_[k]];
  if (current.p_WB.norm() <= kContactRange && isFinite(current)) world_->setPose(k, current.p_WB, current.q_WB);
  return conflict;
}

void ContactStep::restart(const std::vector<State>& states) {
  placeAll(states);
  detectPoints();
  touching_.clear();
  warm_.clear();
  warm_runs_.clear();
  asleep_touching_.clear();
  asleep_warm_.clear();
  woken_ = false;
  for (const ContactPoint& point : points_) touching_.push_back(pairKey(point.a, point.b));
  std::sort(touching_.begin(), touching_.end());
  touching_.erase(std::unique(touching_.begin(), touching_.end()), touching_.end());
  indexTouching();
  for (auto& list : contacts_) list.clear();
  impacts_.clear();
  statistics_ = ContactStatistics();
  sleep_.reset(colliders_.size());
  syncSleep();
}

void ContactStep::step(SceneBodies& bodies, const std::vector<char>& running, double h,
                       std::vector<StepStatus>& failed, ThreadPool* pool, std::size_t bodies_per_block) {
  pool_ = pool;
  bodies_per_block_ = std::max<std::size_t>(1, bodies_per_block);
  if (sleep_.anyAsleep()) wakeReachedIslands(bodies, running, h);
  syncSleep();  // islands woken from outside (a new input, a force model) leave Bullet's sleep here
  restoreWokenPairs();
  awake_.resize(colliders_.size());
  for (std::size_t k = 0; k < colliders_.size(); ++k) awake_[k] = running[k] && !sleep_.asleep(k);
  stepSplitting(bodies, awake_, h, failed, 0);
  if (settings_.sleep) updateSleep(bodies, h);
}

void ContactStep::stepSplitting(SceneBodies& bodies, const std::vector<char>& running, double h,
                                std::vector<StepStatus>& failed, int splits) {
  // A body that would move farther than it is thick, with something near its path, steps in halves (each
  // half decides again): docs/contact.md, "No tunnelling".
  if (settings_.continuous && splits < kMaxStepSplits && needsShorterStep(bodies, running, h)) {
    ++statistics_.split_steps;
    stepSplitting(bodies, running, 0.5 * h, failed, splits + 1);
    stepSplitting(bodies, running, 0.5 * h, failed, splits + 1);
    return;
  }
  stepWhole(bodies, running, h, failed);
}

void ContactStep::stepWhole(SceneBodies& bodies, const std::vector<char>& running, double h,
                            std::vector<StepStatus>& failed) {
  const std::size_t n = colliders_.size();
  // 1. Free motion: every colliding body by its own integrator, as if nothing touched it.
  stepFreeMotion(bodies, running, h, failed);
  countOutside();
  detectPoints(&bodies, h);
  // 2. Impacts that begin within the step, each alone on its bodies, are resolved at their time.
  if (settings_.event_location || settings_.continuous) {
    findCandidates(bodies, running, h);
    bool any = false;
    for (const Candidate& candidate : candidates_) any = resolveImpact(bodies, candidate, h) || any;
    if (any || !candidates_.empty()) {
      placeAll(bodies.states);
      detectPoints(&bodies, h);
    }
  }
  // 3. The contacts at the end of the step: velocity solve, then position projection.
  solveResting(bodies, h);
  // Nothing non-finite reaches a state or a contact report: a body whose result is not finite keeps its
  // state from before the step (and latches its divergence); such a step is counted as refused.
  bool refused = false;
  for (std::size_t k = 0; k < n; ++k) {
    // A body still asleep was not touched by the step (one the solve needed woke: solverSlot).
    if (sleep_.asleep(k) || isFinite(bodies.states[colliders_[k]])) continue;
    bodies.states[colliders_[k]] = start_[k];
    if (running[k]) failed[k] = StepStatus::kNonFinite;
    refused = true;
  }
  refused = refused || std::find(island_finite_.begin(), island_finite_.end(), char{0}) != island_finite_.end();
  if (refused) {
    for (auto& list : contacts_) list.clear();
    ++statistics_.refused_steps;
    touching_.clear();
    indexTouching();
    warm_.clear();
    warm_runs_.clear();
    asleep_touching_.clear();
    asleep_warm_.clear();
  }
}

void ContactStep::startSolverLists() {
  solver_bodies_.assign(1, environmentBody());
  solver_body_of_.assign(1, kUnassigned);
}

std::size_t ContactStep::solverSlot(std::size_t object) {
  if (!world_->isBody(object)) return kEnvironment;
  if (solver_of_[object] != kUnassigned) return solver_of_[object];
  // A sleeping body in a contact with an awake one: wakeReachedIslands wakes it before the step whenever the
  // awake body's reach bound holds; should it not, the island wakes now and moves with the solve.
  wake(object);
  solver_of_[object] = solver_bodies_.size();
  solver_bodies_.emplace_back();
  solver_body_of_.push_back(object);
  return solver_of_[object];
}

void ContactStep::fillSolverBody(const SceneBodies& bodies, std::size_t s) {
  const std::size_t body = colliders_[solver_body_of_[s]];
  const MassProperties& mass = bodies.models[body].mass;
  const State& state = bodies.states[body];
  SolverBody& solver = solver_bodies_[s];
  solver = SolverBody();
  solver.inverse_mass = mass.inverseMass();
  const Eigen::Matrix3d R = state.q_WB.toRotationMatrix();
  solver.inverse_inertia_W = R * mass.inverseInertia() * R.transpose();
  solver.v = state.P_W * mass.inverseMass();
  solver.w = solver.inverse_inertia_W * state.L_W;
}

std::size_t ContactStep::solverIndex(const SceneBodies& bodies, std::size_t object) {
  const std::size_t bodies_before = solver_bodies_.size();
  const std::size_t s = solverSlot(object);
  if (solver_bodies_.size() > bodies_before) fillSolverBody(bodies, s);
  return s;
}

void ContactStep::buildSolverLists() {
  // The contacts and anchors are sized below and made whole by makeContact (not cleared first: a step's
  // thousands of contacts would be constructed twice), their solver bodies too (solver_pairs_): each
  // contact is written once, by the thread that fills its island.
  startSolverLists();
  admitted_.clear();
  admitted_links_.clear();
  admitted_touching_.clear();
  PairLookup lookup;
  std::uint64_t admitted_pair = ~std::uint64_t{0}, run_key = ~std::uint64_t{0};
  bool run_admitted = false;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const ContactPoint& point = points_[i];
    const std::uint64_t key = pairKey(point.a, point.b);
    const bool touching = wasTouching(key, lookup);
    if (key != run_key) {
      // A pair is admitted if it was touching and a point is within the slop, or if a point now touches (a
      // pair's points follow each other). Then its points within the slop all are: a face landing with some
      // corners in and the rest not yet (a hair above) had only those in admitted, the others went on
      // approaching, unseen by the solve, and were a step's travel deep in the next step.
      run_key = key, run_admitted = false;
      for (std::size_t j = i; j < points_.size() && pairKey(points_[j].a, points_[j].b) == key; ++j) {
        if (!points_[j].speculative && points_[j].distance <= (touching ? settings_.penetration_slop : 0.0)) {
          run_admitted = true;
          break;
        }
      }
    }
    // A speculative point (after its pair's others) only with a pair that is admitted.
    if (point.speculative && key != admitted_pair) continue;
    if (!point.speculative) {
      if (!run_admitted || point.distance > settings_.penetration_slop) continue;
      admitted_pair = key;
    }
    statistics_.max_penetration = std::max(statistics_.max_penetration, -point.distance);
    admitted_.push_back(i);
    admitted_links_.emplace_back(point.a, point.b);
    admitted_touching_.push_back(touching ? 1 : 0);
  }
  // The solver's lists island by island (solver_islands.hpp): a body enters them with its island's first
  // contact, so each island's bodies follow each other too. Numbered here, in order (solverSlot may wake a
  // body); each block of islands fills its own bodies and contacts as the solve begins it (fillBodies,
  // fillContacts; a large island's contacts in runs over the pool).
  islands_.group(admitted_links_, colliders_.size());
  const std::size_t count = admitted_.size();
  solver_contacts_.resize(count);
  solver_points_.resize(count);
  solver_anchors_.resize(count);
  solver_touching_.resize(count);
  solver_local_.resize(count);
  solver_pairs_.resize(count);
  island_body_start_.clear();
  for (std::size_t island = 0; island < islands_.islands(); ++island) {
    island_body_start_.push_back(solver_bodies_.size());
    for (std::size_t j = islands_.islandStart(island); j < islands_.islandStart(island + 1); ++j) {
      const std::size_t admitted = islands_.order()[j];
      const ContactPoint& point = points_[admitted_[admitted]];
      solver_points_[j] = &point;
      solver_touching_[j] = admitted_touching_[admitted];
      solver_pairs_[j] = {solverSlot(point.a), solverSlot(point.b)};
    }
  }
  island_body_start_.push_back(solver_bodies_.size());
}

void ContactStep::fillBodies(const SceneBodies& bodies, std::size_t first_island, std::size_t end_island) {
  for (std::size_t s = island_body_start_[first_island]; s < island_body_start_[end_island]; ++s) {
    fillSolverBody(bodies, s);
  }
}

void ContactStep::fillContacts(const SceneBodies& bodies, double h, std::size_t first, std::size_t end) {
  PairLookup lookup;
  for (std::size_t j = first; j < end; ++j) {
    solver_contacts_[j].a = solver_pairs_[j].first, solver_contacts_[j].b = solver_pairs_[j].second;
    makeContact(*solver_points_[j], bodies, solver_touching_[j] != 0, h, lookup, solver_contacts_[j],
                solver_anchors_[j], &solver_local_[j]);
  }
}

void ContactStep::finishBlock(SceneBodies& bodies, double h, std::size_t first_island, std::size_t end_island) {
  // The warm points and anchors first, in the bodies' frames as they stand at detection (the free step's end):
  // next step's points are found there too. Taken after the move, each point's place on its body was off by
  // the move c h Δv, the free fall undone (c h² g: 3.9 mm at h = 20 ms with semi-implicit Euler), which is
  // more than the warm-start match, and no point of a pair of bodies was ever warm-started or anchored.
  for (std::size_t island = first_island; island < end_island; ++island) {
    bool finite = true;
    for (std::size_t i = islands_.islandStart(island); i < islands_.islandStart(island + 1); ++i) {
      warm_next_[i] = warmPointOf(i, bodies, h);
      const SolverContact& c = solver_contacts_[i];
      finite = finite && std::isfinite(c.normal_impulse) && c.friction_impulse.allFinite() && c.n.allFinite() &&
               c.r_a.allFinite() && c.r_b.allFinite();
    }
    island_finite_[island] = finite ? 1 : 0;
  }
  for (std::size_t s = island_body_start_[first_island]; s < island_body_start_[end_island]; ++s) {
    const std::size_t k = solver_body_of_[s];
    State& state = bodies.states[colliders_[k]];
    state.P_W += solver_bodies_[s].dP;
    state.L_W += solver_bodies_[s].dL;
    state.p_WB += solver_bodies_[s].dx;
    rotate(state.q_WB, solver_bodies_[s].dtheta);
    solver_of_[k] = kUnassigned;
  }
}

void ContactStep::solveResting(SceneBodies& bodies, double h) {
  buildSolverLists();
  if (recording_) {
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
      if (!sleep_.asleep(k)) contacts_[k].clear();  // a sleeping body reports its contacts as it fell asleep
    }
  }
  if (restoreWokenPairs()) {  // the lists woke a sleeping body (solverSlot): its pairs touched
    for (std::size_t j = 0; j < solver_points_.size(); ++j) {
      solver_touching_[j] = wasTouching(pairKey(solver_points_[j]->a, solver_points_[j]->b)) ? 1 : 0;
    }
  }
  island_finite_.clear();
  if (solver_contacts_.empty()) {
    rememberTouching();
    warm_.clear();
    indexWarmPoints();
    for (std::size_t s = 1; s < solver_bodies_.size(); ++s) solver_of_[solver_body_of_[s]] = kUnassigned;
    return;
  }

  RestingSolveSettings solve;
  solve.options.iterations = sweepsPerStep(settings_, h);
  solve.options.restitution_threshold = settings_.restitution_threshold;
  solve.options.dt = h;
  solve.move_weight = h * integratorInfo(integrator_type_).constant_force_weight;
  solve.position_iterations = settings_.position_iterations;
  solve.penetration_slop = settings_.penetration_slop;
  solve.position_correction = settings_.position_correction;
  solve.lanes.wide_instructions = wide_lanes_;
  // Block by block on the pool: the lists filled (against last step's touching pairs and warm points),
  // solved, the moves applied and the warm points made.
  warm_next_.resize(solver_contacts_.size());
  island_finite_.assign(islands_.islands(), 1);
  SolverIslands::Hooks hooks;
  hooks.fill_bodies = [&](std::size_t, std::size_t first, std::size_t end) { fillBodies(bodies, first, end); };
  hooks.fill_contacts = [&](std::size_t first, std::size_t end) { fillContacts(bodies, h, first, end); };
  hooks.after = [&](std::size_t, std::size_t first, std::size_t end) { finishBlock(bodies, h, first, end); };
  islands_.solve(solver_contacts_, solver_bodies_, island_body_start_, solve, pool_, hooks);
  rememberTouching();
  rememberContacts();
}

void ContactStep::rememberTouching() {
  // A sleeping island's pairs are set aside (asleep_touching_), kept for when it wakes.
  touching_.clear();
  // A pair's points follow each other: one key per run (indexTouching sorts them should a pair come twice).
  std::uint64_t last = ~std::uint64_t{0};
  for (const ContactPoint* point : solver_points_) {
    const std::uint64_t key = pairKey(point->a, point->b);
    if (key != last) touching_.push_back(key), last = key;
  }
  indexTouching();
}

}  // namespace contact
}  // namespace rigid_body
