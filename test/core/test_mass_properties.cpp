#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rigid_body_sim/mass_properties.hpp"

using rigid_body::InvalidMassProperties;
using rigid_body::MassProperties;

TEST(MassProperties, BoxMatchesClosedForm) {
  // I = M/12 diag(y²+z², x²+z², x²+y²) for the default scene's 1 kg, 0.4 × 0.2 × 0.1 m box.
  const MassProperties box = MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1));
  EXPECT_DOUBLE_EQ(box.mass(), 1.0);
  EXPECT_NEAR(box.inertia()(0, 0), (0.04 + 0.01) / 12.0, 1e-16);
  EXPECT_NEAR(box.inertia()(1, 1), (0.16 + 0.01) / 12.0, 1e-16);
  EXPECT_NEAR(box.inertia()(2, 2), (0.16 + 0.04) / 12.0, 1e-16);
  EXPECT_EQ(box.inertia()(0, 1), 0.0);
  EXPECT_TRUE((box.inertia() * box.inverseInertia()).isApprox(Eigen::Matrix3d::Identity(), 1e-14));
}

TEST(MassProperties, SphereMatchesClosedForm) {
  const MassProperties sphere = MassProperties::sphere(3.0, 0.5);
  EXPECT_TRUE(sphere.inertia().isApprox(0.4 * 3.0 * 0.25 * Eigen::Matrix3d::Identity(), 1e-15));
  EXPECT_NEAR(sphere.inverseMass(), 1.0 / 3.0, 1e-16);
}

TEST(MassProperties, CylinderAlongZMatchesClosedForm) {
  const double m = 2.0, r = 0.1, l = 1.0;
  const MassProperties cylinder = MassProperties::cylinder(m, r, l);
  EXPECT_NEAR(cylinder.inertia()(0, 0), m * (3 * r * r + l * l) / 12.0, 1e-15);
  EXPECT_NEAR(cylinder.inertia()(1, 1), m * (3 * r * r + l * l) / 12.0, 1e-15);
  EXPECT_NEAR(cylinder.inertia()(2, 2), 0.5 * m * r * r, 1e-15);
}

TEST(MassProperties, FullTensorKeepsOffDiagonalAndSortsPrincipalMoments) {
  Eigen::Matrix3d I;
  I << 2.0, -0.1, 0.0,  //
      -0.1, 3.0, 0.2,   //
      0.0, 0.2, 4.0;
  const MassProperties body = MassProperties::fromInertia(5.0, I);
  EXPECT_TRUE(body.inertia().isApprox(I, 1e-15));
  const Eigen::Vector3d moments = body.principalMoments();
  EXPECT_LT(moments(0), moments(1));
  EXPECT_LT(moments(1), moments(2));
  EXPECT_NEAR(moments.sum(), I.trace(), 1e-13);  // the trace is invariant under rotation
}

TEST(MassProperties, ThinPlateOnTheTriangleBoundIsAccepted) {
  // A flat plate has I_zz = I_xx + I_yy exactly (perpendicular axis theorem).
  EXPECT_NO_THROW(MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()));
}

TEST(MassProperties, RefusesInvalidMass) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double mass : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW(MassProperties::box(mass, Eigen::Vector3d::Ones()), InvalidMassProperties) << mass;
    EXPECT_THROW(MassProperties::fromInertia(mass, Eigen::Matrix3d::Identity()), InvalidMassProperties) << mass;
  }
}

TEST(MassProperties, RefusesInvalidSizes) {
  EXPECT_THROW(MassProperties::box(1.0, Eigen::Vector3d(1.0, 0.0, 1.0)), InvalidMassProperties);
  EXPECT_THROW(MassProperties::sphere(1.0, -0.5), InvalidMassProperties);
  EXPECT_THROW(MassProperties::cylinder(1.0, 0.1, std::nan("")), InvalidMassProperties);
}

TEST(MassProperties, RefusesNonPhysicalTensors) {
  Eigen::Matrix3d asymmetric = Eigen::Matrix3d::Identity();
  asymmetric(0, 1) = 0.1;
  EXPECT_THROW(MassProperties::fromInertia(1.0, asymmetric), InvalidMassProperties);

  const Eigen::Matrix3d negative = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
  EXPECT_THROW(MassProperties::fromInertia(1.0, negative), InvalidMassProperties);

  const Eigen::Matrix3d singular = Eigen::Vector3d(0.0, 1.0, 1.0).asDiagonal();
  EXPECT_THROW(MassProperties::fromInertia(1.0, singular), InvalidMassProperties);

  // Positive definite, but 5 > 1 + 2: no mass distribution has these principal moments.
  const Eigen::Matrix3d triangle = Eigen::Vector3d(1.0, 2.0, 5.0).asDiagonal();
  try {
    MassProperties::fromInertia(1.0, triangle);
    FAIL() << "expected InvalidMassProperties";
  } catch (const InvalidMassProperties& error) {
    EXPECT_NE(std::string(error.what()).find("triangle inequality"), std::string::npos) << error.what();
  }

  Eigen::Matrix3d with_nan = Eigen::Matrix3d::Identity();
  with_nan(2, 2) = std::nan("");
  EXPECT_THROW(MassProperties::fromInertia(1.0, with_nan), InvalidMassProperties);
}

TEST(MassProperties, PublishedNonPhysicalTestBodiesNeedTheExplicitExemption) {
  // Principia's Dzhanibekov body breaks the triangle inequality (9 > 3 + 5): refused unless exempted.
  const Eigen::Matrix3d principia = Eigen::Vector3d(3.0, 5.0, 9.0).asDiagonal();
  EXPECT_THROW(MassProperties::fromInertia(1.0, principia), InvalidMassProperties);
  EXPECT_NO_THROW(MassProperties::fromInertia(1.0, principia, rigid_body::InertiaCheck::kPositiveDefiniteOnly));
  // The exemption does not extend to tensors that are not positive definite.
  EXPECT_THROW(MassProperties::fromInertia(1.0, Eigen::Vector3d(0.0, 5.0, 9.0).asDiagonal().toDenseMatrix(),
                                           rigid_body::InertiaCheck::kPositiveDefiniteOnly),
               InvalidMassProperties);
}

TEST(MassProperties, ExtremeButValidBodiesKeepAFiniteInverseAndImpossibleOnesAreRefused) {
  // Principal moments ~1e-150 kg m²: det I ~ 1e-450 underflows to 0, so an inverse through the determinant
  // would be NaN; through the eigen-decomposition it is exact.
  const MassProperties tiny = MassProperties::box(1e-140, Eigen::Vector3d(1e-5, 2e-5, 3e-5));
  EXPECT_TRUE(tiny.inverseInertia().allFinite());
  EXPECT_TRUE((tiny.inertia() * tiny.inverseInertia()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  // Overflow, underflow and subnormal masses give no usable body: refused with the reason.
  EXPECT_THROW(MassProperties::box(1e300, Eigen::Vector3d(1e10, 1.0, 1.0)), InvalidMassProperties);  // I = inf
  EXPECT_THROW(MassProperties::sphere(1.0, 1e200), InvalidMassProperties);                           // r² = inf
  EXPECT_THROW(MassProperties::box(1e-300, Eigen::Vector3d(1e-100, 1e-100, 1e-100)), InvalidMassProperties);
  EXPECT_THROW(MassProperties::box(1e-320, Eigen::Vector3d::Ones()), InvalidMassProperties);  // subnormal mass
}
