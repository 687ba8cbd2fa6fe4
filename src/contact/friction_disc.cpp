#include "friction_disc.hpp"

#include <Eigen/Eigenvalues>

namespace rigid_body {
namespace contact {

// Coulomb's law at one point, given the sticking impulse f* outside the disc |f| ≤ L: the impulse on the disc
// that leaves the least slip energy ½ s⁺ᵀ K⁻¹ s⁺ = ½ (f − f*)ᵀ K (f − f*), K the slip change per impulse
// (docs/references.md, "Friction on the disc"). Its optimality condition K (f − f*) = −λ f says s⁺ = −λ f:
// the impulse opposes the slip it leaves (maximal dissipation). So f = (K + λ)⁻¹ K f*, with λ ≥ 0 the root of
// |f(λ)| = L, found by Newton's method on 1/|f(λ)| − 1/L (nearly linear in λ; from λ = 0 it rises
// monotonically to the root, as for a trust region's secular equation, Moré & Sorensen 1983). Each point's
// update then lowers the bodies' kinetic energy, so the sweeps descend to a sticking solution where one exists.
Eigen::Vector2d ontoFrictionDisc(const Eigen::Vector2d& sticking, const Eigen::Matrix2d& response, double limit) {
  if (!(limit > 0.0)) return Eigen::Vector2d::Zero();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
  eigen.computeDirect(response);
  const Eigen::Vector2d k = eigen.eigenvalues().cwiseMax(0.0);
  const Eigen::Vector2d g = eigen.eigenvectors().transpose() * sticking;
  const Eigen::Vector2d kg = k.cwiseProduct(g);
  double lambda = 0.0;
  Eigen::Vector2d f = kg;  // in the eigenbasis, at λ = 0 (= g where K is regular)
  for (int i = 0; i < 40; ++i) {
    double dr = 0.0;  // d|f|/dλ · |f|
    for (int j = 0; j < 2; ++j) {
      const double denominator = k[j] + lambda;
      f[j] = denominator > 0.0 ? kg[j] / denominator : 0.0;  // no slip response along it: no impulse
      if (denominator > 0.0) dr -= f[j] * f[j] / denominator;
    }
    const double r = f.norm();
    if (!(r > limit * (1.0 + 1e-15)) || !(dr < 0.0)) break;
    lambda += (1.0 / r - 1.0 / limit) * r * r * r / dr;
  }
  const double r = f.norm();
  const Eigen::Vector2d on_disc = r > 0.0 ? Eigen::Vector2d(f * (limit / r)) : Eigen::Vector2d::Zero();
  return eigen.eigenvectors() * on_disc;
}

}  // namespace contact
}  // namespace rigid_body
