// OutputSchedule: an output with its own rate goes out at the ticks on a grid of its period in simulated
// time, so that it keeps its rate on average whatever the ticks.
#include <gtest/gtest.h>

#include <vector>

#include "rigid_body_sim/ros/output_schedule.hpp"

using rigid_body::Nanoseconds;
using rigid_body_ros::OutputSchedule;

namespace {
constexpr Nanoseconds kMs = 1000000;

// The ticks at which the output went out, of ticks every `tick` from `start` for `count` ticks.
std::vector<Nanoseconds> dueTicks(OutputSchedule& schedule, Nanoseconds start, Nanoseconds tick, int count,
                                  Nanoseconds period) {
  std::vector<Nanoseconds> due;
  for (int k = 0; k < count; ++k) {
    if (schedule.due(start + k * tick, period)) due.push_back(start + k * tick);
  }
  return due;
}
}  // namespace

// 30 Hz on 100 Hz ticks: the grid 0, 33.3, 66.7, … ms has exactly 30 points in a second, each served by
// the first tick at or after it (0, 40, 70, 100, …). Counting the period from the tick that served the last
// one instead (0, 40, 80, …) gives 25: that drift is what the grid prevents.
TEST(OutputSchedule, KeepsItsRateOnATickGridItDoesNotDivide) {
  OutputSchedule schedule;
  const std::vector<Nanoseconds> due = dueTicks(schedule, 0, 10 * kMs, 100, 1000000000 / 30);
  ASSERT_EQ(due.size(), 30u);
  EXPECT_EQ(due[0], 0);
  EXPECT_EQ(due[1], 40 * kMs);
  EXPECT_EQ(due[2], 70 * kMs);
  EXPECT_EQ(due[3], 100 * kMs);
}

TEST(OutputSchedule, AtTheTickRateIsDueEveryTickAndAtATenthEveryTenth) {
  OutputSchedule every, tenth;
  EXPECT_EQ(dueTicks(every, 5 * kMs, 10 * kMs, 50, 10 * kMs).size(), 50u);
  const std::vector<Nanoseconds> due = dueTicks(tenth, 5 * kMs, 10 * kMs, 50, 100 * kMs);
  ASSERT_EQ(due.size(), 5u);
  for (std::size_t i = 0; i < due.size(); ++i) EXPECT_EQ(due[i], 5 * kMs + static_cast<Nanoseconds>(i) * 100 * kMs);
}

// A tick a whole period late is due at once and starts the grid again there (no burst to catch up); a rewind
// of simulated time (reset_time) is due at once too.
TEST(OutputSchedule, ALateTickAndARewindStartTheGridAgain) {
  OutputSchedule schedule;
  const Nanoseconds period = 100 * kMs;
  EXPECT_TRUE(schedule.due(0, period));
  EXPECT_FALSE(schedule.due(50 * kMs, period));
  EXPECT_TRUE(schedule.due(450 * kMs, period));   // four periods late: once
  EXPECT_FALSE(schedule.due(500 * kMs, period));  // not again until 550
  EXPECT_TRUE(schedule.due(550 * kMs, period));
  EXPECT_TRUE(schedule.due(10 * kMs, period));    // rewound
  EXPECT_FALSE(schedule.due(60 * kMs, period));
  EXPECT_TRUE(schedule.due(110 * kMs, period));
}

// A live rate change counts from the last point served: a schedule that kept the next due time of the old
// period would stay silent for 1000 s after a rate of 0.001 Hz was turned back up.
TEST(OutputSchedule, APeriodChangedLiveCountsFromTheLastPointServed) {
  OutputSchedule schedule;
  EXPECT_TRUE(schedule.due(0, 100 * kMs));
  EXPECT_FALSE(schedule.due(10 * kMs, 20 * kMs));
  EXPECT_TRUE(schedule.due(20 * kMs, 20 * kMs));
  EXPECT_TRUE(schedule.due(40 * kMs, 20 * kMs));
  OutputSchedule slowed;
  const Nanoseconds kThousandSeconds = 1000000 * kMs;
  EXPECT_TRUE(slowed.due(0, kThousandSeconds));
  EXPECT_FALSE(slowed.due(10 * kMs, kThousandSeconds));
  EXPECT_FALSE(slowed.due(40 * kMs, 50 * kMs));  // back to 20 Hz: due at 50 ms
  EXPECT_TRUE(slowed.due(50 * kMs, 50 * kMs));
  EXPECT_FALSE(slowed.due(60 * kMs, 50 * kMs));
  EXPECT_TRUE(slowed.due(100 * kMs, 50 * kMs));
}
