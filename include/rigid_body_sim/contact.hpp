// Contact between bodies and with the static environment: how a scene declares it, how the solver is set
// and what one step reports. The method is in docs/contact.md.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"

namespace rigid_body {

/// The contact solver's settings (docs/contact.md explains each).
struct ContactSettings {
  int iterations = 20;                      ///< sequential-impulse sweeps over the contacts per step
  /// [s] the step `iterations` is meant for: a longer step may sweep an island that has not converged as
  /// often per simulated second (sweepsPerStep); 0: `iterations` at every step
  double iterations_dt = 1e-3;
  int position_iterations = 4;              ///< position-projection sweeps for what penetration remains
  double restitution_threshold = 0.05;      ///< [m/s] an approach slower than this does not bounce (e → 0)
  double penetration_slop = 1e-4;           ///< [m] penetration left alone by the position projection
  double position_correction = 0.2;         ///< fraction of the penetration beyond the slop removed per step
  bool event_location = true;               ///< locate an isolated impact in time within the step
  bool continuous = true;                   ///< sweep fast bodies so that they cannot pass thin obstacles
  double event_tolerance = 1e-12;           ///< [s] width of the bracket that locates an impact
  bool sleep = true;                        ///< put islands at rest to sleep (docs/contact.md, "Sleeping")
  double sleep_time = 0.5;                  ///< [s] how long an island stays quiet before it sleeps
  /// keep a pair's points from one detection to the next while it has not moved relative to itself by more
  /// than a thousandth of the slop (docs/contact.md, step 2, "Points reused at rest")
  bool reuse_points = true;
};

/// Throws std::invalid_argument naming the setting for one out of range.
void validateContactSettings(const ContactSettings& settings);

/// The sweeps the resting solve may take in a step of h: `iterations`, or at a step longer than
/// `iterations_dt` iterations × h / iterations_dt (docs/contact.md, step 5), at most kMostSweepsPerStep
/// (ten times the largest `iterations`: an iterations_dt of 1e-300 s asks for more sweeps than a step can
/// take, and a step cannot be cut short).
int sweepsPerStep(const ContactSettings& settings, double h);
constexpr int kMostSweepsPerStep = 10000;

/// What a scene declares about contact: the static environment and, per body, its collision shape or none.
struct ContactSetup {
  std::vector<CollisionShape> environment;
  std::vector<std::optional<CollisionShape>> bodies;  ///< one per body; empty: no body collides
  ContactSettings settings;

  /// True when at least one body collides: only then does the scene step contact at all.
  bool active() const;
};

/// The other side of a contact: another body or a shape of the environment.
struct ContactPartner {
  bool is_body = false;
  std::size_t index = 0;  ///< body index, or index into ContactSetup::environment
};

/// One contact point of a body after a step, in world axes.
struct Contact {
  ContactPartner other;
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();  ///< the point on this body's surface [m]
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();   ///< from the other side towards this body
  double penetration = 0.0;                              ///< depth at the end of the free step [m], ≥ 0 when touching
  double normal_impulse = 0.0;                           ///< on this body along normal_W during the step [N s]
  Eigen::Vector3d friction_impulse_W = Eigen::Vector3d::Zero();  ///< on this body, tangent to the contact [N s]
};

/// An impact located in time within a step (event location), for logs and tests.
struct ImpactEvent {
  double time = 0.0;  ///< since the scene's start [s]
  std::size_t body = 0;
  ContactPartner other;
  double approach_speed = 0.0;  ///< normal speed of approach just before the impact [m/s]
};

/// Scene-wide contact figures since the last reset.
struct ContactStatistics {
  std::int64_t located_impacts = 0;    ///< impacts resolved at their located time
  std::int64_t swept_impacts = 0;      ///< impacts found by the swept test (a fast body would have passed)
  std::int64_t split_steps = 0;        ///< steps taken in halves: a fast body had something near its path
  std::int64_t refused_steps = 0;      ///< steps whose contact result was not finite (bodies kept their state)
  double max_penetration = 0.0;        ///< deepest penetration seen at the end of a free step [m]
  std::int64_t out_of_range = 0;       ///< bodies now beyond 1e6 m of the origin: out of the contact world
  std::int64_t sleeping_bodies = 0;    ///< bodies asleep now
  std::int64_t wakes = 0;              ///< islands woken since the last reset
};

}  // namespace rigid_body
