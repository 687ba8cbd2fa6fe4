#include "solver_islands.hpp"

#include <algorithm>
#include <limits>

namespace rigid_body {
namespace contact {

namespace {

constexpr std::size_t kNoIsland = std::numeric_limits<std::size_t>::max();

// A contact made within the step (after a located impact, or a landing found at the step's end) has not
// pushed for the whole step: its body's fall was partly free flight, and undoing all of it by c h Δv would
// lift the contact off the surface (at h = 10 ms a ball hopped for ever: each landing lifted it by c h of
// its arrival speed). So a body moves by c h Δv only as far as brings such a contact to the surface, to
// first order in the move (as the projection measures it); a new contact that bounces is not lifted at all
// (its rebound already has the kinetic energy of its arrival, and the lift would add potential energy).
void limitLiftOfNewContacts(const std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                            const SolveRange& range, std::vector<double>& lift_share) {
  for (std::size_t s = range.body_begin; s < range.body_end; ++s) lift_share[s] = 1.0;
  bool limited = false;
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    if (c.sustained) continue;
    if (c.separation > 0.0 && c.normal_impulse == 0.0) continue;  // a speculative point that stopped nothing
    const SolverBody& a = bodies[c.a];
    const SolverBody& b = bodies[c.b];
    const double lift = c.n.dot(a.dx - b.dx) + c.cross_a.col(0).dot(a.dtheta) - c.cross_b.col(0).dot(b.dtheta);
    const bool bouncing = c.target_speed > 0.0;
    if (!(lift > 0.0) || (c.separation + lift <= 0.0 && !bouncing)) continue;
    const double share = bouncing ? 0.0 : std::max(0.0, -c.separation) / lift;
    if (c.a != kEnvironment) lift_share[c.a] = std::min(lift_share[c.a], share);
    if (c.b != kEnvironment) lift_share[c.b] = std::min(lift_share[c.b], share);
    limited = true;
  }
  if (!limited) return;
  for (std::size_t s = std::max<std::size_t>(range.body_begin, 1); s < range.body_end; ++s) {  // 0: environment
    bodies[s].dx *= lift_share[s];
    bodies[s].dtheta *= lift_share[s];
  }
}

// A point slipping faster than this slides, and its island is not solved at once as if it stuck: a tenth of
// the slop per step, the bound below which a point may anchor (docs/contact.md, step 6).
double slidingSpeed(const RestingSolveSettings& settings) {
  return settings.options.dt > 0.0 ? 0.1 * settings.penetration_slop / settings.options.dt
                                   : std::numeric_limits<double>::infinity();
}

}  // namespace

bool solveRestingContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                          const RestingSolveSettings& settings, const SolveRange& range,
                          std::vector<double>& lift_share) {
  prepareContacts(contacts, bodies, settings.options, range);
  LaneContactSolver lanes;
  char converged = 0;
  lanes.solve(contacts, bodies, settings.options, &range, 1, &converged, settings.lanes);
  StickingScratch scratch;
  const double sliding = slidingSpeed(settings);
  if (converged != kConvergedInSweeps &&
      solveStickingIsland(contacts, bodies, range, settings.options.dt, sliding, scratch) == StickingOutcome::kSolved) {
    converged = kConvergedInSweeps;
  }
  finishRestingContacts(contacts, bodies, settings, range, lift_share);
  return converged != 0;
}

void finishRestingContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                           const RestingSolveSettings& settings, const SolveRange& range,
                           std::vector<double>& lift_share) {
  sumImpulses(contacts, bodies, range);
  limitEnergyGain(contacts, bodies, range);
  // The impulses stand for a contact force constant over the step: besides the momenta they move the body
  // by c h Δv (and turn it by c h Δω), as the integrator would have moved it under that force; then the
  // projection.
  for (std::size_t s = range.body_begin; s < range.body_end; ++s) {
    SolverBody& body = bodies[s];
    body.dx = settings.move_weight * body.inverse_mass * body.dP;
    body.dtheta = settings.move_weight * (body.inverse_inertia_W * body.dL);
  }
  limitLiftOfNewContacts(contacts, bodies, range, lift_share);
  projectPositions(contacts, bodies, settings.position_iterations, settings.penetration_slop,
                   settings.position_correction, range);
}

std::size_t SolverIslands::root(std::size_t body) {
  while (parent_[body] != body) {
    parent_[body] = parent_[parent_[body]];  // path halving
    body = parent_[body];
  }
  return body;
}

void SolverIslands::group(const std::vector<std::pair<std::size_t, std::size_t>>& links, std::size_t bodies) {
  parent_.resize(bodies);
  for (std::size_t k = 0; k < bodies; ++k) parent_[k] = k;
  // A pair's points follow each other: each run of one link is joined (and looked up) once.
  const auto repeats = [&](std::size_t i) { return i > 0 && links[i] == links[i - 1]; };
  for (std::size_t i = 0; i < links.size(); ++i) {
    const auto& [first, second] = links[i];
    if (repeats(i) || first >= bodies || second >= bodies) continue;
    const std::size_t a = root(first), b = root(second);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  // Islands (of the bodies that have a point) numbered by their smallest body, its root; then the points
  // counted into place, each island's in their given order.
  const auto bodyOf = [&](std::size_t i) { return links[i].first < bodies ? links[i].first : links[i].second; };
  island_of_root_.assign(bodies, kNoIsland);
  for (std::size_t i = 0; i < links.size(); ++i) {
    if (!repeats(i)) island_of_root_[root(bodyOf(i))] = 0;
  }
  std::size_t count = 0;
  island_root_.clear();
  for (std::size_t k = 0; k < bodies; ++k) {
    if (island_of_root_[k] != kNoIsland) island_of_root_[k] = count++, island_root_.push_back(k);
  }
  if (refusals_.size() != bodies) refusals_.assign(bodies, 0), waits_.assign(bodies, 0);
  island_of_point_.resize(links.size());
  island_start_.assign(count + 1, 0);
  for (std::size_t i = 0; i < links.size(); ++i) {
    island_of_point_[i] = repeats(i) ? island_of_point_[i - 1] : island_of_root_[root(bodyOf(i))];
    ++island_start_[island_of_point_[i] + 1];
  }
  for (std::size_t island = 0; island < count; ++island) island_start_[island + 1] += island_start_[island];
  next_.assign(island_start_.begin(), island_start_.end() - 1);
  order_.resize(links.size());
  island_of_contact_.resize(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    const std::size_t j = next_[island_of_point_[i]]++;
    order_[j] = i;
    island_of_contact_[j] = island_of_point_[i];
  }
  block_end_.clear();
  std::size_t in_block = 0;
  for (std::size_t island = 0; island < count; ++island) {
    if (large(island) && in_block > 0) block_end_.push_back(island), in_block = 0;  // a large island alone
    in_block += island_start_[island + 1] - island_start_[island];
    if (in_block >= kContactsPerBlock || island + 1 == count) block_end_.push_back(island + 1), in_block = 0;
  }
}

std::size_t SolverIslands::triedAtOnce() const {
  std::size_t tried = 0;
  for (const std::size_t block : tried_at_once_) tried += block;
  return tried;
}

bool SolverIslands::waitsToSolveAtOnce(std::size_t island) {
  std::uint32_t& wait = waits_[island_root_[island]];
  if (wait == 0) return false;
  --wait;
  return true;
}

void SolverIslands::noteOutcome(std::size_t island, StickingOutcome outcome) {
  const std::size_t root = island_root_[island];
  if (outcome == StickingOutcome::kSolved) {
    refusals_[root] = 0;
  } else if (outcome == StickingOutcome::kRefused) {
    refusals_[root] = static_cast<std::uint8_t>(std::min<int>(refusals_[root] + 1, kMostBackOffDoublings));
    waits_[root] = (1u << refusals_[root]) - 1u;
  }
}

std::size_t SolverIslands::takeScratch() {
  const std::lock_guard<std::mutex> lock(scratch_mutex_);
  const std::size_t slot = free_scratch_.back();
  free_scratch_.pop_back();
  return slot;
}

void SolverIslands::giveBackScratch(std::size_t slot) {
  const std::lock_guard<std::mutex> lock(scratch_mutex_);
  free_scratch_.push_back(slot);
}

void SolverIslands::forEachBlock(ThreadPool* pool, const BlockWork& work) const {
  const auto run = [&](std::size_t block) { work(block, block == 0 ? 0 : block_end_[block - 1], block_end_[block]); };
  if (pool != nullptr && pool->threads() > 1 && block_end_.size() > 1) {
    pool->parallelFor(block_end_.size(), run);
  } else {
    for (std::size_t block = 0; block < block_end_.size(); ++block) run(block);
  }
}

bool SolverIslands::prepareLargeIslands(std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                                        const SolveOptions& options, ThreadPool* pool, const Hooks& hooks) {
  if (pool == nullptr || pool->threads() == 1) return false;
  large_runs_.clear();
  for (std::size_t island = 0; island < islands(); ++island) {
    if (!large(island)) continue;
    if (hooks.fill_bodies) hooks.fill_bodies(0, island, island + 1);
    for (std::size_t first = island_start_[island]; first < island_start_[island + 1]; first += kContactsPerBlock) {
      large_runs_.emplace_back(first, std::min(island_start_[island + 1], first + kContactsPerBlock));
    }
  }
  if (large_runs_.empty()) return false;
  pool->parallelFor(large_runs_.size(), [&](std::size_t run) {
    const auto [first, end] = large_runs_[run];
    if (hooks.fill_contacts) hooks.fill_contacts(first, end);
    prepareContactRows(contacts, bodies, options, first, end);
  });
  return true;
}

void SolverIslands::solve(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                          const std::vector<std::size_t>& body_start, const RestingSolveSettings& settings,
                          ThreadPool* pool, const Hooks& hooks) {
  const std::size_t count = islands();
  island_converged_.assign(count, 0);
  lift_share_.resize(bodies.size());
  RestingSolveSettings shared = settings;
  shared.options.budget_contacts = contacts.size();
  const auto rangeOf = [&](std::size_t island) {
    return SolveRange{island_start_[island], island_start_[island + 1], body_start[island], body_start[island + 1]};
  };
  ranges_.resize(count);
  for (std::size_t island = 0; island < count; ++island) ranges_[island] = rangeOf(island);
  // As many scratches as threads may run blocks at once (made before, so none moves while in use).
  const std::size_t at_once = pool != nullptr && block_end_.size() > 1 ? pool->threads() : 1;
  if (scratch_.size() < at_once) scratch_.resize(at_once);
  free_scratch_.clear();
  for (std::size_t slot = scratch_.size(); slot-- > 0;) free_scratch_.push_back(slot);
  tried_at_once_.assign(block_end_.size(), 0);
  const bool large_prepared = prepareLargeIslands(contacts, bodies, shared.options, pool, hooks);
  // A block's islands are filled, prepared, swept together in the lanes, and finished one by one.
  forEachBlock(pool, [&](std::size_t block, std::size_t begin, std::size_t end) {
    if (large_prepared && large(begin)) {
      applyWarmStarts(contacts, bodies, ranges_[begin]);
    } else {
      if (hooks.fill_bodies) hooks.fill_bodies(block, begin, end);
      if (hooks.fill_contacts) hooks.fill_contacts(island_start_[begin], island_start_[end]);
      for (std::size_t island = begin; island < end; ++island) {
        prepareContacts(contacts, bodies, shared.options, ranges_[island]);
      }
    }
    const std::size_t slot = takeScratch();
    BlockScratch& scratch = scratch_[slot];
    scratch.lanes.solve(contacts, bodies, shared.options, ranges_.data() + begin, end - begin,
                        island_converged_.data() + begin, shared.lanes);
    // What the sweeps left unconverged, or converged only beyond the sweeps asked for, at once.
    for (std::size_t island = begin; island < end; ++island) {
      if (island_converged_[island] == kConvergedInSweeps || waitsToSolveAtOnce(island)) continue;
      const StickingOutcome outcome = solveStickingIsland(contacts, bodies, ranges_[island], shared.options.dt,
                                                          slidingSpeed(shared), scratch.sticking);
      noteOutcome(island, outcome);
      if (outcome != StickingOutcome::kNotTried) ++tried_at_once_[block];
      if (outcome == StickingOutcome::kSolved) island_converged_[island] = kConvergedInSweeps;
    }
    giveBackScratch(slot);
    for (std::size_t island = begin; island < end; ++island) {
      finishRestingContacts(contacts, bodies, shared, ranges_[island], lift_share_);
    }
    if (hooks.after) hooks.after(block, begin, end);
  });
}

}  // namespace contact
}  // namespace rigid_body
