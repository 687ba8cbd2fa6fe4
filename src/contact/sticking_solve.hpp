// An island solved at once as if all its points stuck (docs/contact.md, "An island that sticks, solved at
// once"): where the sweeps leave an island unconverged, its velocity rows are solved directly, and the
// result is kept if every point then pushes and holds within its friction disc. Internal to the contact
// solver.
#pragma once

#include <Eigen/SparseCore>
#include <cstddef>
#include <utility>
#include <vector>

#include "contact_solver.hpp"

namespace rigid_body {
namespace contact {

/// What solveStickingIsland did: left the island to the sweeps without a factorisation (too large, sliding
/// or already held), solved it and found the result refused (nothing changed), or applied it.
enum class StickingOutcome { kNotTried, kRefused, kSolved };

/// What a direct solve keeps between calls (its lists), so that a thread's solves reuse their memory.
struct StickingScratch {
  std::vector<std::size_t> row_of;   // per contact direction (3 k + d): its row, or kNoRow
  std::vector<std::size_t> contact;  // per row: its contact direction (3 k + d)
  std::vector<Eigen::Triplet<double>> entries;    // K's lower triangle
  std::vector<std::vector<std::size_t>> rows_on;  // per body of the range: its contacts, 2 k (side a) or 2 k + 1 (b)
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> velocities;  // per body of the range: (v, ω) before
  std::vector<Eigen::Vector3d> impulses;  // per point of the range: (normal, two tangents) before
  std::vector<char> let_go;               // per point of the range: no rows, its impulses zero
};

/// Solves the rows of `range` (each point's normal, and its two tangents where it has friction) as
/// equalities, K λ = K λ₀ + target − v with K = J M⁻¹ Jᵀ (every point pushing and sticking), in the
/// least-squares sense (targets no rigid motion meets get the nearest velocities), and applies the first of
/// two solutions that keeps every point's normal impulse at or above its floor and its friction within μ
/// times it: the least-norm impulses, else the least change from the sweeps' impulses λ₀; failing both, the
/// points that pulled are let go (no rows, zero impulses) and the rest solved again, three solves in all. A
/// point apart by more than 1e-9 m that the sweeps left unpressed is no row; the result is kept only if such
/// points and those let go then close no more than their targets allow within the step `dt` [s]. kSolved if
/// applied, kRefused if not. Not tried (kNotTried) for more than 256 points,
/// where a point of a pair that already touched slipped in the sweeps' last friction update with its
/// friction at the disc's edge, faster than `sliding_speed` [m/s] and than a tenth of the largest normal
/// speed a point's impulse makes in the island (fₙ / m_n), where every row already holds to 1e-13 of
/// the island's impulses, or where every point is left out (no rows). K is singular (a face of four points has twelve rows and six degrees of freedom):
/// docs/references.md §4.16.
/// A point shallower than half the resting depth (1e-9 m) is sunk to it within the step.
StickingOutcome solveStickingIsland(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                                    const SolveRange& range, double dt, double sliding_speed, StickingScratch& scratch);

}  // namespace contact
}  // namespace rigid_body
