// Coulomb's law on the disc (docs/references.md §4.8): the impulse on the disc that leaves the least slip
// energy is on the circle and opposes the slip it leaves, s⁺ = K (f − f*) = −λ f with λ ≥ 0.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#define RIGID_BODY_CONTACT_LANES_ISA test_isa
#include "../../src/contact/lane_kernel.hpp"
#include "../../src/contact/friction_disc.hpp"

using rigid_body::contact::ontoFrictionDisc;

namespace {

// A symmetric positive definite 2 × 2 matrix with eigenvalues k1, k2 and its first eigenvector at `angle`.
Eigen::Matrix2d response(double k1, double k2, double angle) {
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
  return R * Eigen::Vector2d(k1, k2).asDiagonal() * R.transpose();
}

TEST(FrictionDisc, TheImpulseIsOnTheCircleAndOpposesTheSlipItLeaves) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 20000; ++trial) {
    // Anisotropy up to 10⁶ (a light body's corner on a heavy one), sticking impulses from just outside the
    // disc to 10⁴ times its radius.
    const double k1 = std::pow(10.0, -2.0 + 4.0 * unit(random));
    const double k2 = k1 * std::pow(10.0, 6.0 * unit(random) - 3.0);
    const Eigen::Matrix2d K = response(k1, k2, 6.3 * unit(random));
    const double limit = std::pow(10.0, -3.0 + 4.0 * unit(random));
    const double angle = 6.3 * unit(random);
    const double outside = 1.0 + (trial % 2 == 0 ? 1e-6 * unit(random) : std::pow(10.0, 4.0 * unit(random)));
    const Eigen::Vector2d sticking = limit * outside * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    const Eigen::Vector2d f = ontoFrictionDisc(sticking, K, limit);
    ASSERT_NEAR(f.norm(), limit, 1e-12 * limit) << trial;
    // The slip left, s⁺ = K (f − f*), anti-parallel to f. Just outside the disc s⁺ is small beside K f (f − f*
    // cancels), so a rounding δf of f (~1e-12 |f| after the scaling onto the circle) moves s⁺ by up to ‖K‖ δf:
    // the bound allows that besides the direction's own error.
    const Eigen::Vector2d slip = K * (f - sticking);
    const double cross = slip.x() * f.y() - slip.y() * f.x();
    const double rounding = 1e-12 * K.norm() * f.squaredNorm();
    EXPECT_LE(std::abs(cross), 1e-9 * slip.norm() * f.norm() + rounding) << trial;
    EXPECT_LE(slip.dot(f), rounding) << trial;
  }
}

TEST(FrictionDisc, AnIsotropicResponseScalesTheStickingImpulseOntoTheDisc) {
  const Eigen::Vector2d sticking(3.0, -4.0);
  const Eigen::Vector2d f = ontoFrictionDisc(sticking, 2.5 * Eigen::Matrix2d::Identity(), 0.5);
  EXPECT_NEAR((f - 0.1 * sticking).norm(), 0.0, 1e-15);
}

TEST(FrictionDisc, NoResponseAlongADirectionGivesNoImpulseAlongIt) {
  // K = diag(2, 0): friction along t2 changes no slip, so none is applied along it.
  Eigen::Matrix2d K = Eigen::Matrix2d::Zero();
  K(0, 0) = 2.0;
  const Eigen::Vector2d f = ontoFrictionDisc(Eigen::Vector2d(3.0, 4.0), K, 1.0);
  EXPECT_NEAR(f.x(), 1.0, 1e-9);
  EXPECT_NEAR(f.y(), 0.0, 1e-9);
  EXPECT_EQ(ontoFrictionDisc(Eigen::Vector2d(3.0, 4.0), Eigen::Matrix2d::Zero(), 1.0), Eigen::Vector2d::Zero());
  EXPECT_EQ(ontoFrictionDisc(Eigen::Vector2d(3.0, 4.0), K, 0.0), Eigen::Vector2d::Zero());
}

// The lane solver's projection (contact_lanes.hpp) against this file's scalar function, bit for bit, in one,
// four and eight lanes: random lanes outside the disc and inside it (kept), anisotropy to 10⁶, K singular or
// zero, limits of zero, and sticking impulses from just outside the disc (many Newton steps) to far outside.
// Catches a lane form that rounds otherwise (a reordered product, a reciprocal for a division), that stops
// a lane before or after the scalar loop would, or that lets one lane's iterations change another's result.
template <class T>
void expectLanesMatchTheScalarProjection(unsigned seed) {
  using rigid_body::contact::test_isa::frictionOntoDiscLanes;
  using rigid_body::contact::LaneMask;
  using rigid_body::integrators::laneValue;
  using rigid_body::integrators::setLane;
  constexpr std::size_t kWidth = rigid_body::integrators::kLaneCount<T>;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 5000; ++trial) {
    T k00{}, k01{}, k11{}, limit{}, f1{}, f2{};
    LaneMask<T> outside{};
    Eigen::Matrix2d K[kWidth];
    for (std::size_t l = 0; l < kWidth; ++l) {
      const double k1 = std::pow(10.0, -2.0 + 4.0 * unit(random));
      const double kind = unit(random);
      const double k2 = kind < 0.1 ? 0.0 : k1 * std::pow(10.0, 6.0 * unit(random) - 3.0);
      K[l] = kind < 0.15 ? Eigen::Matrix2d::Zero() : response(k1, k2, 6.3 * unit(random));
      K[l](0, 1) *= 1.0 + 1e-15 * (unit(random) - 0.5);  // as prepared: symmetric only to rounding
      const double radius = unit(random) < 0.05 ? 0.0 : std::pow(10.0, -3.0 + 4.0 * unit(random));
      const double scale = unit(random) < 0.5 ? 1.0 + 1e-9 * unit(random) : std::pow(10.0, 3.0 * unit(random));
      const double angle = 6.3 * unit(random);
      const bool on = unit(random) < 0.7;
      rigid_body::contact::test_isa::setMaskLane(outside, l, on);
      setLane(k00, l, K[l](0, 0)), setLane(k01, l, 0.5 * (K[l](0, 1) + K[l](1, 0))), setLane(k11, l, K[l](1, 1));
      setLane(limit, l, radius);
      setLane(f1, l, std::max(radius, 1e-3) * scale * std::cos(angle));
      setLane(f2, l, std::max(radius, 1e-3) * scale * std::sin(angle));
    }
    const T before1 = f1, before2 = f2;
    frictionOntoDiscLanes<T>(outside, k00, k01, k11, limit, f1, f2);
    for (std::size_t l = 0; l < kWidth; ++l) {
      const Eigen::Vector2d sticking(laneValue(before1, l), laneValue(before2, l));
      const Eigen::Vector2d expected = rigid_body::contact::test_isa::laneOn(outside, l)
                                           ? ontoFrictionDisc(sticking, K[l], laneValue(limit, l))
                                           : sticking;
      ASSERT_EQ(laneValue(f1, l), expected.x()) << "trial " << trial << ", lane " << l;
      ASSERT_EQ(laneValue(f2, l), expected.y()) << "trial " << trial << ", lane " << l;
    }
  }
}

TEST(FrictionDisc, TheLaneFormProjectsToTheBitsOfTheScalarFunction) {
  expectLanesMatchTheScalarProjection<double>(5);
  expectLanesMatchTheScalarProjection<rigid_body::integrators::Lanes>(6);
  expectLanesMatchTheScalarProjection<rigid_body::contact::EightLanes>(7);
}

}  // namespace
