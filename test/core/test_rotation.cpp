#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rigid_body_sim/rotation.hpp"

using namespace rigid_body;

TEST(Rotation, ExpOfZeroIsIdentityExactly) {
  const Eigen::Quaterniond q = quaternionExp(Eigen::Vector3d::Zero());
  EXPECT_EQ(q.w(), 1.0);
  EXPECT_EQ(q.vec(), Eigen::Vector3d::Zero());
}

TEST(Rotation, ExpOfTinyVectorsIsFiniteAndFirstOrderExact) {
  for (double angle : {1e-300, 1e-12, 1e-8, 1e-4}) {
    const Eigen::Vector3d v = angle * Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
    const Eigen::Quaterniond q = quaternionExp(v);
    ASSERT_TRUE(q.coeffs().allFinite()) << angle;
    EXPECT_NEAR(q.norm(), 1.0, 1e-16) << angle;
    // The rotation angle 2 atan2(|vec|, w) is |v| to rounding, relative (stableNorm: |vec| ~ 1e-300 would
    // underflow when squared).
    EXPECT_NEAR(2.0 * std::atan2(q.vec().stableNorm(), q.w()) / angle, 1.0, 1e-15) << angle;
  }
}

TEST(Rotation, ExpMatchesAngleAxisAcrossTheGuard) {
  // Below 0.25 rad the exp is two series, above it sine and cosine: either must agree with Eigen's angle-axis
  // (the library's sin and cos) to rounding, each component within 4e-16 (two units in the last place of 1),
  // at every angle of a sweep over both sides of the guard, at it and next to it.
  const Eigen::Vector3d axis = Eigen::Vector3d(-1.0, 0.5, 2.0).normalized();
  std::vector<double> angles{1e-3, 0.25, std::nextafter(0.25, 0.0), std::nextafter(0.25, 1.0), 0.5, 3.0};
  for (int k = 1; k <= 400; ++k) angles.push_back(1e-3 * k);
  for (double angle : angles) {
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    EXPECT_LE((quaternionExp(angle * axis).coeffs() - expected.coeffs()).cwiseAbs().maxCoeff(), 4e-16) << angle;
  }
}

TEST(Rotation, LogInvertsExp) {
  const Eigen::Vector3d v(0.3, -1.2, 0.8);
  EXPECT_TRUE(quaternionLog(quaternionExp(v)).isApprox(v, 1e-14));
  // −q is the same rotation: the log is the same vector.
  const Eigen::Quaterniond negated(-quaternionExp(v).coeffs());
  EXPECT_TRUE(quaternionLog(negated).isApprox(v, 1e-14));
}

TEST(Rotation, AngleBetweenOrientations) {
  const Eigen::Quaterniond a(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond b = a * Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(rotationAngleBetween(a, b), 0.05, 1e-15);
  EXPECT_NEAR(rotationAngleBetween(a, Eigen::Quaterniond(-b.coeffs())), 0.05, 1e-15);  // sign of q does not count
}
