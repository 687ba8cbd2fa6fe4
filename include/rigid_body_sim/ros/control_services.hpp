// The node's services, each a translation of a request into one World command and of its reply into the
// response: scene-wide reset, reset_time, pause, unpause, step, clear_wrenches; per body get_state,
// get_properties, set_state and (with wrench input) apply_wrench.
#pragma once

#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include <functional>
#include <vector>

#include "rigid_body_sim/ApplyWrench.h"
#include "rigid_body_sim/GetProperties.h"
#include "rigid_body_sim/GetState.h"
#include "rigid_body_sim/SetState.h"
#include "rigid_body_sim/Step.h"
#include "rigid_body_sim/ros/body_list.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/wrench_input.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class ControlServices {
 public:
  /// `now` gives a request's arrival on the node's clock; `clock_moved` is called after a request moved
  /// the world's own clock (lockstep step and reset_time), to publish /clock and the state at once.
  ControlServices(ros::NodeHandle& nh, const NodeConfig& config, rigid_body::World& world, WrenchInput& wrench_input,
                  std::function<rigid_body::Nanoseconds()> now, std::function<void()> clock_moved);

  /// The body the config now has last, at `body`: its services.
  void addBody(std::size_t body);
  /// The body at `body` is gone: its services shut down, the later bodies move down one index.
  void removeBody(std::size_t body);

  bool onReset(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onResetTime(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onPause(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onUnpause(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onStep(rigid_body_sim::Step::Request& request, rigid_body_sim::Step::Response& response);
  bool onClearWrenches(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onApplyWrench(std::size_t body, rigid_body_sim::ApplyWrench::Request& request,
                     rigid_body_sim::ApplyWrench::Response& response);
  bool onSetState(std::size_t body, rigid_body_sim::SetState::Request& request,
                  rigid_body_sim::SetState::Response& response);
  /// The state of the last update (its stamp says when); no step is taken for the request.
  bool onGetState(std::size_t body, rigid_body_sim::GetState::Request& request,
                  rigid_body_sim::GetState::Response& response);
  /// What the body is (body_properties.hpp): constant but for its step terms, which live settings change.
  bool onGetProperties(std::size_t body, rigid_body_sim::GetProperties::Request& request,
                       rigid_body_sim::GetProperties::Response& response);

 private:
  const NodeConfig& config_;
  ros::NodeHandle nh_;
  rigid_body::World& world_;
  WrenchInput& wrench_input_;
  std::function<rigid_body::Nanoseconds()> now_;
  std::function<void()> clock_moved_;
  std::vector<ros::ServiceServer> services_;                     ///< the scene's
  BodyList<std::vector<ros::ServiceServer>> body_services_;       ///< per body
};

}  // namespace rigid_body_ros
