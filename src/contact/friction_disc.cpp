#include "friction_disc.hpp"

#include <algorithm>
#include <cmath>

namespace rigid_body {
namespace contact {

// Coulomb's law at one point, given the sticking impulse f* outside the disc |f| ≤ L: the impulse on the disc
// that leaves the least slip energy ½ s⁺ᵀ K⁻¹ s⁺ = ½ (f − f*)ᵀ K (f − f*), K the slip change per impulse
// (docs/references.md §4.8). Its optimality condition K (f − f*) = −λ f says s⁺ = −λ f: the impulse opposes
// the slip it leaves (maximal dissipation). So f(λ) = (K + λ)⁻¹ K f*, with λ ≥ 0 the root of |f(λ)| = L.
// |f(λ)| falls monotonically in λ, and Newton's method on 1/|f(λ)| − 1/L (nearly linear in λ) rises
// monotonically to the root from any λ below it (the secular equation of a trust region, Moré & Sorensen
// 1983). It starts at a bound below the root, λ₀ = k_min (|f*|/L − 1) (§4.8: each eigen-component of f(λ)
// shrinks by kᵢ/(kᵢ + λ) ≥ k_min/(k_min + λ)), which is the root itself where K is isotropic. Each step is a
// 2 × 2 solve: with M = K + λ, f = M⁻¹ K f* = adj(M) K f* / det M, and d|f|/dλ · |f| = f·f' = −fᵀ M⁻¹ f
// = −q / det M with q = fᵀ adj(M) f, so Newton's step (1/|f| − 1/L) |f|³ / (f·f') is (|f| − L) |f|² det M / (L q):
// one reciprocal, one square root and one division a step (the lane solver runs the same operations,
// contact_lanes.hpp).
Eigen::Vector2d ontoFrictionDisc(const Eigen::Vector2d& sticking, const Eigen::Matrix2d& response, double limit) {
  if (!(limit > 0.0)) return Eigen::Vector2d::Zero();
  const double k00 = response(0, 0), k11 = response(1, 1), k01 = 0.5 * (response(0, 1) + response(1, 0));
  const double half_trace = 0.5 * (k00 + k11), half_gap = 0.5 * (k00 - k11);
  const double k_min = half_trace - std::sqrt(half_gap * half_gap + k01 * k01);
  const double kf1 = k00 * sticking.x() + k01 * sticking.y(), kf2 = k01 * sticking.x() + k11 * sticking.y();
  // A singular K (no slip response along a direction, so no impulse there) starts just above λ = 0.
  const double norm = std::sqrt(sticking.x() * sticking.x() + sticking.y() * sticking.y());
  double lambda = k_min > 0.0 ? std::max(0.0, k_min * (norm / limit - 1.0)) : 1e-12 * half_trace;
  double f1 = 0.0, f2 = 0.0, r = 0.0;
  for (int i = 0; i < 40; ++i) {
    const double m00 = k00 + lambda, m11 = k11 + lambda, det = m00 * m11 - k01 * k01;
    if (!(det > 0.0)) break;  // K is zero: no friction can act
    const double inverse = 1.0 / det;
    f1 = (m11 * kf1 - k01 * kf2) * inverse, f2 = (m00 * kf2 - k01 * kf1) * inverse;
    const double squared = f1 * f1 + f2 * f2;
    r = std::sqrt(squared);
    const double q = m11 * f1 * f1 - 2.0 * k01 * f1 * f2 + m00 * f2 * f2;
    if (!(r > limit * (1.0 + 1e-15)) || !(q > 0.0)) break;
    lambda += (r - limit) * squared * det / (limit * q);
  }
  return r > 0.0 ? Eigen::Vector2d(f1 * (limit / r), f2 * (limit / r)) : Eigen::Vector2d::Zero();
}

}  // namespace contact
}  // namespace rigid_body
