// The index of the warm points' pair runs (src/contact/pair_runs.hpp): every run found where it lies,
// whatever the keys' order and however their hashes collide; a list whose pair's entries do not follow
// each other refused; and the contact step's lookups (warm starts) unchanged by it, which the thread-bits
// and regime tests check end to end.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "../../src/contact/pair_runs.hpp"

namespace {

using rigid_body::contact::PairRuns;

TEST(PairRuns, FindsEveryRunOfAListGroupedByPairInAnyOrder) {
  // Keys in no sorted order, runs of 1 to 4, keys that differ by multiples of large powers of two (their
  // hashes' low bits collide in a small table) and the largest key a pair can have below the empty mark.
  const std::vector<std::uint64_t> run_keys = {907, 3, std::uint64_t{1} << 40, (std::uint64_t{1} << 40) + (1u << 20),
                                               0, 12, (std::uint64_t{1} << 62), ~std::uint64_t{0} - 1};
  std::vector<std::uint64_t> keys;
  for (std::size_t r = 0; r < run_keys.size(); ++r) {
    for (std::size_t i = 0; i <= r % 4; ++i) keys.push_back(run_keys[r]);
  }
  PairRuns runs;
  ASSERT_TRUE(runs.build(keys.size(), [&](std::size_t i) { return keys[i]; }));
  std::size_t begin = 0;
  for (std::size_t r = 0; r < run_keys.size(); ++r) {
    const std::size_t end = begin + r % 4 + 1;
    EXPECT_EQ(runs.find(run_keys[r]), std::make_pair(begin, end)) << "run " << r;
    begin = end;
  }
  for (const std::uint64_t absent : {std::uint64_t{1}, std::uint64_t{906}, std::uint64_t{1} << 41}) {
    const auto run = runs.find(absent);
    EXPECT_EQ(run.first, run.second) << absent;
  }
}

TEST(PairRuns, FindsRunsAmongThousandsOfPairs) {
  // A scene's worth of pairs: keys a·n + b of objects a < b, each pair with a run of two.
  const std::uint64_t objects = 20000;
  std::vector<std::uint64_t> keys;
  for (std::uint64_t a = 0; a < 3000; ++a) keys.insert(keys.end(), 2, a * objects + (a * 7919) % objects);
  PairRuns runs;
  ASSERT_TRUE(runs.build(keys.size(), [&](std::size_t i) { return keys[i]; }));
  for (std::size_t i = 0; i < keys.size(); i += 2) EXPECT_EQ(runs.find(keys[i]), std::make_pair(i, i + 2));
}

TEST(PairRuns, RefusesAPairWhoseEntriesDoNotFollowEachOther) {
  const std::vector<std::uint64_t> keys = {5, 5, 9, 5};
  PairRuns runs;
  EXPECT_FALSE(runs.build(keys.size(), [&](std::size_t i) { return keys[i]; }));
  EXPECT_EQ(runs.find(9).first, runs.find(9).second);  // holds nothing after a refusal
}

TEST(PairRuns, AnEmptyListHoldsNothing) {
  PairRuns runs;
  EXPECT_TRUE(runs.build(0, [](std::size_t) { return std::uint64_t{0}; }));
  EXPECT_EQ(runs.find(0), std::make_pair(std::size_t{0}, std::size_t{0}));
}

}  // namespace
