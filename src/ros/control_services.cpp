#include "rigid_body_sim/ros/control_services.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <cstdio>

#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/body_properties.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

ControlServices::ControlServices(ros::NodeHandle& nh, const NodeConfig& config, rigid_body::World& world,
                                 WrenchInput& wrench_input, std::function<rigid_body::Nanoseconds()> now,
                                 std::function<void()> clock_moved)
    : config_(config),
      nh_(nh),
      world_(world),
      wrench_input_(wrench_input),
      now_(std::move(now)),
      clock_moved_(std::move(clock_moved)) {
  services_ = {
      nh.advertiseService("reset", &ControlServices::onReset, this),
      nh.advertiseService("reset_time", &ControlServices::onResetTime, this),
      nh.advertiseService("pause", &ControlServices::onPause, this),
      nh.advertiseService("unpause", &ControlServices::onUnpause, this),
      nh.advertiseService("step", &ControlServices::onStep, this),
      nh.advertiseService("clear_wrenches", &ControlServices::onClearWrenches, this),
  };
  for (std::size_t body = 0; body < config.bodies.size(); ++body) addBody(body);
}

void ControlServices::addBody(std::size_t body) {
  using rigid_body_sim::ApplyWrench;
  using rigid_body_sim::GetProperties;
  using rigid_body_sim::GetState;
  using rigid_body_sim::SetState;
  if (!config_.publish.body_services || !config_.publish.per_body_topics) return;
  const BodyConfig& body_config = config_.bodies[body];
  // The callbacks read the body's index where the list keeps it up to date.
  auto& own = body_services_.append(body);
  std::vector<ros::ServiceServer>& servers = own.handles;
  servers.push_back(nh_.advertiseService<GetState::Request, GetState::Response>(
      body_config.topic("get_state"), [this, &own](auto& req, auto& res) { return onGetState(own.body, req, res); }));
  servers.push_back(nh_.advertiseService<GetProperties::Request, GetProperties::Response>(
      body_config.topic("get_properties"),
      [this, &own](auto& req, auto& res) { return onGetProperties(own.body, req, res); }));
  servers.push_back(nh_.advertiseService<SetState::Request, SetState::Response>(
      body_config.topic("set_state"), [this, &own](auto& req, auto& res) { return onSetState(own.body, req, res); }));
  if (!body_config.wrench_input) return;  // no input term: no apply_wrench
  servers.push_back(nh_.advertiseService<ApplyWrench::Request, ApplyWrench::Response>(
      body_config.topic("apply_wrench"),
      [this, &own](auto& req, auto& res) { return onApplyWrench(own.body, req, res); }));
}

void ControlServices::removeBody(std::size_t body) { body_services_.erase(body); }

bool ControlServices::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  if (world_.reset(now_()).accepted) ROS_INFO("rigid_body_node: reset to the initial state, wrenches cleared");
  return true;
}

bool ControlServices::onResetTime(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  if (!world_.ownsClock()) {
    response.success = false;
    response.message = "reset_time rewinds simulated time, which only a lockstep node owns; use reset";
    return true;
  }
  world_.rewind();
  clock_moved_();
  response.success = true;
  response.message = "state and simulated time back to the start";
  ROS_INFO("rigid_body_node: reset_time: state and /clock back to the start");
  return true;
}

bool ControlServices::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_.pause(now_());
  return true;
}

bool ControlServices::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_.unpause(now_());
  return true;
}

bool ControlServices::onStep(rigid_body_sim::Step::Request& request, rigid_body_sim::Step::Response& response) {
  const rigid_body::CommandReply reply = world_.step(request.steps, now_());
  if (reply.accepted && world_.ownsClock()) clock_moved_();  // the clock is ours: publish the new time
  const rigid_body::Scene& scene = world_.scene();
  const std::size_t diverged = scene.firstDiverged();
  response.success = reply.accepted && diverged == scene.bodyCount();
  response.message = !reply.accepted ? reply.message
                     : response.success
                         ? ""
                         : config_.bodies[diverged].body_frame + ": " + rigid_body::divergenceName(scene.divergence(diverged));
  response.sim_time = toSeconds(world_.stamp());
  response.total_steps = scene.integratedSteps();
  return true;
}

bool ControlServices::onClearWrenches(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_.clearWrenches(now_());
  return true;
}

bool ControlServices::onApplyWrench(std::size_t body, rigid_body_sim::ApplyWrench::Request& request,
                                    rigid_body_sim::ApplyWrench::Response& response) {
  response.success = false;
  if (!wrench_input_.accept(request.wrench)) {
    response.message = "wrench rejected: non-finite or above max_force / max_torque";
    return true;
  }
  Eigen::Vector3d point;
  tf2::fromMsg(request.point, point);
  if (request.use_point && !point.allFinite()) {
    response.message = "refused: the point is not finite";
    return true;
  }
  ConvertedWrench converted;
  if (!wrench_input_.convert(body, request.wrench, request.frame_id, request.start_time,
                             request.use_point ? &point : nullptr, converted)) {
    response.message = "frame '" + request.frame_id + "' cannot be resolved by tf2 (or the change of frame overflowed)";
    return true;
  }
  const double duration = request.duration.toSec();
  const rigid_body::CommandReply reply =
      world_.applyWrench(body, converted.wrench, toNanoseconds(request.start_time), duration, now_(),
                         converted.has_point ? &converted.p_WQ : nullptr);
  response.success = reply.accepted;
  if (!reply.accepted) {
    response.message = reply.message;
  } else if (duration < 0.0) {
    response.message = "acting until clear_wrenches";
  } else {
    // Start and end on the step grid: the wrench acts over whole steps, so its impulse is exact to one step.
    char text[64];
    std::snprintf(text, sizeof text, "acting for %.0f steps of dt", std::max(1.0, std::round(duration / config_.dt)));
    response.message = text;
  }
  return true;
}

bool ControlServices::onSetState(std::size_t body, rigid_body_sim::SetState::Request& request,
                                 rigid_body_sim::SetState::Response& response) {
  Eigen::Vector3d p, v, w;
  Eigen::Quaterniond q;
  tf2::fromMsg(request.pose.position, p);
  tf2::fromMsg(request.pose.orientation, q);
  tf2::fromMsg(request.twist.linear, v);
  tf2::fromMsg(request.twist.angular, w);
  response.success = false;
  if (!p.allFinite() || !q.coeffs().allFinite() || !v.allFinite() || !w.allFinite()) {
    response.message = "refused: a non-finite value in pose or twist";
    return true;
  }
  if (std::abs(q.norm() - 1.0) > rigid_body::Integrator::kUnitQuaternionTolerance) {  // then normalised
    response.message = "refused: the orientation is not a unit quaternion (|q| = " + std::to_string(q.norm()) +
                       ", allowed 1 +- 1e-6)";
    return true;
  }
  const std::string& frame = request.twist_frame;
  if (!frame.empty() && frame != "body" && frame != "world") {
    response.message = "refused: twist_frame must be 'body' (or empty) or 'world', got '" + frame + "'";
    return true;
  }
  q.normalize();
  const bool world_axes = frame == "world";
  const Eigen::Vector3d v_W = world_axes ? v : Eigen::Vector3d(q * v);
  const Eigen::Vector3d w_B = world_axes ? Eigen::Vector3d(q.conjugate() * w) : w;
  rigid_body::State state = rigid_body::stateFromVelocities(world_.scene().model(body).mass, p, q, v_W, w_B);
  state.t = world_.scene().state(body).t;
  const rigid_body::CommandReply reply = world_.setState(body, state, now_());
  response.success = reply.accepted;
  response.message = reply.message;
  return true;
}

bool ControlServices::onGetState(std::size_t body, rigid_body_sim::GetState::Request&,
                                 rigid_body_sim::GetState::Response& response) {
  const rigid_body::State& state = world_.scene().state(body);
  const rigid_body::Motion motion = rigid_body::motionOf(world_.scene().model(body).mass, state);
  response.stamp = toRosTime(world_.stamp());
  response.pose.position = tf2::toMsg(state.p_WB);
  response.pose.orientation = tf2::toMsg(state.q_WB);
  tf2::toMsg(motion.v_WB_W, response.twist_world.linear);
  tf2::toMsg(motion.w_WB_W, response.twist_world.angular);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.v_WB_W), response.twist_body.linear);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.w_WB_W), response.twist_body.angular);
  response.total_steps = world_.scene().integratedSteps(body);
  response.paused = world_.paused();
  response.wrench_messages = wrench_input_.messages(body);
  response.wrench_messages_refused = wrench_input_.refusedMessages(body);
  return true;
}

bool ControlServices::onGetProperties(std::size_t body, rigid_body_sim::GetProperties::Request&,
                                      rigid_body_sim::GetProperties::Response& response) {
  fillProperties(config_.bodies[body], rigid_body::integratorName(world_.scene().integratorType()),
                 world_.scene().terms(body), response);
  return true;
}

}  // namespace rigid_body_ros
