// Islands and sleeping (docs/contact.md, "Sleeping"): the colliding bodies linked by touching contacts form
// islands; an island whose every body has stayed quiet for the sleep time is put to sleep as a whole (its
// bodies skip the free step, detection and the solve, and keep their state), and wakes as a whole.
// Nothing here knows a shape or a solver: it sees body indices, links between them and per-body flags.
#pragma once

#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace rigid_body {
namespace contact {

class IslandSleep {
 public:
  /// `bodies` colliding bodies, all awake.
  void reset(std::size_t bodies);

  bool asleep(std::size_t k) const { return island_of_[k] != kAwake; }
  bool anyAsleep() const { return sleeping_ > 0; }
  std::size_t sleepingBodies() const { return sleeping_; }

  /// Wakes the island body k sleeps in (nothing if it is awake); its bodies start their quiet time anew and
  /// are appended to `woken` if given.
  void wake(std::size_t k, std::vector<std::size_t>* woken = nullptr);

  /// After a step of h: `links` are the pairs of awake bodies in contact (indices of colliding bodies),
  /// `quiet[k]` whether body k was quiet at the step's end and `supported[k]` whether it has a contact at
  /// all (with a body or the environment). An awake body's quiet time grows by h while it is quiet and
  /// restarts otherwise; every island (connected by `links`) that has a supported body and whose bodies
  /// have all been quiet for `sleep_time` falls asleep. Islands are found by union–find with the smaller
  /// index as root, so the result does not depend on the order of `links`.
  void update(const std::vector<std::pair<std::size_t, std::size_t>>& links, const std::vector<char>& quiet,
              const std::vector<char>& supported, double h, double sleep_time);

 private:
  static constexpr std::size_t kAwake = std::numeric_limits<std::size_t>::max();
  std::size_t root(std::size_t k);
  std::vector<std::size_t> island_of_;  // per body: its sleeping island's root, or kAwake
  std::vector<std::vector<std::size_t>> members_;  // per root of a sleeping island: its bodies
  std::vector<double> quiet_time_;      // per body [s]
  std::size_t sleeping_ = 0;
  // Scratch of update().
  std::vector<std::size_t> parent_;
  std::vector<double> island_quiet_;
  std::vector<char> island_supported_;
};

}  // namespace contact
}  // namespace rigid_body
