// When an output with its own rate is due: on a grid of its period in simulated time (pure: tested without
// a master). The node's outputs go out at ticks; an output slower than the ticks goes out at the first tick
// at or after each point of its grid.
#pragma once

#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class OutputSchedule {
 public:
  /// Whether the output, every `period` of simulated time [ns] (> 0; it may change between calls, as a live
  /// rate does, and then counts from the last grid point served), is due at `now` (a tick's stamp): one
  /// period after the grid point last served, not after the tick that served it, so that a late tick does
  /// not push every later one back and the output keeps its rate on average. The first call, a rewind (now before the last one) and falling a
  /// whole period behind are due at once and start the grid again at now. Sums saturate at the largest
  /// stamp.
  bool due(rigid_body::Nanoseconds now, rigid_body::Nanoseconds period);

 private:
  rigid_body::Nanoseconds last_ = -1;  ///< the stamp of the last time it was due
  rigid_body::Nanoseconds grid_ = -1;  ///< the grid point last served
};

}  // namespace rigid_body_ros
