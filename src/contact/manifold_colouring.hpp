// Manifolds and their colours, the order in which the lane solver sweeps a block of islands
// (docs/contact.md, "The solver's lanes"; the words manifold, colour and block: docs/architecture.md).
//
// A manifold is a run of up to four consecutive contacts between the same two solver bodies (a pair's
// points, as detection lists them); one lane solves its points one after another. Two manifolds of one
// colour share no body other than the environment, so a colour's manifolds can be solved side by side in the
// lanes of a vector and in any order with the same bits: each reads and writes only its own bodies. Colours
// are given greedily, manifold by manifold in the lists' order, the lowest colour neither body has yet (the
// environment holds none), as Box2D v3's constraint graph does. A body in more than 64 manifolds' worth of
// colours sends the rest to an overflow colour, solved last, one manifold at a time.
//
// The colour of a manifold depends only on the manifolds of its own island before it (islands share no
// body), so each island is swept in the same order, colour by colour, whatever other islands share its block.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "contact_solver.hpp"

namespace rigid_body {
namespace contact {

/// Up to kMaxManifoldPoints consecutive contacts between the same two solver bodies.
struct Manifold {
  std::size_t first = 0;    ///< its first contact's index in the solver's list
  std::uint32_t count = 0;  ///< its contacts: first, first + 1, ..., first + count − 1
  std::uint32_t island = 0; ///< which of the colouring's islands it belongs to
};

constexpr std::size_t kMaxManifoldPoints = 4;

/// How many contacts form the manifold that starts at contacts[first]: those that follow it before `end`
/// between the same two bodies, up to kMaxManifoldPoints.
inline std::uint32_t manifoldLength(const std::vector<SolverContact>& contacts, std::size_t first, std::size_t end) {
  std::uint32_t count = 0;
  while (first + count < end && count < kMaxManifoldPoints && contacts[first + count].a == contacts[first].a &&
         contacts[first + count].b == contacts[first].b) {
    ++count;
  }
  return count;
}

class ManifoldColouring {
 public:
  /// Colours with a body mask; manifolds that find none free go to the overflow colour kColours.
  static constexpr std::size_t kColours = 64;

  /// Splits the contacts of `islands` (ranges of `contacts` over disjoint bodies; island i of the result is
  /// islands[i]) into manifolds and colours them. `bodies` is the solver's body count.
  void colour(const std::vector<SolverContact>& contacts, const SolveRange* islands, std::size_t count,
              std::size_t bodies);
  /// The manifolds colour by colour (the overflow colour last), each colour's in the lists' order.
  const std::vector<Manifold>& manifolds() const { return ordered_; }
  /// Colour c's manifolds are manifolds()[colourStart(c)] up to manifolds()[colourStart(c + 1)] (exclusive),
  /// for c = 0 … kColours (the overflow).
  std::size_t colourStart(std::size_t colour) const { return colour_start_[colour]; }

 private:
  std::vector<Manifold> found_, ordered_;
  std::vector<std::uint8_t> colour_of_;      // per found manifold
  std::vector<std::uint64_t> used_;          // per solver body: the colours of its manifolds so far
  std::vector<std::size_t> colour_start_, next_;
};

}  // namespace contact
}  // namespace rigid_body
