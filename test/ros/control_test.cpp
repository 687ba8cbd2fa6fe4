// Simulation control and realism against a lockstep node: /clock faster than real time, pause, step,
// reset and reset_time, apply_wrench with a duration and at a point, set_state/get_state, get_properties,
// sensor noise,
// and bit-for-bit reproducibility of a stepped run.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <geometry_msgs/Wrench.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "rigid_body_sim/ApplyWrench.h"
#include "rigid_body_sim/GetProperties.h"
#include "rigid_body_sim/GetState.h"
#include "rigid_body_sim/SetState.h"
#include "rigid_body_sim/Step.h"
#include "test_helpers.hpp"

using namespace test_helpers;

namespace {

constexpr double kDt = 0.001, kMass = 2.0;

class Control : public ::testing::Test {
 protected:
  template <typename Service>
  Service call(const std::string& name, Service service = Service()) {
    ros::ServiceClient client = nh_.serviceClient<Service>("lock/" + name);
    EXPECT_TRUE(client.waitForExistence(ros::Duration(kWaitLimit))) << name;
    EXPECT_TRUE(client.call(service)) << name;
    return service;
  }
  void pause() { call<std_srvs::Empty>("pause"); }
  void unpause() { call<std_srvs::Empty>("unpause"); }
  rigid_body_sim::Step::Response step(int n) {
    rigid_body_sim::Step s;
    s.request.steps = n;
    return call("step", s).response;
  }
  rigid_body_sim::GetState::Response state() { return call<rigid_body_sim::GetState>("get_state").response; }
  void resetTime() { EXPECT_TRUE(call<std_srvs::Trigger>("reset_time").response.success); }
  rigid_body_sim::ApplyWrench::Response apply(const std::string& frame, const Eigen::Vector3d& force, double duration,
                                              const Eigen::Vector3d* point = nullptr) {
    rigid_body_sim::ApplyWrench a;
    a.request.frame_id = frame;
    a.request.wrench.force.x = force.x();
    a.request.wrench.force.y = force.y();
    a.request.wrench.force.z = force.z();
    a.request.duration = ros::Duration(duration);
    if (point) {
      a.request.use_point = true;
      a.request.point = tf2::toMsg(*point);
    }
    return call("apply_wrench", a).response;
  }
  static Eigen::Vector3d vec(const geometry_msgs::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }

  ros::NodeHandle nh_;
};

}  // namespace

// The lock node's body (control.test): a 2 kg solid sphere of radius 0.1 m, rk4 by default, no collision.
TEST_F(Control, GetPropertiesSaysWhatTheBodyIs) {
  const auto p = call<rigid_body_sim::GetProperties>("get_properties").response;
  EXPECT_EQ(p.mass, kMass);
  EXPECT_EQ(p.shape, "sphere");
  ASSERT_EQ(p.size.size(), 1u);
  EXPECT_EQ(p.size[0], 0.1);
  const double I = 0.4 * kMass * 0.1 * 0.1;  // (2/5) m r²
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(p.inertia[4 * i], I, 1e-15);  // the diagonal of the row-major 3 × 3
    EXPECT_NEAR(p.principal_moments[i], I, 1e-15);
  }
  EXPECT_EQ(p.inertia[1], 0.0);
  EXPECT_FALSE(p.collides);
  EXPECT_TRUE(p.wrench_input);
  EXPECT_EQ(p.integrator, "rk4");
}

TEST_F(Control, PausedAtStartThenStepAdvancesExactlyNSteps) {
  const auto before = state();
  EXPECT_TRUE(before.paused);
  spinFor(0.3);
  EXPECT_EQ(state().total_steps, before.total_steps);  // paused: nothing moves, the clock neither
  const auto stepped = step(37);
  ASSERT_TRUE(stepped.success) << stepped.message;
  EXPECT_EQ(stepped.total_steps, before.total_steps + 37);
  EXPECT_NEAR(stepped.sim_time - before.stamp.toSec(), 37 * kDt, 1e-9);
  EXPECT_NEAR(state().stamp.toSec(), stepped.sim_time, 1e-12);
}

TEST_F(Control, ApplyWrenchWithADurationChangesMomentumByForceTimesDuration) {
  resetTime();
  pause();
  const Eigen::Vector3d force(2.0, 0.0, -1.0);
  ASSERT_TRUE(apply("world", force, 0.25).success);
  ASSERT_TRUE(step(1000).success);  // 1 s: the wrench acted for 0.25 s of it
  const Eigen::Vector3d dv = vec(state().twist_world.linear);
  const Eigen::Vector3d expected = force * 0.25 / kMass;
  EXPECT_LT((dv - expected).norm(), force.norm() * kDt / kMass + 1e-12) << dv.transpose();
  // A point force: τ = (p − x) × F about the centre of mass, here at body point (0, 0.1, 0) with F along x.
  resetTime();
  pause();
  const Eigen::Vector3d point(0.0, 0.1, 0.0);
  ASSERT_TRUE(apply("lock_link", Eigen::Vector3d(1.0, 0.0, 0.0), 0.1, &point).success);
  ASSERT_TRUE(step(100).success);
  const double I0 = 0.4 * kMass * 0.01;  // sphere r = 0.1
  const Eigen::Vector3d w = vec(state().twist_world.angular);
  EXPECT_NEAR(w.z(), -0.1 * 1.0 * 0.1 / I0, 1e-9);  // (0, 0.1, 0) × (1, 0, 0) = (0, 0, −0.1) N m for 0.1 s
  EXPECT_NEAR(w.x(), 0.0, 1e-12);
  call<std_srvs::Empty>("clear_wrenches");
}

TEST_F(Control, StepNAboveTheCatchUpCapTakesExactlyNStepsAndHugeRequestsAreRefused) {
  // max_substeps is 1000 (the default): a request for 5000 steps must still take 5000, not the cap's 1000.
  resetTime();
  pause();
  const Eigen::Vector3d force(2.0, 0.0, 0.0);
  ASSERT_TRUE(apply("world", force, -1.0).success);  // until clear_wrenches
  const auto before = state();
  const auto stepped = step(5000);
  ASSERT_TRUE(stepped.success) << stepped.message;
  EXPECT_EQ(stepped.total_steps, before.total_steps + 5000);
  EXPECT_NEAR(stepped.sim_time - before.stamp.toSec(), 5.0, 1e-9);
  EXPECT_NEAR(state().twist_world.linear.x, 2.0 * 5.0 / kMass, 1e-9);  // v = F t / M over the whole 5 s
  call<std_srvs::Empty>("clear_wrenches");
  // Beyond the request bound (2e6 body-steps): refused with a message, nothing moves, the node answers.
  rigid_body_sim::Step huge;
  huge.request.steps = std::numeric_limits<std::int64_t>::max();
  const auto refused = call("step", huge).response;
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("at most"), std::string::npos) << refused.message;
  EXPECT_EQ(state().total_steps, stepped.total_steps);
}

TEST_F(Control, AStepRequestPastItsWallTimeBudgetStopsWhereItGotToAndSaysSo) {
  // The budget node allows 1 ms of wall time per request; 2e6 steps (the count cap) take ~0.2 s or more.
  rigid_body_sim::Step s;
  s.request.steps = 2000000;
  ros::ServiceClient client = nh_.serviceClient<rigid_body_sim::Step>("budget/step");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(kWaitLimit)));
  ASSERT_TRUE(client.call(s));
  EXPECT_FALSE(s.response.success);
  EXPECT_NE(s.response.message.find("of 2000000 steps"), std::string::npos) << s.response.message;
  EXPECT_NE(s.response.message.find("max_request_seconds"), std::string::npos) << s.response.message;
  const std::int64_t first = s.response.total_steps;
  EXPECT_GT(first, 0);
  EXPECT_LT(first, 2000000);
  EXPECT_NEAR(s.response.sim_time, first * kDt, 1e-9);  // the clock moved by the steps taken, not by N
  s.request.steps = 10;  // within the budget: exactly these steps more
  ASSERT_TRUE(client.call(s));
  EXPECT_TRUE(s.response.success) << s.response.message;
  EXPECT_EQ(s.response.total_steps, first + 10);
}

TEST_F(Control, ABodyFrameForceAtAPointOnABodyTurnedAboutXActsInBodyAxes) {
  // Turned 90° about world x: body y is world z, body z is world −y. A force (0, 0, 1) N in body axes at the
  // body point (0.1, 0, 0): τ_B = (0.1, 0, 0) × (0, 0, 1) = (0, −0.1, 0) N m, which in world axes is
  // (0, 0, −0.1): about world z. A torque left in body axes by mistake would turn the sphere about world y.
  resetTime();
  pause();
  rigid_body_sim::SetState turn;
  turn.request.pose.orientation = tf2::toMsg(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())));
  ASSERT_TRUE(call("set_state", turn).response.success);
  const Eigen::Vector3d point(0.1, 0.0, 0.0);
  ASSERT_TRUE(apply("lock_link", Eigen::Vector3d(0.0, 0.0, 1.0), 0.01, &point).success);
  ASSERT_TRUE(step(10).success);
  const double I0 = 0.4 * kMass * 0.01;  // sphere r = 0.1
  const auto got = state();
  // For a sphere from rest ω stays along the torque's axis, which the rotation keeps: exact but for rounding.
  EXPECT_NEAR(got.twist_world.angular.z, -0.1 * 0.01 / I0, 1e-12);
  EXPECT_NEAR(got.twist_world.angular.x, 0.0, 1e-12);
  EXPECT_NEAR(got.twist_world.angular.y, 0.0, 1e-12);
  // The force, body z = world −y, turns a little with the body about world z (by ½ α t² = 6e-4 rad).
  EXPECT_NEAR(got.twist_world.linear.y, -1.0 * 0.01 / kMass, 1e-6);
  EXPECT_NEAR(got.twist_world.linear.z, 0.0, 1e-12);
  call<std_srvs::Empty>("clear_wrenches");
}

TEST_F(Control, GetStateCountsWrenchMessagesSoATestWaitsInsteadOfSleeping) {
  // The handshake of rigid_body_sim.testing: once get_state has counted a message, the node holds it and it
  // acts from the next step. A refused message counts too (else a test would wait for it forever), and does
  // not clear the wrench that was acting; the latest accepted message of either topic wins.
  resetTime();
  pause();
  ros::Publisher stamped = advertiseWrench(nh_, "lock");
  ros::Publisher unstamped = nh_.advertise<geometry_msgs::Wrench>("lock/wrench_unstamped", 10);
  ASSERT_TRUE(waitUntil([&] { return unstamped.getNumSubscribers() > 0; }));
  const auto start = state();
  auto counted = [&](std::uint64_t messages, std::uint64_t refused) {
    return waitUntil([&] {
      const auto now = state();
      return now.wrench_messages == start.wrench_messages + messages &&
             now.wrench_messages_refused == start.wrench_messages_refused + refused;
    });
  };
  stamped.publish(wrench("world", 1.0, 0.0, 0.0));
  ASSERT_TRUE(counted(1, 0));
  stamped.publish(wrench("world", std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0));
  ASSERT_TRUE(counted(2, 1));
  stamped.publish(wrench("no_such_frame", 5.0, 0.0, 0.0));  // tf2 cannot resolve it: refused
  ASSERT_TRUE(counted(3, 2));
  ASSERT_TRUE(step(100).success);
  EXPECT_NEAR(state().twist_world.linear.x, 1.0 * 0.1 / kMass, 1e-12);  // from the first step on: v = F t / M
  geometry_msgs::Wrench sideways;
  sideways.force.y = 2.0;
  unstamped.publish(sideways);
  ASSERT_TRUE(counted(4, 2));
  ASSERT_TRUE(step(100).success);
  const auto end = state();
  EXPECT_NEAR(end.twist_world.linear.x, 1.0 * 0.1 / kMass, 1e-12);  // replaced, not summed
  EXPECT_NEAR(end.twist_world.linear.y, 2.0 * 0.1 / kMass, 1e-12);
  unstamped.publish(geometry_msgs::Wrench());
  ASSERT_TRUE(counted(5, 2));
}

TEST_F(Control, SetStateAndGetStateRoundTripAndBadStatesAreRefused) {
  pause();
  rigid_body_sim::SetState set;
  set.request.pose.position.x = 1.5;
  set.request.pose.orientation = tf2::toMsg(Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())));
  set.request.twist.linear.x = 1.0;  // body axes
  set.request.twist.angular.z = 0.3;
  set.request.twist_frame = "body";
  ASSERT_TRUE(call("set_state", set).response.success);
  const auto got = state();
  EXPECT_NEAR(got.pose.position.x, 1.5, 1e-15);
  EXPECT_NEAR(got.pose.orientation.z, std::sin(0.25), 1e-15);
  EXPECT_NEAR(got.twist_body.linear.x, 1.0, 1e-14);
  EXPECT_NEAR(got.twist_world.linear.y, std::sin(0.5), 1e-14);  // body x turned by 0.5 rad
  EXPECT_NEAR(got.twist_body.angular.z, 0.3, 1e-14);
  set.request.pose.orientation.w *= 1.001;  // |q| off by ~1e-3
  const auto refused = call("set_state", set).response;
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("unit quaternion"), std::string::npos) << refused.message;
  set.request.pose.orientation.w = std::nan("");
  EXPECT_FALSE(call("set_state", set).response.success);
  EXPECT_NEAR(state().pose.position.x, 1.5, 1e-15);  // the refused requests changed nothing
}

TEST_F(Control, LockstepRunsFasterThanRealTimeAndResetKeepsStampsIncreasing) {
  resetTime();
  Recorder<nav_msgs::Odometry> odom(nh_, "lock/odom");
  Recorder<rosgraph_msgs::Clock> clock(nh_, "/clock");
  ASSERT_TRUE(odom.waitForConnection() && clock.waitForConnection());
  pause();
  ASSERT_TRUE(apply("world", Eigen::Vector3d(1.0, 0.0, 0.0), -1.0).success);  // moving when reset comes
  unpause();
  const ros::WallTime start = ros::WallTime::now();
  ASSERT_TRUE(waitUntil([&] { return !clock.messages.empty() && clock.messages.back().clock.toSec() >= 5.0; }, 30.0));
  const double wall = (ros::WallTime::now() - start).toSec();
  // real_time_factor 0: not paced. A node paced at real time would need the full 5 s (no speed is asserted).
  EXPECT_LT(wall, 5.0) << "5 s of sim time took " << wall << " s";
  // Odometry comes on a connection of its own and may trail /clock: wait for a message from the last second.
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && odom.messages.back().header.stamp.toSec() >= 4.0; }, 30.0));
  // At full speed a subscriber may miss messages (documented); those it gets are in sim time, in order.
  ASSERT_GT(odom.messages.size(), 10u);
  for (size_t i = 1; i < odom.messages.size(); ++i) {
    ASSERT_GT(odom.messages[i].header.stamp, odom.messages[i - 1].header.stamp);
  }
  // Sim time: seconds since the lockstep start on the 10 ms publish grid, not wall-clock epoch seconds.
  for (const auto& message : odom.messages) {
    const double stamp = message.header.stamp.toSec();
    ASSERT_LT(stamp, 1000.0);
    ASSERT_NEAR(std::remainder(stamp, 0.01), 0.0, 1e-9) << stamp;
  }
  // reset of a moving body: state back, the wrench gone, time keeps going.
  ASSERT_GT(worldVelocity(odom.messages.back()).x(), 1.0);
  const ros::Time before = odom.messages.back().header.stamp;
  call<std_srvs::Empty>("reset");
  pause();
  const auto after = state();
  EXPECT_GT(after.stamp, before);
  EXPECT_EQ(vec(after.twist_world.linear), Eigen::Vector3d::Zero());
  EXPECT_EQ(after.pose.position.x, 0.0);
  ASSERT_TRUE(step(100).success);  // the open-ended wrench was cleared: the body stays at rest
  EXPECT_EQ(vec(state().twist_world.linear), Eigen::Vector3d::Zero());
}

TEST_F(Control, NoisyOdometryHasTheConfiguredStatisticsAndCovariances) {
  resetTime();
  pause();
  // Turned 90° about world z, at rest: body x is world y. The noise must have the declared covariance in the
  // frames the message declares: pose (position and orientation) about the world axes, twist in body axes.
  rigid_body_sim::SetState turn;
  turn.request.pose.orientation = tf2::toMsg(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())));
  ASSERT_TRUE(call("set_state", turn).response.success);
  Recorder<nav_msgs::Odometry> truth(nh_, "lock/odom");
  Recorder<nav_msgs::Odometry> noisy(nh_, "lock/odom_noisy");
  ASSERT_TRUE(truth.waitForConnection() && noisy.waitForConnection());
  // Stepped, one output per request (the node publishes after each `step`), and each pair received before
  // the next: every message arrives. Left running at full speed, the lockstep node outran the recorders'
  // queues, which dropped messages of either topic apart (a loaded CI machine matched 763 pairs of 1 500).
  const std::size_t truth_before = truth.messages.size(), noisy_before = noisy.messages.size();
  for (std::size_t k = 1; k <= 1500; ++k) {
    ASSERT_TRUE(step(10).success);
    ASSERT_TRUE(truth.waitForCount(truth_before + k) && noisy.waitForCount(noisy_before + k)) << "output " << k;
  }
  std::map<double, const nav_msgs::Odometry*> by_stamp;
  for (const auto& message : truth.messages) by_stamp[message.header.stamp.toSec()] = &message;
  // Errors of the noisy copy against the truth at the same stamp: position and the rotation exp(δ_W) in world
  // axes, linear and angular velocity in body axes.
  enum { kPosition, kOrientation, kLinear, kAngular, kQuantities };
  std::array<Eigen::Array3d, kQuantities> sum, sum2;
  for (int k = 0; k < kQuantities; ++k) sum[k] = sum2[k] = Eigen::Array3d::Zero();
  int n = 0;
  for (const auto& message : noisy.messages) {
    const auto found = by_stamp.find(message.header.stamp.toSec());
    if (found == by_stamp.end()) continue;
    const nav_msgs::Odometry& exact = *found->second;
    Eigen::Quaterniond q_noisy, q_exact;
    tf2::fromMsg(message.pose.pose.orientation, q_noisy);
    tf2::fromMsg(exact.pose.pose.orientation, q_exact);
    const Eigen::AngleAxisd delta(q_noisy * q_exact.conjugate());  // exp(δ_W) = q_noisy q_exact⁻¹
    const std::array<Eigen::Array3d, kQuantities> d = {
        (position(message) - position(exact)).array(), (delta.angle() * delta.axis()).array(),
        (vec(message.twist.twist.linear) - vec(exact.twist.twist.linear)).array(),
        (vec(message.twist.twist.angular) - vec(exact.twist.twist.angular)).array()};
    for (int k = 0; k < kQuantities; ++k) sum[k] += d[k], sum2[k] += d[k] * d[k];
    ++n;
  }
  ASSERT_GT(n, 1000);
  // Root mean square about zero (not about the sample mean, so a biased noise fails) against the configured
  // deviation: the relative standard error of n normals' RMS is 1/√(2n) ≈ 2 %, 4 of them allowed; the mean
  // within 4 σ/√n of zero.
  const std::array<Eigen::Array3d, kQuantities> configured = {
      Eigen::Array3d(0.01, 0.02, 0.03), Eigen::Array3d(0.001, 0.002, 0.003), Eigen::Array3d(0.1, 0.1, 0.1),
      Eigen::Array3d(0.05, 0.05, 0.05)};
  for (int k = 0; k < kQuantities; ++k) {
    for (int i = 0; i < 3; ++i) {
      const double rms = std::sqrt(sum2[k](i) / n), mean = sum[k](i) / n;
      EXPECT_NEAR(rms / configured[k](i), 1.0, 4.0 / std::sqrt(2.0 * n)) << "quantity " << k << ", axis " << i;
      EXPECT_LT(std::abs(mean), 4.0 * configured[k](i) / std::sqrt(n)) << "quantity " << k << ", axis " << i;
    }
  }
  const auto& covariance = noisy.messages.back().pose.covariance;
  EXPECT_DOUBLE_EQ(covariance[0], 1e-4);
  EXPECT_DOUBLE_EQ(covariance[7], 4e-4);
  EXPECT_DOUBLE_EQ(covariance[35], 9e-6);
  EXPECT_DOUBLE_EQ(noisy.messages.back().twist.covariance[0], 0.01);
  EXPECT_EQ(truth.messages.back().pose.covariance[0], 0.0);  // ground truth stays exact
}

TEST_F(Control, ASteppedRunIsReproducibleBitForBit) {
  const auto run = [&] {
    resetTime();
    pause();
    std::vector<rigid_body_sim::GetState::Response> trace;
    // The same inputs at the same step indices: a push, a torque at a point, a body-frame force.
    const Eigen::Vector3d point(0.05, 0.0, 0.02);
    apply("world", Eigen::Vector3d(1.0, 0.5, 0.0), 0.05);
    step(20);
    trace.push_back(state());
    apply("lock_link", Eigen::Vector3d(0.0, 0.3, 0.1), 0.03, &point);
    step(50);
    trace.push_back(state());
    apply("lock_link", Eigen::Vector3d(0.2, 0.0, 0.0), -1.0);
    step(200);
    trace.push_back(state());
    call<std_srvs::Empty>("clear_wrenches");
    return trace;
  };
  const auto first = run(), second = run();
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].stamp, second[i].stamp);
    EXPECT_EQ(first[i].pose, second[i].pose) << i;                // == on every field: bit for bit
    EXPECT_EQ(first[i].twist_world, second[i].twist_world) << i;
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "control_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
