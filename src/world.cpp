#include "rigid_body_sim/world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "rigid_body_sim/number_format.hpp"

namespace rigid_body {

namespace {

// elapsed/dt is rounded up to the next integer when it is within this relative distance of it: a ratio
// computed as 29.999999999999996 is the grid point 30, not 29.
constexpr double kGridTolerance = 1e-9;
// No step count goes beyond 2^62: sums of two of them still fit in an int64.
constexpr std::int64_t kMaxSteps = std::int64_t(1) << 62;
constexpr Nanoseconds kMaxNanoseconds = std::numeric_limits<Nanoseconds>::max();
constexpr Nanoseconds kMinNanoseconds = std::numeric_limits<Nanoseconds>::min();

std::int64_t saturatingAdd(std::int64_t a, std::int64_t b) {
  std::int64_t sum;
  if (__builtin_add_overflow(a, b, &sum)) return b > 0 ? kMaxNanoseconds : kMinNanoseconds;
  return sum;
}

std::int64_t saturatingSubtract(std::int64_t a, std::int64_t b) {
  std::int64_t difference;
  if (__builtin_sub_overflow(a, b, &difference)) return b < 0 ? kMaxNanoseconds : kMinNanoseconds;
  return difference;
}

}  // namespace

Nanoseconds toNanoseconds(double seconds) {
  if (std::isnan(seconds)) return 0;
  const double ns = seconds * 1e9;
  if (ns >= 9.2e18) return kMaxNanoseconds;
  if (ns <= -9.2e18) return kMinNanoseconds;
  return std::llround(ns);
}

std::int64_t wholeStepsIn(double elapsed, double dt) {
  if (!(elapsed > 0.0) || !(dt > 0.0)) return 0;
  const double steps = std::floor(elapsed / dt * (1.0 + kGridTolerance));
  if (!(steps < static_cast<double>(kMaxSteps))) return kMaxSteps;
  return static_cast<std::int64_t>(steps);
}

World::World(const std::vector<BodyDefinition>& bodies, IntegratorType integrator,
             const IntegratorSettings& integrator_settings, const WorldSettings& settings, StepAssembly assembly,
             const ContactSetup& contact)
    : settings_(settings), scene_(bodies, integrator, settings.dt, integrator_settings, assembly, contact) {
  if (!(settings.dt >= 1e-9) || !std::isfinite(settings.dt)) {
    throw std::invalid_argument("dt must be a finite number >= 1e-9 [s] (the clock counts nanoseconds)");
  }
  if (settings.max_substeps < 1 || settings.max_body_steps_per_tick < 1 || settings.max_body_steps_per_request < 1) {
    throw std::invalid_argument("the step caps must be >= 1");
  }
  if (!(settings.max_request_seconds > 0.0)) throw std::invalid_argument("max_request_seconds must be > 0 [s]");
  if (!(settings.max_tick_seconds > 0.0)) throw std::invalid_argument("max_tick_seconds must be > 0 [s]");
  if (!(settings.wrench_timeout >= 0.0) || !std::isfinite(settings.wrench_timeout)) {
    throw std::invalid_argument("wrench_timeout must be a finite number >= 0 [s]");
  }
  if (settings.jitter_tolerance < 0 || settings.max_pending_commands < 1) {
    throw std::invalid_argument("jitter_tolerance must be >= 0 and max_pending_commands >= 1");
  }
  // Stamps are exact integers when dt is a whole number of nanoseconds (1 ms is), and rounded otherwise.
  const double dt_ns = settings.dt * 1e9;
  if (dt_ns < 9e18 && std::abs(dt_ns - std::round(dt_ns)) <= 1e-9 * dt_ns) dt_ns_ = std::llround(dt_ns);
  scene_.setMaxEnergyGrowth(settings.max_energy_growth);
  scene_.setThreads(settings.threads);
  inputs_.resize(bodies.size());
  pending_.reserve(std::min<std::size_t>(settings.max_pending_commands, 1024));
  paused_ = settings.start_paused;
}

void World::start(Nanoseconds start) {
  start_time_ = last_now_ = start;
  started_ = true;
  anchor(start);
}

void World::anchor(Nanoseconds time) {
  anchor_time_ = time;
  anchor_step_ = clock_;
  // The last step whose stamp the caller can still represent.
  const Nanoseconds room = saturatingSubtract(settings_.end_of_time, time);
  std::int64_t steps = 0;
  if (room > 0) {
    steps = dt_ns_ > 0 ? room / dt_ns_
                       : static_cast<std::int64_t>(std::min(std::floor(static_cast<double>(room) * 1e-9 / settings_.dt),
                                                            static_cast<double>(kMaxSteps)));
  }
  last_step_ = saturatingAdd(anchor_step_, std::min(steps, kMaxSteps));
  end_of_time_ = clock_ >= last_step_;
}

Nanoseconds World::timeOfStep(std::int64_t k) const {
  const std::int64_t offset = saturatingSubtract(k, anchor_step_);
  Nanoseconds elapsed;
  if (dt_ns_ > 0) {
    if (__builtin_mul_overflow(offset, dt_ns_, &elapsed)) elapsed = offset > 0 ? kMaxNanoseconds : kMinNanoseconds;
  } else {
    elapsed = toNanoseconds(static_cast<double>(offset) * settings_.dt);
  }
  return std::min(saturatingAdd(anchor_time_, elapsed), std::max(settings_.end_of_time, anchor_time_));
}

std::int64_t World::stepAt(Nanoseconds time) const {
  if (time <= anchor_time_) return anchor_step_;
  const Nanoseconds elapsed = saturatingSubtract(time, anchor_time_);
  const std::int64_t steps =
      dt_ns_ > 0 ? elapsed / dt_ns_ : wholeStepsIn(static_cast<double>(elapsed) * 1e-9, settings_.dt);
  return saturatingAdd(anchor_step_, std::min(steps, kMaxSteps));
}

std::int64_t World::updateBudget() const {
  return std::min(settings_.max_substeps,
                  std::max<std::int64_t>(1, settings_.max_body_steps_per_tick / runningCount()));
}

UpdateResult World::update(Nanoseconds now) {
  UpdateResult result;
  if (!started_) start(now);
  const std::int64_t before = clock_;
  if (now < last_now_ && !settings_.owns_clock) {
    // ROS time went back (rosbag play --loop, a restarted /clock). A step back within the jitter tolerance is
    // waited out (no step is due until time passes the last grid point again); a larger one re-anchors: the
    // bodies keep their states and the stamps follow the new time from here.
    if (saturatingSubtract(last_now_, now) > settings_.jitter_tolerance) {
      ++counters_.backward_time_jumps;
      anchor(now);
      last_now_ = now;
      result.reanchored = result.advanced = true;
    }
    for (const Command& command : pending_) apply(command, &result);  // they all arrived before this call
    pending_.clear();
    return result;
  }
  last_now_ = std::max(last_now_, now);
  std::int64_t target = stepAt(now);
  target = std::min(target, last_step_);
  std::int64_t budget = updateBudget();
  // The wall-time budget of a tick (not of our own clock's: that never drops steps).
  ChunkTimer timer(*this, settings_.owns_clock ? std::numeric_limits<double>::infinity() : settings_.max_tick_seconds);
  for (const Command& command : pending_) {
    const std::int64_t at = std::max(clock_, std::min(stepAt(command.arrival), std::max(clock_, target)));
    advanceClockTo(at, budget, false, result, &timer);
    apply(command, &result);
  }
  pending_.clear();
  advanceClockTo(target, budget, false, result, &timer);
  result.advanced = result.advanced || clock_ > before;
  result.end_of_time = end_of_time_ = clock_ >= last_step_;
  counters_.last_substeps = result.steps;
  counters_.max_substeps_seen = std::max(counters_.max_substeps_seen, result.steps);
  return result;
}

void World::advanceClockTo(std::int64_t target, std::int64_t& budget, bool integrate_paused, UpdateResult& result,
                           ChunkTimer* timer) {
  const bool limited = timer != nullptr && timer->limited();
  while (clock_ < target) {
    const std::int64_t next = std::min(target, nextEvent());
    const std::int64_t due = next - clock_;
    if (paused_ && !integrate_paused) {
      if (settings_.owns_clock) return;  // our own time stands still while paused
      clock_ = next;                     // someone else's clock runs; the states hold
    } else {
      const std::int64_t steps = std::min(due, budget);
      const std::int64_t chunk = limited ? chunkSteps() : steps;
      std::int64_t done = 0;
      bool out_of_time = false;
      while (done < steps && !out_of_time) {
        const std::int64_t n = std::min(chunk, steps - done);
        const SceneStepResult stepped = scene_.step(n);
        result.steps += stepped.steps;
        result.diverged = result.diverged || stepped.diverged;
        done += n;
        out_of_time = limited && timer->nextWouldOverrun();
      }
      budget = out_of_time ? 0 : budget - done;  // out of wall time: the rest of this update passes without motion
      result.dropped += due - done;
      counters_.dropped_steps += static_cast<std::uint64_t>(due - done);
      clock_ = next;
    }
    expireAt(clock_, result);
  }
}

std::int64_t World::nextEvent() const {
  std::int64_t next = kForever;
  for (std::size_t body : scheduled_) {
    const InputTimeline& timeline = inputs_[body];
    if (timeline.topic_expiry > clock_) next = std::min(next, timeline.topic_expiry);
    for (const TimedWrench& timed : timeline.timed) {
      if (timed.start > clock_) next = std::min(next, timed.start);
      if (timed.end > clock_) next = std::min(next, timed.end);
    }
  }
  return next;
}

void World::refreshInput(std::size_t body) {
  const InputTimeline& timeline = inputs_[body];
  AppliedWrench input = timeline.topic;
  for (const TimedWrench& timed : timeline.timed) {
    if (timed.start <= clock_ && clock_ < timed.end) input += timed.wrench;
  }
  scene_.setInput(body, input);
}

void World::expireAt(std::int64_t k, UpdateResult& result) {
  for (std::size_t body : scheduled_) {
    InputTimeline& timeline = inputs_[body];
    if (timeline.topic_expiry <= k) {
      timeline.topic = AppliedWrench();
      timeline.topic_expiry = kForever;
      timeline.timed_out = true;
      ++counters_.wrench_timeouts;
      result.timed_out.push_back(body);
    }
    timeline.timed.erase(std::remove_if(timeline.timed.begin(), timeline.timed.end(),
                                        [k](const TimedWrench& timed) { return timed.end <= k; }),
                         timeline.timed.end());
    refreshInput(body);
  }
  scheduled_.erase(std::remove_if(scheduled_.begin(), scheduled_.end(),
                                  [this](std::size_t body) {
                                    InputTimeline& timeline = inputs_[body];
                                    timeline.scheduled = !timeline.timed.empty() || timeline.topic_expiry != kForever;
                                    return !timeline.scheduled;
                                  }),
                   scheduled_.end());
}

CommandReply World::submit(const Command& command) {
  if (command.body >= bodyCount()) return {false, "no body " + std::to_string(command.body)};
  // Nothing due before the arrival (or our own clock, where every arrival is now): it acts at once.
  if (!started_ || settings_.owns_clock || (pending_.empty() && stepAt(command.arrival) <= clock_)) {
    UpdateResult ignored;
    apply(command, &ignored);
    return {true, ""};
  }
  // A newer topic wrench of the same body on the same step replaces the waiting one (latest wins there).
  if (command.kind == CommandKind::kTopicWrench && !pending_.empty()) {
    Command& last = pending_.back();
    if (last.kind == CommandKind::kTopicWrench && last.body == command.body &&
        stepAt(last.arrival) == stepAt(command.arrival)) {
      last = command;
      return {true, ""};
    }
  }
  if (pending_.size() >= settings_.max_pending_commands) {
    ++counters_.refused_commands;
    return {false, "refused: " + std::to_string(pending_.size()) + " commands already wait for their step"};
  }
  pending_.push_back(command);
  return {true, ""};
}

void World::apply(const Command& command, UpdateResult* result) {
  InputTimeline& timeline = inputs_[command.body];
  const auto schedule = [this](std::size_t body) {
    if (inputs_[body].scheduled) return;
    inputs_[body].scheduled = true;
    scheduled_.push_back(body);
  };
  switch (command.kind) {
    case CommandKind::kTopicWrench: {
      if (!aboutCentreOfMass(command, timeline.topic)) return;
      timeline.timed_out = false;
      timeline.topic_expiry = kForever;
      ++counters_.topic_wrenches;
      last_wrench_arrival_ = std::max(last_wrench_arrival_, command.arrival);
      if (settings_.wrench_timeout > 0.0) {
        timeline.topic_expiry = stepAt(saturatingAdd(command.arrival, toNanoseconds(settings_.wrench_timeout)));
        schedule(command.body);
        if (timeline.topic_expiry <= clock_) {  // it expired before the step it would act on
          UpdateResult local;
          expireAt(clock_, result ? *result : local);
        }
      }
      break;
    }
    case CommandKind::kTimedWrench: {
      if (timeline.timed.size() >= settings_.max_timed_wrenches) {
        ++counters_.refused_commands;
        break;
      }
      TimedWrench timed;
      if (!aboutCentreOfMass(command, timed.wrench)) return;
      timed.start = command.start <= 0 ? clock_ : std::max(clock_, stepAt(command.start));
      if (command.duration < 0.0) {
        timed.end = kForever;
      } else {
        const double steps = std::max(1.0, std::round(command.duration / settings_.dt));
        timed.end = saturatingAdd(timed.start, static_cast<std::int64_t>(std::min(steps, static_cast<double>(kMaxSteps))));
      }
      timeline.timed.push_back(timed);
      ++counters_.timed_wrenches;
      schedule(command.body);
      break;
    }
    case CommandKind::kClearWrenches:
      clearWrenchesNow();
      return;  // every body's input is zero now
    case CommandKind::kReset:
      resetNow();
      return;
    case CommandKind::kSetState:
      scene_.setState(command.body, command.state);
      return;
    case CommandKind::kPause:
      paused_ = true;
      return;
    case CommandKind::kUnpause:
      paused_ = false;
      return;
    case CommandKind::kSetForces:
      scene_.setForceModel(command.body, command.forces);
      return;
    case CommandKind::kSetWrenchTimeout:
      settings_.wrench_timeout = command.duration;
      return;
  }
  refreshInput(command.body);
}

bool World::aboutCentreOfMass(const Command& command, AppliedWrench& wrench) {
  AppliedWrench moved = command.wrench;
  if (command.has_point) {
    moved.world = wrenchAboutCentreOfMass(command.wrench.world.force, command.wrench.world.torque, command.p_WQ,
                                          scene_.state(command.body).p_WB);
  }
  if (!moved.isFinite()) {
    ++counters_.refused_moment_arms;
    return false;
  }
  wrench = moved;
  return true;
}

void World::clearWrenchesNow() {
  for (std::size_t body = 0; body < inputs_.size(); ++body) {
    InputTimeline& timeline = inputs_[body];
    timeline.topic = AppliedWrench();
    timeline.topic_expiry = kForever;
    timeline.timed.clear();
    timeline.scheduled = false;
    scene_.setInput(body, AppliedWrench());
  }
  scheduled_.clear();
}

void World::resetNow() {
  clearWrenchesNow();
  for (InputTimeline& timeline : inputs_) timeline.timed_out = false;
  scene_.reset();
  ++counters_.resets;
}

World::Command World::command(CommandKind kind, std::size_t body, Nanoseconds arrival) {
  Command command;
  command.kind = kind;
  command.body = body;
  command.arrival = arrival;
  return command;
}

World::Command World::wrenchCommand(CommandKind kind, std::size_t body, const AppliedWrench& wrench,
                                    Nanoseconds arrival, const Eigen::Vector3d* p_WQ) {
  Command made = command(kind, body, arrival);
  made.wrench = wrench;
  if (p_WQ) {
    made.has_point = true;
    made.p_WQ = *p_WQ;
  }
  return made;
}

CommandReply World::setWrench(std::size_t body, const AppliedWrench& wrench, Nanoseconds arrival,
                              const Eigen::Vector3d* p_WQ) {
  if (body < bodyCount() && !scene_.takesInput(body) && !wrench.isZero()) return {false, "this body takes no wrench input"};
  if (!wrench.isFinite() || (p_WQ && !p_WQ->allFinite())) return {false, "refused: a non-finite wrench or point"};
  return submit(wrenchCommand(CommandKind::kTopicWrench, body, wrench, arrival, p_WQ));
}

CommandReply World::applyWrench(std::size_t body, const AppliedWrench& wrench, Nanoseconds start, double duration,
                                Nanoseconds arrival, const Eigen::Vector3d* p_WQ) {
  if (body < bodyCount() && !scene_.takesInput(body)) return {false, "this body takes no wrench input"};
  if (!wrench.isFinite() || (p_WQ && !p_WQ->allFinite())) return {false, "refused: a non-finite wrench or point"};
  if (std::isnan(duration) || std::isinf(duration)) return {false, "refused: the duration must be finite"};
  if (body < bodyCount() && inputs_[body].timed.size() >= settings_.max_timed_wrenches) {
    ++counters_.refused_commands;
    return {false, "refused: " + std::to_string(settings_.max_timed_wrenches) +
                       " timed wrenches already act on this body (clear_wrenches first)"};
  }
  Command timed = wrenchCommand(CommandKind::kTimedWrench, body, wrench, arrival, p_WQ);
  timed.start = start;
  timed.duration = duration;
  return submit(timed);
}

CommandReply World::clearWrenches(Nanoseconds arrival) { return submit(command(CommandKind::kClearWrenches, 0, arrival)); }

CommandReply World::reset(Nanoseconds arrival) { return submit(command(CommandKind::kReset, 0, arrival)); }

CommandReply World::setState(std::size_t body, const State& state, Nanoseconds arrival) {
  if (!Integrator::acceptable(state)) {  // what a step may commit, a state from outside must be too
    return {false, "refused: the state is not finite or its orientation not a unit quaternion"};
  }
  if (body < scene_.bodyCount()) {
    const std::string conflict = scene_.placementConflict(body, state);
    if (!conflict.empty()) return {false, "refused: " + conflict};
  }
  Command replace = command(CommandKind::kSetState, body, arrival);
  replace.state = state;
  return submit(replace);
}

CommandReply World::setForceModel(std::size_t body, const ForceModel& forces, Nanoseconds arrival) {
  if (body >= scene_.bodyCount()) return {false, "refused: no such body"};
  if (!forces.gravity_W.allFinite() || !(forces.linear_damping >= 0.0) || !std::isfinite(forces.linear_damping) ||
      !(forces.angular_damping >= 0.0) || !std::isfinite(forces.angular_damping)) {
    return {false, "refused: gravity must be finite and the dampings finite and >= 0"};
  }
  Command change = command(CommandKind::kSetForces, body, arrival);
  change.forces = forces;
  return submit(change);
}

CommandReply World::setWrenchTimeout(double seconds, Nanoseconds arrival) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return {false, "refused: wrench_timeout must be finite and >= 0"};
  Command change = command(CommandKind::kSetWrenchTimeout, 0, arrival);
  change.duration = seconds;
  return submit(change);
}

CommandReply World::pause(Nanoseconds arrival) { return submit(command(CommandKind::kPause, 0, arrival)); }

CommandReply World::unpause(Nanoseconds arrival) { return submit(command(CommandKind::kUnpause, 0, arrival)); }

CommandReply World::step(std::int64_t steps, Nanoseconds now) {
  if (steps < 1) return {false, "steps must be >= 1"};
  if (!settings_.owns_clock) update(now);  // what arrived before the request acts first (paused: no motion)
  if (!paused_) return {false, "call pause first: step advances a paused simulation"};
  const std::int64_t most = std::max<std::int64_t>(1, settings_.max_body_steps_per_request / runningCount());
  if (steps > most) {
    return {false, "refused: at most " + std::to_string(most) + " steps per call for this scene (" +
                       std::to_string(settings_.max_body_steps_per_request) +
                       " body-steps); call step again for more"};
  }
  if (settings_.owns_clock && steps > last_step_ - clock_) {
    end_of_time_ = true;
    return {false, "refused: the clock would pass the last representable time"};
  }
  // In chunks, the wall clock read between them (as advanceClockTo does for a tick): a request stops at its
  // time budget, where it got to.
  ChunkTimer timer(*this, settings_.max_request_seconds);
  const std::int64_t chunk = timer.limited() ? chunkSteps() : steps;
  for (std::int64_t done = 0; done < steps;) {
    const std::int64_t n = std::min(chunk, steps - done);
    if (settings_.owns_clock) {
      std::int64_t unlimited = kForever;
      UpdateResult result;
      advanceClockTo(clock_ + n, unlimited, true, result);
    } else {
      scene_.step(n);  // the clock is someone else's: it stays where it is
    }
    done += n;
    if (done < steps && timer.nextWouldOverrun()) {
      return {false, "stopped after " + std::to_string(done) + " of " + std::to_string(steps) +
                         " steps: a step request takes at most " + formatNumber(settings_.max_request_seconds, 6) +
                         " s of wall time (max_request_seconds); call step again for the rest"};
    }
  }
  return {true, ""};
}

std::int64_t World::runningCount() const {
  return static_cast<std::int64_t>(std::max<std::size_t>(1, scene_.runningBodies()));
}

std::int64_t World::chunkSteps() const {
  const auto colliders = static_cast<std::int64_t>(scene_.collidingBodies());
  if (colliders == 0) return std::max(kMinChunkSteps, kRequestChunkBodySteps / runningCount());
  const std::int64_t weighted = runningCount() + (kColliderChunkWeight - 1) * colliders;
  return std::max<std::int64_t>(1, kRequestChunkBodySteps / weighted);
}

World::ChunkTimer::ChunkTimer(const World& world, double budget_seconds)
    : world_(world), deadline_(kNoDeadline), last_(0) {
  if (!std::isfinite(budget_seconds)) return;
  last_ = world.wallClock();
  deadline_ = saturatingAdd(last_, toNanoseconds(budget_seconds));
}

bool World::ChunkTimer::nextWouldOverrun() {
  if (!limited()) return false;
  const Nanoseconds now = world_.wallClock();
  const Nanoseconds took = std::max<Nanoseconds>(0, now - last_);
  last_ = now;
  return now >= deadline_ || took > deadline_ - now;
}

Nanoseconds World::wallClock() const {
  if (settings_.wall_clock) return settings_.wall_clock();
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

CommandReply World::rewind() {
  if (!settings_.owns_clock) return {false, "rewinding time is only for a world that owns its clock (lockstep)"};
  pending_.clear();
  resetNow();
  clock_ = 0;
  anchor(start_time_);
  return {true, ""};
}

}  // namespace rigid_body
