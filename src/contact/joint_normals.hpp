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

/// The readable solver's manifolds: runs of up to kMaxManifoldPoints consecutive contacts of one pair in
/// [begin, end), as the lane solver's colouring forms them, and each one's K⁺ where it has one.
struct JointManifold {
  std::size_t first = 0, count = 0;
  bool joint = false;
  JointInverse inverse = {};
};
void jointManifolds(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                    std::size_t begin, std::size_t end, std::vector<JointManifold>& manifolds);

/// One joint update of a manifold's normal impulses: the increments K⁺ (target − v_n) taken together if
/// none leaves an impulse below its floor, else none. True if taken; raises `largest_change` to the largest
/// increment's size.
bool solveJointNormals(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                       const JointManifold& manifold, double& largest_change);

}  // namespace contact
}  // namespace rigid_body
