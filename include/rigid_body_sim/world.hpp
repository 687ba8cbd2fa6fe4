// The core runner: a Scene advanced on a fixed step grid against a clock, with everything about time and
// inputs. The ROS layer converts each message once into a command stamped with its arrival and hands it
// here; the timer calls update(now) once a tick (one update() is a tick: the word the parameters use, as
// in max_tick_seconds); the lockstep driver calls the same update with its own clock.
//
// Time. The caller's clock is in integer nanoseconds (ROS time's toNSec()). Simulated time is an integer
// count k of steps of dt on a grid anchored at the start: the state belongs to stamp(k) = anchor +
// (k − k_anchor)·dt. k only grows, also across reset, so stamps strictly increase; a backward jump of the
// caller's clock by more than the jitter tolerance re-anchors the grid at the new time (the body keeps its
// state). Every conversion is checked: k never passes the last step whose stamp the caller can represent
// (WorldSettings::end_of_time), and no arithmetic on k or on nanoseconds can overflow.
//
// Inputs. A body's input at step k is its topic wrench (latest wins, acting from the step of its arrival,
// to zero at arrival + wrench_timeout when that is set) plus every timed wrench with start ≤ k < end. A
// command takes effect at the step of its arrival: at once when no step is due before it, otherwise at that
// step of the next update (commands wait in a bounded queue, in arrival order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/scene.hpp"

namespace rigid_body {

/// A time on the caller's clock [ns].
using Nanoseconds = std::int64_t;

/// Nanoseconds of a time in seconds, saturated to ±(2^63 − 1) and 0 for NaN (never undefined behaviour).
Nanoseconds toNanoseconds(double seconds);

/// Whole steps of length dt that fit into `elapsed` seconds: ⌊elapsed/dt⌋, with a relative guard so that
/// e.g. 0.03/0.001 = 29.999999999999996 counts as 30. 0 for elapsed ≤ 0 or NaN; saturated at 2^62.
std::int64_t wholeStepsIn(double elapsed, double dt);

struct WorldSettings {
  double dt = 0.001;  ///< the physics step [s], > 0
  /// Catch-up cap: the steps one update() integrates, at most this many per body and, counted in body-steps
  /// (steps × running bodies), at most max_body_steps_per_tick in all; the rest of the due steps pass
  /// without motion (time lost, counted as dropped). At least one step is always integrated.
  std::int64_t max_substeps = 1000;
  std::int64_t max_body_steps_per_tick = 2000000;
  /// step(N) integrates at most this many body-steps (N × running bodies) in one call; a larger N is refused.
  std::int64_t max_body_steps_per_request = 2000000;
  /// step(N) stops once it has taken this much wall time [s] (the clock is read between chunks of about
  /// kRequestChunkBodySteps body-steps) and says how far it got: a request holds its caller (the node's
  /// callbacks) no longer than this, whatever a step costs (a contact step of a stack costs a thousand free
  /// steps). Infinite: no limit.
  double max_request_seconds = std::numeric_limits<double>::infinity();
  /// update() integrates for at most this much wall time [s] (read between chunks, as step(N) does); the
  /// steps still due then pass without motion, counted as dropped, like the catch-up cap's. A scene that
  /// cannot keep real time (a pile of contact bodies) then keeps ticking and publishing, slower in simulated
  /// time, instead of spending seconds in each tick. Not with owns_clock (our own time never drops steps).
  /// Infinite: no limit.
  double max_tick_seconds = std::numeric_limits<double>::infinity();
  /// The wall clock step(N) and update() time themselves with [ns]; std::chrono::steady_clock when empty
  /// (tests give their own).
  std::function<Nanoseconds()> wall_clock;
  double wrench_timeout = 0.0;                 ///< [s]; 0: a topic wrench holds until the next one
  Nanoseconds jitter_tolerance = 0;            ///< backward steps of the clock up to this are waited out [ns]
  Nanoseconds end_of_time = std::numeric_limits<Nanoseconds>::max();  ///< the latest stamp the caller can use
  bool owns_clock = false;       ///< lockstep: pause stops time, step(N) moves the clock by N steps
  bool start_paused = false;
  double max_energy_growth = std::numeric_limits<double>::infinity();  ///< the Scene's divergence guard
  std::size_t threads = 1;  ///< the Scene's threads (Scene::setThreads; 0: as many as the machine has)
  std::size_t max_pending_commands = 100000;   ///< commands waiting for their step; more are refused
  std::size_t max_timed_wrenches = 1000;       ///< per body; more are refused
};

/// What one update() did.
struct UpdateResult {
  std::int64_t steps = 0;      ///< steps integrated (by the running bodies)
  std::int64_t dropped = 0;    ///< steps due but passed without motion (catch-up cap)
  bool advanced = false;       ///< the clock reached a new grid point (or was re-anchored): publish
  bool reanchored = false;     ///< the caller's clock jumped back by more than the jitter tolerance
  bool diverged = false;       ///< some body's divergence was latched in this update
  bool end_of_time = false;    ///< the clock stopped at the last representable stamp
  std::vector<std::size_t> timed_out;  ///< bodies whose topic wrench timed out in this update
};

/// The answer to a command.
struct CommandReply {
  bool accepted = false;
  std::string message;  ///< why not, or what was scheduled
};

/// Counts since construction.
struct WorldCounters {
  std::uint64_t topic_wrenches = 0;       ///< topic wrenches accepted
  std::uint64_t timed_wrenches = 0;       ///< timed (service) wrenches accepted
  std::uint64_t refused_commands = 0;     ///< commands refused: queue full, too many timed wrenches
  std::uint64_t refused_moment_arms = 0;  ///< wrenches whose torque about the centre of mass overflowed
  std::uint64_t dropped_steps = 0;        ///< steps passed without motion (catch-up cap)
  std::uint64_t wrench_timeouts = 0;      ///< topic wrenches that timed out
  std::uint64_t backward_time_jumps = 0;  ///< re-anchors
  std::uint64_t resets = 0;               ///< resets applied (reset and rewind)
  std::int64_t last_substeps = 0;         ///< steps integrated by the last update
  std::int64_t max_substeps_seen = 0;     ///< most steps one update integrated
};

/// Body-steps between two readings of the wall clock in step(N) and a timed update(), but for a scene without
/// colliders at least kMinChunkSteps steps: a tick's usual steps stay one Scene::step (one hand-out to the
/// threads, one energy check).
constexpr std::int64_t kRequestChunkBodySteps = 1024;
constexpr std::int64_t kMinChunkSteps = 16;
/// A colliding body counts as this many body-steps in a chunk, and a scene with colliders may chunk single
/// steps: a colliding body's step (free step, detection, solve) costs tens of free ones (docs/performance.md,
/// "Contact"), so that a large pile still reads the clock, and stops at its budget, within one step.
constexpr std::int64_t kColliderChunkWeight = 64;

class World {
 public:
  /// Throws std::invalid_argument for settings out of range (dt, caps) or a bad scene.
  World(const std::vector<BodyDefinition>& bodies, IntegratorType integrator,
        const IntegratorSettings& integrator_settings, const WorldSettings& settings,
        StepAssembly assembly = StepAssembly::kLeaveOut, const ContactSetup& contact = ContactSetup());

  /// Anchors simulated time 0 (step 0) at `start` on the caller's clock.
  void start(Nanoseconds start);

  /// Integrates every step due up to `now`, applying the waiting commands at the steps of their arrival and
  /// switching inputs at every start and end of a timed wrench and at every timeout.
  UpdateResult update(Nanoseconds now);

  // ----- commands, each stamped with its arrival on the caller's clock -----
  /// A topic wrench: replaces the body's previous one from the step of its arrival. If `p_WQ` is given, the
  /// world part's torque is about that world point Q [m]; it is moved to the centre of mass at the step the
  /// wrench starts to act, τ = τ_Q + (p_WQ − x) × F_W (held in world axes from then on). A wrench whose
  /// moment arm overflows is refused and counted then.
  CommandReply setWrench(std::size_t body, const AppliedWrench& wrench, Nanoseconds arrival,
                         const Eigen::Vector3d* p_WQ = nullptr);
  /// A timed wrench over [start, start + duration) on the step grid, summed with the others: start ≤ 0
  /// means the arrival; duration 0 means one step, negative until clear_wrenches. The window's bounds are
  /// rounded to whole steps, so its impulse is exact to one step.
  /// `p_WQ` as for setWrench.
  CommandReply applyWrench(std::size_t body, const AppliedWrench& wrench, Nanoseconds start, double duration,
                           Nanoseconds arrival, const Eigen::Vector3d* p_WQ = nullptr);
  /// Every topic and timed wrench of every body to zero.
  CommandReply clearWrenches(Nanoseconds arrival);
  /// Every body to its initial state, wrenches cleared, divergences cleared; the clock keeps running.
  CommandReply reset(Nanoseconds arrival);
  /// Replaces a body's state (refused unless finite).
  CommandReply setState(std::size_t body, const State& state, Nanoseconds arrival);
  CommandReply pause(Nanoseconds arrival);
  CommandReply unpause(Nanoseconds arrival);
  /// Exactly `steps` steps of a paused world, whatever the catch-up cap. With its own clock (lockstep) the
  /// clock advances by them, inputs following their timeline; otherwise the clock stays and the inputs are
  /// those of the current step. Refused when not paused, for steps < 1, beyond max_body_steps_per_request,
  /// or past the end of time.
  CommandReply step(std::int64_t steps, Nanoseconds now);
  /// Lockstep only: clock back to step 0 at the start time, every body reset, nothing waiting.
  CommandReply rewind();
  /// Live settings, from the step of their arrival: a body's force models (damping, gravity; its step terms
  /// are assembled again, so turning gravity on adds the gravity term and off removes it), and the timeout of
  /// topic wrenches arriving from then on. Refused for non-finite or negative values.
  CommandReply setForceModel(std::size_t body, const ForceModel& forces, Nanoseconds arrival);
  CommandReply setWrenchTimeout(double seconds, Nanoseconds arrival);

  // ----- edits of the body list (world_edits.cpp): at once, on the state of stamp(), not queued -----
  /// Appends a body (Scene::addBody) with no input; its index, the last, goes to `index` when accepted.
  /// Refused, the world unchanged, for a non-finite state, an invalid shape or a colliding body placed
  /// inside another body or the environment (the message says which).
  CommandReply addBody(const BodyDefinition& body, const std::optional<CollisionShape>& shape,
                       std::size_t* index = nullptr);
  /// Removes a body with its inputs and its waiting commands; the later bodies, their inputs and their
  /// waiting commands move down one index. Refused for the only body.
  CommandReply removeBody(std::size_t body);

  // ----- queries -----
  const Scene& scene() const { return scene_; }
  /// Keeps each colliding body's contacts of the last step for its outputs (Scene::setRecordContacts).
  void setRecordContacts(bool record) { scene_.setRecordContacts(record); }
  std::size_t bodyCount() const { return scene_.bodyCount(); }
  double dt() const { return settings_.dt; }
  bool paused() const { return paused_; }
  bool ownsClock() const { return settings_.owns_clock; }
  /// Grid points passed since the start, integrated or not: the states belong to stamp().
  std::int64_t clockSteps() const { return clock_; }
  /// The stamp of the current state [ns].
  Nanoseconds stamp() const { return timeOfStep(clock_); }
  /// The stamp of step k on the current anchor [ns], saturated at end_of_time.
  Nanoseconds timeOfStep(std::int64_t k) const;
  /// The step a time falls on (never before the current anchor's step).
  std::int64_t stepAt(Nanoseconds time) const;
  /// The clock stopped at the last stamp the caller can represent.
  bool endOfTime() const { return end_of_time_; }
  const WorldCounters& counters() const { return counters_; }
  /// A body's topic wrench timed out (until its next wrench or a reset).
  bool wrenchTimedOut(std::size_t body) const { return inputs_[body].timed_out; }
  /// Arrival of the latest topic wrench on any body, or -1 when none came [ns].
  Nanoseconds lastWrenchArrival() const { return last_wrench_arrival_; }
  std::size_t pendingCommands() const { return pending_.size(); }
  /// The most steps one update() integrates (the catch-up caps over the running bodies); more due are dropped.
  std::int64_t updateBudget() const;

 private:
  Nanoseconds wallClock() const;  // settings_.wall_clock, or steady_clock

  static constexpr std::int64_t kForever = std::numeric_limits<std::int64_t>::max();

  struct TimedWrench {
    AppliedWrench wrench;
    std::int64_t start;  // first step it acts on
    std::int64_t end;    // first step it no longer acts on; kForever: until cleared
  };
  // A body's input sources (the Scene holds their sum for the current step).
  struct InputTimeline {
    AppliedWrench topic;
    std::int64_t topic_expiry = kForever;  // step at which the topic wrench drops to zero; kForever: never
    bool timed_out = false;
    bool scheduled = false;  // listed in scheduled_ (a flag, so that listing a body costs O(1))
    std::vector<TimedWrench> timed;
  };
  enum class CommandKind {
    kTopicWrench, kTimedWrench, kClearWrenches, kReset, kSetState, kPause, kUnpause, kSetForces, kSetWrenchTimeout
  };
  struct Command {
    CommandKind kind = CommandKind::kReset;
    std::size_t body = 0;
    Nanoseconds arrival = 0;
    AppliedWrench wrench;
    bool has_point = false;  // wrench.world.torque is about p_WQ, not the centre of mass
    Eigen::Vector3d p_WQ = Eigen::Vector3d::Zero();
    Nanoseconds start = 0;
    double duration = 0.0;  // kTimedWrench: its duration; kSetWrenchTimeout: the timeout [s]
    State state;
    ForceModel forces;
  };

  static Command command(CommandKind kind, std::size_t body, Nanoseconds arrival);
  static Command wrenchCommand(CommandKind kind, std::size_t body, const AppliedWrench& wrench, Nanoseconds arrival,
                               const Eigen::Vector3d* p_WQ);
  CommandReply submit(const Command& command);
  // The command's wrench about the body's centre of mass now; false if that overflowed.
  bool aboutCentreOfMass(const Command& command, AppliedWrench& wrench);
  void apply(const Command& command, UpdateResult* result);
  // A wall-time budget read between chunks of steps: the next chunk is not begun where it would end past
  // the deadline if it took as long as the last one did, so an update or a request overruns its budget by
  // no more than the variation of one chunk's cost (in a pile a chunk is one step), not by a whole chunk.
  class ChunkTimer {
   public:
    ChunkTimer(const World& world, double budget_seconds);  // reads the wall clock: the budget starts now
    bool limited() const { return deadline_ != kNoDeadline; }
    bool nextWouldOverrun();  // reads the wall clock after a chunk
   private:
    const World& world_;
    Nanoseconds deadline_, last_;
  };
  // Moves the clock to `target`, integrating at most `budget` steps (the rest pass without motion) unless
  // `integrate_paused` makes a paused world integrate (step N in lockstep). With a `timer`, it integrates in
  // chunks and, once the timer says the next chunk would overrun, integrates no more (budget 0).
  void advanceClockTo(std::int64_t target, std::int64_t& budget, bool integrate_paused, UpdateResult& result,
                      ChunkTimer* timer = nullptr);
  static constexpr Nanoseconds kNoDeadline = std::numeric_limits<Nanoseconds>::max();
  std::int64_t runningCount() const;  // the running bodies, at least 1 (the caps divide by it)
  std::int64_t chunkSteps() const;    // steps per chunk: kRequestChunkBodySteps (weighted) body-steps
  std::int64_t nextEvent() const;
  void refreshInput(std::size_t body);
  void expireAt(std::int64_t k, UpdateResult& result);
  void clearWrenchesNow();
  void resetNow();
  void anchor(Nanoseconds time);

  WorldSettings settings_;
  Scene scene_;
  std::vector<InputTimeline> inputs_;
  std::vector<std::size_t> scheduled_;  // bodies with timed wrenches or a pending expiry
  std::vector<Command> pending_;
  WorldCounters counters_;
  Nanoseconds start_time_ = 0;
  Nanoseconds anchor_time_ = 0;     // the stamp of step anchor_step_
  std::int64_t anchor_step_ = 0;
  std::int64_t last_step_ = 0;      // the last step whose stamp is ≤ end_of_time on this anchor
  Nanoseconds last_now_ = 0;        // the latest time update() saw, to detect backward jumps
  Nanoseconds last_wrench_arrival_ = -1;
  std::int64_t clock_ = 0;
  std::int64_t dt_ns_ = 0;          // dt in whole nanoseconds when it is one (exact stamps), else 0
  bool started_ = false;
  bool paused_ = false;
  bool end_of_time_ = false;
};

}  // namespace rigid_body
