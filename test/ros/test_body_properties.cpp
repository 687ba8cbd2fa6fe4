// get_properties' response (body_properties.hpp) without a master: what a body is, in its published frame.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/ros/body_properties.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

namespace {

rigid_body_sim::GetProperties::Response propertiesOf(const XmlRpcValue& params) {
  const rigid_body_ros::NodeConfig config = parseConfig(params);
  rigid_body_sim::GetProperties::Response response;
  rigid_body_ros::fillProperties(config.bodies[0], "rk4", rigid_body::StepTerms::all(), response);
  return response;
}

Eigen::Matrix3d inertiaOf(const rigid_body_sim::GetProperties::Response& r) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.inertia.data());
}

}  // namespace

TEST(BodyProperties, ABoxReportsItsSolidsInertiaShapeSizeAndMaterial) {
  XmlRpcValue params;
  params["mass"] = 3.0;
  params["size"] = parameter_test::list({0.4, 0.2, 0.1});
  params["collision"] = true;
  const auto r = propertiesOf(params);
  EXPECT_EQ(r.mass, 3.0);
  EXPECT_EQ(r.shape, "box");
  ASSERT_EQ(r.size.size(), 3u);
  EXPECT_EQ(r.size[0], 0.4);
  // The solid box about its centre: I_xx = m (y² + z²)/12, the others alike; no products.
  const Eigen::Matrix3d I = inertiaOf(r);
  EXPECT_NEAR(I(0, 0), 3.0 * (0.04 + 0.01) / 12.0, 1e-15);
  EXPECT_NEAR(I(1, 1), 3.0 * (0.16 + 0.01) / 12.0, 1e-15);
  EXPECT_NEAR(I(2, 2), 3.0 * (0.16 + 0.04) / 12.0, 1e-15);
  EXPECT_EQ(I(0, 1), 0.0);
  EXPECT_EQ(r.center_of_mass.x, 0.0);
  EXPECT_FALSE(std::signbit(r.center_of_mass.x)) << "printed as -0.0";
  EXPECT_TRUE(r.collides);
  EXPECT_EQ(r.collision_shape, "box");
  EXPECT_EQ(r.restitution, 0.0);
  EXPECT_EQ(r.friction, 0.5);
  EXPECT_TRUE(r.wrench_input);
  EXPECT_EQ(r.integrator, "rk4");
  EXPECT_FALSE(r.step_terms.empty());
}

// test/urdf/offset_link.urdf: the inertial frame I at xyz (0.1, −0.05, 0.02), rpy (0.3, 0.2, −0.4) in the
// link frame L, which is the published frame; the inertia given about I in I's axes. In L's axes it is
// R_LI I_I R_LIᵀ with R_LI = Rz(yaw) Ry(pitch) Rx(roll), and the centre of mass is I's origin: a wrong
// frame (the body's principal frame, or R_BP applied the wrong way round) moves both.
TEST(BodyProperties, AUrdfLinkReportsItsInertiaAndCentreInTheLinkFrame) {
  XmlRpcValue params;
  params["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  params["link"] = std::string("base_link");
  const auto r = propertiesOf(params);
  EXPECT_EQ(r.mass, 2.0);
  EXPECT_EQ(r.shape, "urdf");
  EXPECT_TRUE(r.size.empty());
  EXPECT_NEAR(r.center_of_mass.x, 0.1, 1e-12);
  EXPECT_NEAR(r.center_of_mass.y, -0.05, 1e-12);
  EXPECT_NEAR(r.center_of_mass.z, 0.02, 1e-12);
  Eigen::Matrix3d I_I;
  I_I << 0.10, 0.005, -0.002,  //
      0.005, 0.20, 0.004,      //
      -0.002, 0.004, 0.25;
  const Eigen::Matrix3d R_LI = (Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
  const Eigen::Matrix3d expected = R_LI * I_I * R_LI.transpose();
  EXPECT_LT((inertiaOf(r) - expected).norm(), 1e-12) << inertiaOf(r);
  // The principal moments are the eigenvalues, and the principal axes' frame diagonalises I in L.
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(expected).eigenvalues();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.principal_moments[i], moments[i], 1e-12);
  const Eigen::Quaterniond q(r.principal_axes.w, r.principal_axes.x, r.principal_axes.y, r.principal_axes.z);
  const Eigen::Matrix3d diagonal = q.toRotationMatrix().transpose() * expected * q.toRotationMatrix();
  EXPECT_LT((diagonal - Eigen::Matrix3d(moments.asDiagonal())).norm(), 1e-12) << diagonal;
}

TEST(BodyProperties, ABodyGivenByItsInertiaHasNoShapeAndNoContact) {
  XmlRpcValue params;
  params["inertia"] = parameter_test::list({1.0, 2.0, 2.5, 0.1, 0.0, 0.0});
  params["wrench_input"] = false;
  const auto r = propertiesOf(params);
  EXPECT_EQ(r.shape, "inertia");
  EXPECT_TRUE(r.size.empty());
  EXPECT_FALSE(r.collides);
  EXPECT_EQ(r.collision_shape, "");
  EXPECT_FALSE(r.wrench_input);
  EXPECT_EQ(inertiaOf(r)(0, 1), 0.1);
}

TEST(BodyProperties, TheStartUpLineSaysMassPrincipalMomentsAndCentre) {
  // A 3 kg box 0.4 × 0.2 × 0.1 m: principal moments m/12 (b² + c², a² + c², a² + b²), ascending.
  XmlRpcValue params;
  params["mass"] = 3.0;
  params["size"] = parameter_test::list({0.4, 0.2, 0.1});
  const std::string line = rigid_body_ros::describeProperties(propertiesOf(params));
  EXPECT_NE(line.find("mass 3 kg"), std::string::npos) << line;
  EXPECT_NE(line.find("principal moments [0.0125, 0.0425, 0.05] kg m^2"), std::string::npos) << line;
  EXPECT_NE(line.find("centre of mass (0, 0, 0) m"), std::string::npos) << line;
  EXPECT_NE(line.find("shape box"), std::string::npos) << line;
  // A URDF link (test/urdf/offset_link.urdf): 2 kg, its centre of mass at (0.1, −0.05, 0.02) in the link frame.
  XmlRpcValue urdf;
  urdf["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  urdf["link"] = std::string("base_link");
  const std::string link_line = rigid_body_ros::describeProperties(propertiesOf(urdf));
  EXPECT_NE(link_line.find("mass 2 kg"), std::string::npos) << link_line;
  EXPECT_NE(link_line.find("centre of mass (0.1, -0.05, 0.02) m"), std::string::npos) << link_line;
  EXPECT_NE(link_line.find("shape urdf"), std::string::npos) << link_line;
  EXPECT_EQ(line.find("nan"), std::string::npos);
}
