#include "island_sleep.hpp"

#include <algorithm>

namespace rigid_body {
namespace contact {

void IslandSleep::reset(std::size_t bodies) {
  island_of_.assign(bodies, kAwake);
  members_.assign(bodies, {});
  quiet_time_.assign(bodies, 0.0);
  sleeping_ = 0;
}

void IslandSleep::wake(std::size_t k, std::vector<std::size_t>* woken) {
  const std::size_t island = island_of_[k];
  if (island == kAwake) return;
  for (std::size_t member : members_[island]) {
    island_of_[member] = kAwake;
    quiet_time_[member] = 0.0;
    if (woken != nullptr) woken->push_back(member);
  }
  sleeping_ -= members_[island].size();
  members_[island].clear();
}

std::size_t IslandSleep::root(std::size_t k) {
  while (parent_[k] != k) {
    parent_[k] = parent_[parent_[k]];  // path halving
    k = parent_[k];
  }
  return k;
}

void IslandSleep::update(const std::vector<std::pair<std::size_t, std::size_t>>& links, const std::vector<char>& quiet,
                         const std::vector<char>& supported, double h, double sleep_time) {
  const std::size_t n = island_of_.size();
  parent_.resize(n);
  for (std::size_t k = 0; k < n; ++k) parent_[k] = k;
  for (const auto& link : links) {
    const std::size_t a = root(link.first), b = root(link.second);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  // Per root: the shortest quiet time of its bodies and whether any of them is supported.
  island_quiet_.assign(n, sleep_time);
  island_supported_.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    if (asleep(k)) continue;
    quiet_time_[k] = quiet[k] ? quiet_time_[k] + h : 0.0;
    const std::size_t r = root(k);
    island_quiet_[r] = std::min(island_quiet_[r], quiet_time_[k]);
    island_supported_[r] = island_supported_[r] || supported[k];
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (asleep(k)) continue;
    const std::size_t r = root(k);
    if (!island_supported_[r] || island_quiet_[r] < sleep_time) continue;
    island_of_[k] = r;
    members_[r].push_back(k);
    ++sleeping_;
  }
}

}  // namespace contact
}  // namespace rigid_body
