#include "rigid_body_sim/ros/output_schedule.hpp"

#include <limits>

namespace rigid_body_ros {

bool OutputSchedule::due(rigid_body::Nanoseconds now, rigid_body::Nanoseconds period) {
  const bool on_grid = due_ >= 0 && now >= last_;
  if (on_grid && now < due_) return false;
  constexpr rigid_body::Nanoseconds kLatest = std::numeric_limits<rigid_body::Nanoseconds>::max();
  const rigid_body::Nanoseconds from = on_grid && now - due_ < period ? due_ : now;
  due_ = from > kLatest - period ? kLatest : from + period;
  last_ = now;
  return true;
}

}  // namespace rigid_body_ros
