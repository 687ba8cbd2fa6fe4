#include "rigid_body_sim/ros/output_schedule.hpp"

#include <limits>

namespace rigid_body_ros {

bool OutputSchedule::due(rigid_body::Nanoseconds now, rigid_body::Nanoseconds period) {
  const bool on_grid = grid_ >= 0 && now >= last_;
  constexpr rigid_body::Nanoseconds kLatest = std::numeric_limits<rigid_body::Nanoseconds>::max();
  // The next point is computed from the current period at each call, so a live rate change counts from the
  // last point served: a rate turned from 0.001 Hz back to 20 Hz is due 50 ms after the last output.
  const rigid_body::Nanoseconds next = on_grid ? (grid_ > kLatest - period ? kLatest : grid_ + period) : now;
  if (on_grid && now < next) return false;
  grid_ = on_grid && now - next < period ? next : now;
  last_ = now;
  return true;
}

}  // namespace rigid_body_ros
