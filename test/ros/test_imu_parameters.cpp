// A body's `imu` key without a master: its defaults, its refusals (each naming the key), and a sensor given
// in a URDF link's frame placed on the body at the centre of mass.
#include <gtest/gtest.h>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

using parameter_test::errorOf;
using parameter_test::list;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue withImu(const XmlRpcValue& imu) {
  XmlRpcValue params;
  params["body_frame"] = std::string("hull");
  params["rate"] = 200.0;
  params["imu"] = imu;
  return params;
}

XmlRpcValue imuKey(const std::string& key, const XmlRpcValue& value) {
  XmlRpcValue imu;
  imu[key] = value;
  return withImu(imu);
}

}  // namespace

TEST(ImuParameters, TrueIsANoiselessSensorAtTheBodyFrameReadingAtTheNodesRate) {
  const NodeConfig config = parseConfig(withImu(XmlRpcValue(true)));
  ASSERT_TRUE(config.bodies[0].imu.has_value());
  const rigid_body_ros::ImuConfig& imu = *config.bodies[0].imu;
  EXPECT_EQ(imu.frame, "hull_imu");
  EXPECT_EQ(imu.rate, 200.0);
  EXPECT_FALSE(imu.gyro.enabled());
  EXPECT_FALSE(imu.accel.enabled());
  EXPECT_EQ(imu.mount.p_BS_B, Eigen::Vector3d::Zero());
  EXPECT_FALSE(parseConfig(withImu(XmlRpcValue(false))).bodies[0].imu.has_value());
  EXPECT_FALSE(parseConfig(XmlRpcValue()).bodies[0].imu.has_value());
}

TEST(ImuParameters, EveryKeyIsReadIntoTheSensor) {
  XmlRpcValue imu;
  imu["frame"] = std::string("imu_link");
  imu["position"] = list({0.1, 0.2, 0.3});
  imu["orientation"] = list({0.0, 0.0, 0.70710678118654757, 0.70710678118654757});
  imu["rate"] = 50.0;
  imu["gyro_noise_density"] = 1e-3;
  imu["gyro_random_walk"] = 2e-5;
  imu["accel_noise_density"] = 3e-3;
  imu["accel_random_walk"] = 4e-4;
  imu["orientation_stddev"] = 0.01;
  imu["seed"] = 9;
  const NodeConfig config = parseConfig(withImu(imu));
  const rigid_body_ros::ImuConfig& read = *config.bodies[0].imu;
  EXPECT_EQ(read.frame, "imu_link");
  EXPECT_EQ(read.position, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(read.rate, 50.0);
  EXPECT_EQ(read.gyro.noise_density, 1e-3);
  EXPECT_EQ(read.gyro.random_walk, 2e-5);
  EXPECT_EQ(read.accel.noise_density, 3e-3);
  EXPECT_EQ(read.accel.random_walk, 4e-4);
  EXPECT_EQ(read.orientation_stddev, 0.01);
  EXPECT_EQ(read.seed, 9);
  // A box body: the published frame is the body frame, so the mount is the position and axes as given.
  EXPECT_LT((read.mount.p_BS_B - Eigen::Vector3d(0.1, 0.2, 0.3)).norm(), 1e-15);
  EXPECT_LT((read.mount.q_BS * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_TRUE(config.unknown_parameters.empty());
}

TEST(ImuParameters, BadValuesAreRefusedNamingTheKeyAndTheRule) {
  EXPECT_NE(errorOf(imuKey("rate", XmlRpcValue(400.0))).find("~imu/rate = 400: must be a finite number in (0, rate = 200]"),
            std::string::npos);
  EXPECT_NE(errorOf(imuKey("rate", XmlRpcValue(0.0))).find("~imu/rate = 0"), std::string::npos);
  for (const char* key : {"gyro_noise_density", "gyro_random_walk", "accel_noise_density", "accel_random_walk",
                          "orientation_stddev"}) {
    EXPECT_NE(errorOf(imuKey(key, XmlRpcValue(-1e-3))).find(std::string("~imu/") + key + " = -0.001: must be a finite number >= 0"),
              std::string::npos)
        << key;
  }
  EXPECT_NE(errorOf(imuKey("frame", XmlRpcValue(std::string("hull")))).find("~imu/frame = 'hull': must differ"),
            std::string::npos);
  EXPECT_NE(errorOf(imuKey("frame", XmlRpcValue(std::string("world")))).find("must differ"), std::string::npos);
  EXPECT_NE(errorOf(imuKey("frame", XmlRpcValue(std::string("")))).find("~imu/frame"), std::string::npos);
  EXPECT_NE(errorOf(imuKey("orientation", list({0, 0, 0, 2}))).find("~imu/orientation"), std::string::npos);
  EXPECT_NE(errorOf(imuKey("position", list({0, 0}))).find("~imu/position"), std::string::npos);
  EXPECT_NE(errorOf(imuKey("seed", XmlRpcValue(1.5))).find("~imu/seed"), std::string::npos);
  EXPECT_NE(errorOf(withImu(XmlRpcValue(std::string("yes")))).find("~imu"), std::string::npos);
}

TEST(ImuParameters, AMisspelledKeyIsReportedAndAKeyOfABodyItemNamesTheItem) {
  const NodeConfig config = parseConfig(imuKey("gyro_noise_densty", XmlRpcValue(0.1)));
  ASSERT_EQ(config.unknown_parameters.size(), 1u);
  EXPECT_EQ(config.unknown_parameters[0], "imu/gyro_noise_densty");
  XmlRpcValue params;
  params["bodies"][0]["name"] = std::string("a");
  params["bodies"][0]["imu"]["rate"] = 1e6;
  EXPECT_NE(errorOf(params).find("~bodies[0]/imu/rate"), std::string::npos) << errorOf(params);
}

TEST(ImuParameters, ASensorGivenInAUrdfLinksFrameSitsOnTheBodyWhereTheLinkSays) {
  // test/urdf/offset_link.urdf puts the centre of mass at (0.1, −0.05, 0.02) of the link frame, its axes
  // turned by rpy (0.3, 0.2, −0.4): a sensor given there, with those axes, is at B's origin with B's axes.
  XmlRpcValue params;
  params["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  params["link"] = std::string("base_link");
  const Eigen::Quaterniond q_PB = Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  params["imu"]["position"] = list({0.1, -0.05, 0.02});
  params["imu"]["orientation"] = list({q_PB.x(), q_PB.y(), q_PB.z(), q_PB.w()});
  const NodeConfig config = parseConfig(params);
  const rigid_body_ros::ImuConfig& imu = *config.bodies[0].imu;
  EXPECT_LT(imu.mount.p_BS_B.norm(), 1e-12) << imu.mount.p_BS_B.transpose();
  EXPECT_LT(imu.mount.q_BS.angularDistance(Eigen::Quaterniond::Identity()), 1e-9);
  EXPECT_EQ(imu.frame, config.bodies[0].body_frame + "_imu");
}
