// IMUs on a running node (imu.test): +g upward at rest on the ground in the turned sensor's axes, the
// centripetal ω²r of a spinning body in free fall, the rate on the grid of simulated time, the static frame,
// and the noise's covariance and spread.
#include <gtest/gtest.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>

#include "test_helpers.hpp"

using namespace test_helpers;

namespace {

constexpr double kG = 9.81;

Eigen::Vector3d accelOf(const sensor_msgs::Imu& m) {
  Eigen::Vector3d a;
  tf2::fromMsg(m.linear_acceleration, a);
  return a;
}

Eigen::Vector3d gyroOf(const sensor_msgs::Imu& m) {
  Eigen::Vector3d w;
  tf2::fromMsg(m.angular_velocity, w);
  return w;
}

}  // namespace

TEST(Imu, RestingCrateReadsPlusGUpInItsSensorsAxesAt50HzOnTheTickGrid) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::Imu> crate(nh, "imu/crate/imu");
  ASSERT_TRUE(crate.waitForConnection());
  ASSERT_TRUE(crate.waitForCount(40));
  for (std::size_t k = 5; k < crate.messages.size(); ++k) {
    const sensor_msgs::Imu& m = crate.messages[k];
    EXPECT_EQ(m.header.frame_id, "crate_link_imu");
    // The sensor is turned a quarter turn about x: the body's (world's) up is its y axis.
    EXPECT_LT((accelOf(m) - Eigen::Vector3d(0, kG, 0)).norm(), 0.01 * kG) << accelOf(m).transpose();
    EXPECT_LT(gyroOf(m).norm(), 1e-3);
    Eigen::Quaterniond q_WS;
    tf2::fromMsg(m.orientation, q_WS);
    EXPECT_LT((q_WS * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 1e-3);
    EXPECT_EQ(m.header.stamp.toNSec() - crate.messages[k - 1].header.stamp.toNSec(), 20000000u) << "50 Hz";
  }
}

TEST(Imu, SpinningBodyInFreeFallReadsOnlyTheCentripetalAcceleration) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::Imu> spinner(nh, "imu/spinner/imu");
  ASSERT_TRUE(spinner.waitForConnection());
  ASSERT_TRUE(spinner.waitForCount(20));
  // ω = 6 rad/s about z at r = 0.3 m on x: −ω² r = −10.8 m/s² along x; gravity is not felt in free fall.
  for (const sensor_msgs::Imu& m : spinner.messages) {
    EXPECT_LT((accelOf(m) - Eigen::Vector3d(-36.0 * 0.3, 0, 0)).norm(), 1e-6) << accelOf(m).transpose();
    EXPECT_LT((gyroOf(m) - Eigen::Vector3d(0, 0, 6.0)).norm(), 1e-9);
  }
}

TEST(Imu, NoisySensorDeclaresAndHasTheVarianceOfItsDensityTimesTheRate) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::Imu> noisy(nh, "imu/noisy/imu");
  ASSERT_TRUE(noisy.waitForConnection());
  ASSERT_TRUE(noisy.waitForCount(200));
  const sensor_msgs::Imu& first = noisy.messages.front();
  // σ² = density² · rate at 100 Hz: 0.01, 0.04.
  EXPECT_NEAR(first.angular_velocity_covariance[0], 0.01, 1e-12);
  EXPECT_NEAR(first.angular_velocity_covariance[8], 0.01, 1e-12);
  EXPECT_NEAR(first.linear_acceleration_covariance[4], 0.04, 1e-12);
  EXPECT_EQ(first.angular_velocity_covariance[1], 0.0);
  // The body falls without turning: its true readings are zero, so the samples are the noise. 600 gyro draws:
  // the variance's relative standard error is √(2/600) ≈ 6 %; five of it.
  double sum = 0.0, accel_sum = 0.0;
  for (const sensor_msgs::Imu& m : noisy.messages) {
    sum += gyroOf(m).squaredNorm();
    accel_sum += accelOf(m).squaredNorm();
  }
  const double n = 3.0 * static_cast<double>(noisy.messages.size());
  EXPECT_NEAR(sum / n / 0.01, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(accel_sum / n / 0.04, 1.0, 5.0 * std::sqrt(2.0 / n));
}

TEST(Imu, SensorFramesAreStaticTransformsBelowTheBodyFrames) {
  ros::NodeHandle nh;
  std::vector<geometry_msgs::TransformStamped> frames;
  ros::Subscriber sub = nh.subscribe<tf2_msgs::TFMessage>("/tf_static", 10, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    for (const auto& t : m->transforms) frames.push_back(t);
  });
  ASSERT_TRUE(waitUntil([&] { return frames.size() >= 3; }));
  bool crate = false;
  for (const auto& t : frames) {
    if (t.child_frame_id != "crate_link_imu") continue;
    crate = true;
    EXPECT_EQ(t.header.frame_id, "crate_link");
    EXPECT_NEAR(t.transform.translation.x, 0.15, 1e-12);
    EXPECT_NEAR(t.transform.translation.y, -0.1, 1e-12);
    EXPECT_NEAR(t.transform.rotation.x, 0.70710678118654757, 1e-12);
  }
  EXPECT_TRUE(crate);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "imu_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
