// Per-body ROS handles (subscribers, service servers, sensors) that need their body's current index while
// bodies are spawned and removed. Each entry lives on the heap, so the pointer a callback holds stays valid;
// a spawn appends, and erase keeps every entry's index in step with the scene's body list.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace rigid_body_ros {

template <class Handles>
class BodyList {
 public:
  struct Entry {
    std::size_t body = 0;  ///< the body's index in the scene now (the callbacks read it)
    Handles handles;
  };

  /// A new entry for the body at `body`, the scene's last (bodies join at the end).
  Entry& append(std::size_t body) {
    entries_.push_back(std::make_unique<Entry>());
    entries_.back()->body = body;
    return *entries_.back();
  }
  /// Drops the entries of `body` (their handles shut down) and moves the later ones down one index.
  void erase(std::size_t body) {
    entries_.erase(std::remove_if(entries_.begin(), entries_.end(), [body](const auto& e) { return e->body == body; }),
                   entries_.end());
    for (const auto& entry : entries_) entry->body -= entry->body > body ? 1 : 0;
  }
  std::size_t size() const { return entries_.size(); }
  /// The entries, in the order they were appended.
  const std::vector<std::unique_ptr<Entry>>& entries() const { return entries_; }

 private:
  std::vector<std::unique_ptr<Entry>> entries_;
};

}  // namespace rigid_body_ros
