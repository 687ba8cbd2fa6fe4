// Coulomb's law at one point when the sticking impulse lies outside the friction disc (docs/references.md,
// "Friction on the disc"): shared by the readable solver (contact_solver.cpp) and the lane solver
// (lane_contact_solver.cpp), which must agree on it to the bit.
#pragma once

#include <Eigen/Core>

namespace rigid_body {
namespace contact {

/// The impulse on the disc |f| ≤ limit that leaves the least slip energy ½ (f − f*)ᵀ K (f − f*), given the
/// sticking impulse f* (`sticking`, outside the disc) and K the slip change per friction impulse
/// (`response`, symmetric positive semi-definite). Zero for a limit ≤ 0.
Eigen::Vector2d ontoFrictionDisc(const Eigen::Vector2d& sticking, const Eigen::Matrix2d& response, double limit);

}  // namespace contact
}  // namespace rigid_body
