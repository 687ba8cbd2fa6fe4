#include "manifold_colouring.hpp"

namespace rigid_body {
namespace contact {

void ManifoldColouring::colour(const std::vector<SolverContact>& contacts, const SolveRange* islands,
                               std::size_t count, std::size_t bodies) {
  found_.clear();
  colour_of_.clear();
  used_.resize(bodies);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t s = islands[i].body_begin; s < islands[i].body_end; ++s) used_[s] = 0;
  }
  used_[kEnvironment] = 0;
  std::size_t colour_count[kColours + 1] = {};
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t k = islands[i].contact_begin; k < islands[i].contact_end;) {
      const SolverContact& c = contacts[k];
      const Manifold m{k, manifoldLength(contacts, k, islands[i].contact_end), static_cast<std::uint32_t>(i)};
      k += m.count;
      // The environment holds no colour: it is never written, so any number of manifolds may touch it.
      const std::uint64_t a_used = c.a == kEnvironment ? 0 : used_[c.a];
      const std::uint64_t b_used = c.b == kEnvironment ? 0 : used_[c.b];
      const std::uint64_t free = ~(a_used | b_used);
      std::size_t colour = kColours;
      if (free != 0) {
        colour = static_cast<std::size_t>(__builtin_ctzll(free));
        if (c.a != kEnvironment) used_[c.a] |= std::uint64_t{1} << colour;
        if (c.b != kEnvironment) used_[c.b] |= std::uint64_t{1} << colour;
      }
      found_.push_back(m);
      colour_of_.push_back(static_cast<std::uint8_t>(colour));
      ++colour_count[colour];
    }
  }
  // Counted into place: colour by colour, each colour's manifolds in the order they were found.
  colour_start_.assign(kColours + 2, 0);
  for (std::size_t c = 0; c <= kColours; ++c) colour_start_[c + 1] = colour_start_[c] + colour_count[c];
  next_.assign(colour_start_.begin(), colour_start_.end() - 1);
  ordered_.resize(found_.size());
  for (std::size_t m = 0; m < found_.size(); ++m) ordered_[next_[colour_of_[m]]++] = found_[m];
}

}  // namespace contact
}  // namespace rigid_body
