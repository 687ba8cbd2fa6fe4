// ROS time and the core's integer nanoseconds, both ways, without ros::Duration arithmetic (which throws
// past 2^31 s) and without ever throwing: ros::Time holds [0, 2^32) s, and the core clock stops at its end.
#pragma once

#include <ros/time.h>

#include <cstdint>

#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

/// The last instant ros::Time can hold: (2^32 − 1) s + 999 999 999 ns.
constexpr rigid_body::Nanoseconds kEndOfRosTime = 4294967295LL * 1000000000LL + 999999999LL;

inline rigid_body::Nanoseconds toNanoseconds(const ros::Time& time) {
  return static_cast<rigid_body::Nanoseconds>(time.toNSec());  // < 2^63: ros::Time's seconds are 32 bits
}

/// Clamped into [0, kEndOfRosTime].
inline ros::Time toRosTime(rigid_body::Nanoseconds time) {
  ros::Time result;
  result.fromNSec(static_cast<std::uint64_t>(time < 0 ? 0 : (time > kEndOfRosTime ? kEndOfRosTime : time)));
  return result;
}

inline double toSeconds(rigid_body::Nanoseconds time) { return static_cast<double>(time) * 1e-9; }

}  // namespace rigid_body_ros
