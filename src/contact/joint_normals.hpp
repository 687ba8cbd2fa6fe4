// A manifold's normal impulses solved together (docs/contact.md, "A face's normals together"): the readable
// form, and the matrix the lane solver applies. Internal to the contact solver.
#pragma once

#include <cstddef>
#include <vector>

#include "contact_solver.hpp"
#include "manifold_colouring.hpp"

namespace rigid_body {
namespace contact {

/// A manifold's K⁺, symmetric: its upper triangle, row by row (entry (p, q) at jointEntry(p, q)).
constexpr std::size_t kJointEntries = kMaxManifoldPoints * (kMaxManifoldPoints + 1) / 2;
using JointInverse = double[kJointEntries];
constexpr std::size_t jointEntry(std::size_t p, std::size_t q) {
  return p <= q ? p * kMaxManifoldPoints - p * (p - 1) / 2 + (q - p) : jointEntry(q, p);
}

/// K⁺ of the normal rows of `count` consecutive contacts of one pair (K_ij = J_i M⁻¹ J_jᵀ, its least-norm
/// inverse over the face's three normal velocity coordinates) into `inverse`, rows and columns beyond
/// `count` zero. False, and `inverse` untouched, where the manifold is not solved together: fewer than two
/// points, three or four points near one line, or a coupling too ill-conditioned to invert.
bool jointNormalInverse(const SolverContact* points, std::size_t count, double inverse_mass_a,
                        double inverse_mass_b, JointInverse& inverse);

/// A face is left to its points while each point's residual would move its impulse by no more than this
/// fraction of it (normal mass × |target − v_n| ≤ kFaceAtRest λ): a warm start that already holds it, as for
/// a box resting alone, needs neither K⁺ nor the update. The solve's own tolerance within its sweeps.
constexpr double kFaceAtRest = 1e-14;

/// The readable solver's manifolds: runs of up to kMaxManifoldPoints consecutive contacts of one pair in
/// [begin, end), as the lane solver's colouring forms them. K⁺ is found the first time a face is not at
/// rest (`inverted`), and `joint` says whether it has one.
struct JointManifold {
  std::size_t first = 0, count = 0;
  bool inverted = false, joint = false;
  JointInverse inverse = {};
};
void jointManifolds(const std::vector<SolverContact>& contacts, std::size_t begin, std::size_t end,
                    std::vector<JointManifold>& manifolds);

/// One joint update of a manifold's normal impulses: the increments K⁺ (target − v_n) taken together if the
/// face is not at rest, has a K⁺ and none of them leaves an impulse below its floor, else none. True if
/// taken; raises `largest_change` to the largest increment's size.
bool solveJointNormals(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                       JointManifold& manifold, double& largest_change);

}  // namespace contact
}  // namespace rigid_body
