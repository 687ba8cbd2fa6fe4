// Where each pair's run lies in a list whose entries are grouped by pair but not sorted (the warm points,
// in the order the solve made them): an open-addressing hash table (linear probing) from a pair's key to
// its run [begin, end). A lookup costs one hash and a probe or two where a binary search of a sorted list
// costs log₂ n steps, and the list need not be sorted each step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace rigid_body {
namespace contact {

class PairRuns {
 public:
  /// Indexes entries [0, count) by key_of(i). Returns false, holding nothing, if some pair's entries do not
  /// all follow each other (the caller then sorts the list by key and builds again).
  template <class KeyOf>
  bool build(std::size_t count, KeyOf key_of) {
    // The runs first (one pass over the list), then a table for that many: a pair's several entries take
    // one slot.
    runs_.clear();
    for (std::size_t begin = 0; begin < count;) {
      const std::uint64_t key = key_of(begin);
      std::size_t end = begin + 1;
      while (end < count && key_of(end) == key) ++end;
      runs_.push_back(Slot{key, static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(end)});
      begin = end;
    }
    std::size_t capacity = 16;
    while (capacity < 2 * runs_.size()) capacity *= 2;  // at most half full: short probes
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    for (const Slot& run : runs_) {
      Slot& slot = slots_[probe(run.key)];
      if (slot.key == run.key) {  // a second run of the same pair
        slots_.clear();
        return false;
      }
      slot = run;
    }
    return true;
  }

  /// The run of `key`, or an empty one.
  std::pair<std::size_t, std::size_t> find(std::uint64_t key) const {
    if (slots_.empty()) return {0, 0};
    const Slot& slot = slots_[probe(key)];
    return slot.key == key ? std::make_pair(std::size_t{slot.begin}, std::size_t{slot.end})
                           : std::make_pair(std::size_t{0}, std::size_t{0});
  }

  void clear() { slots_.clear(); }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // no pair's key (a product of object counts)
  // 16 bytes: a run's bounds in 32 bits each (a list of the step's points or pairs, far fewer than 2³²).
  struct Slot {
    std::uint64_t key = kEmpty;
    std::uint32_t begin = 0, end = 0;
  };
  // The slot that holds `key`, or the empty one where it would go (Fibonacci hashing: Knuth, TAOCP vol. 3,
  // 6.4, the multiplier 2⁶⁴/φ).
  std::size_t probe(std::uint64_t key) const {
    std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & mask_;
    while (slots_[i].key != key && slots_[i].key != kEmpty) i = (i + 1) & mask_;
    return i;
  }
  std::vector<Slot> slots_;
  std::vector<Slot> runs_;  // build's scratch
  std::size_t mask_ = 0;
};

}  // namespace contact
}  // namespace rigid_body
