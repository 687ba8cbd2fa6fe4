// The node's scene edits: spawn, remove and list_bodies. The World takes or drops the body first (it may
// refuse: an overlap); then the config and every component that keeps something per body follow, in the
// same order, so that a body's index means the same body everywhere.
#include <ros/ros.h>

#include "rigid_body_sim/ListBodies.h"
#include "rigid_body_sim/Remove.h"
#include "rigid_body_sim/Spawn.h"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/ros/body_properties.hpp"
#include "rigid_body_sim/ros/body_spawner.hpp"
#include "rigid_body_sim/ros/node_diagnostics.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {
constexpr double kWarningPeriod = 2.0;  // [s] between repeats of a refusal's warning
}  // namespace

void SimulatorNode::refuseEdit(const std::string& message) {
  ++refused_edits_;
  ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %s (%lu edits refused so far)", message.c_str(),
                    static_cast<unsigned long>(refused_edits_));
}

void SimulatorNode::logBody(std::size_t body) const {
  const BodyConfig& config = config_.bodies[body];
  // What this body's step evaluates (the rest of Ẏ is left out: see StepTerms), and what it is.
  rigid_body_sim::GetProperties::Response properties;
  fillProperties(config, rigid_body::integratorName(world_.scene().integratorType()), world_.scene().terms(body),
                 properties);
  ROS_INFO("rigid_body_node: body %s (%s): %s; step assembled from %s",
           config.name.empty() ? "(flat)" : config.name.c_str(), config.body_frame.c_str(),
           describeProperties(properties).c_str(), describeBodyStep(world_.scene(), body, config_).c_str());
  if (config.mesh_path.empty()) return;
  const Eigen::Vector3d& c = config.X_MB.translation();
  const Eigen::Quaterniond q_MB(config.X_MB.linear());
  ROS_INFO("rigid_body_node: body frame %s = mesh frame moved to the centre of mass (%g, %g, %g) m and turned by "
           "q = [%g, %g, %g, %g] (x, y, z, w)%s",
           config.body_frame.c_str(), c.x(), c.y(), c.z(), q_MB.x(), q_MB.y(), q_MB.z(), q_MB.w(),
           config.mesh_frame.empty() ? "" : ("; published as tf " + config.body_frame + " -> " + config.mesh_frame).c_str());
  for (const std::string& warning : config.mesh_warnings) ROS_WARN("rigid_body_node: %s", warning.c_str());
}

void SimulatorNode::advertiseEditServices() {
  using rigid_body_sim::ListBodies;
  using rigid_body_sim::Remove;
  using rigid_body_sim::Spawn;
  edit_services_.push_back(nh_.advertiseService<Spawn::Request, Spawn::Response>(
      "spawn", [this](Spawn::Request& request, Spawn::Response& response) {
        response.success = spawn(request.body, response.message);
        return true;
      }));
  edit_services_.push_back(nh_.advertiseService<Remove::Request, Remove::Response>(
      "remove", [this](Remove::Request& request, Remove::Response& response) {
        response.success = remove(request.name, response.message);
        return true;
      }));
  edit_services_.push_back(nh_.advertiseService<ListBodies::Request, ListBodies::Response>(
      "list_bodies", [this](ListBodies::Request&, ListBodies::Response& response) {
        for (std::size_t body = 0; body < config_.bodies.size(); ++body) {
          const BodyConfig& config = config_.bodies[body];
          response.names.push_back(config.name);
          response.body_frames.push_back(config.body_frame);
          response.shapes.push_back(config.shapeLabel());
          response.masses.push_back(config.model.mass.mass());
          response.colliding.push_back(world_.scene().collides(body));
        }
        return true;
      }));
}

void SimulatorNode::addToComponents(const BodyConfig& config) {
  config_.bodies.push_back(config);
  const std::size_t body = config_.bodies.size() - 1;
  wrench_input_.addBody(body);
  outputs_.addBody(body);
  imu_.addBody(body);
  services_.addBody(body);
  markers_.bodiesChanged(body);
  publishStaticFrames(toRosTime(world_.stamp()));  // its mesh and sensor frames, if any
}

void SimulatorNode::removeFromComponents(std::size_t body) {
  wrench_input_.removeBody(body);
  outputs_.removeBody(body);
  imu_.removeBody(body);
  services_.removeBody(body);
  config_.bodies.erase(config_.bodies.begin() + static_cast<std::ptrdiff_t>(body));
  markers_.bodiesChanged(config_.bodies.size() + 1);
  publishStaticFrames(toRosTime(world_.stamp()));  // without its mesh and sensor frames
}

bool SimulatorNode::spawn(const std::string& yaml, std::string& message) {
  BodyConfig body;
  try {
    body = parseSpawnedBody(yaml, config_, parameterServerReader());
  } catch (const ParameterError& error) {
    message = error.what();
    refuseEdit(message);
    return false;
  }
  std::size_t index = 0;
  const rigid_body::CommandReply reply =
      world_.addBody({body.model, body.initial, body.wrench_input}, body.collision, &index);
  if (!reply.accepted) {
    message = "spawn: " + body.name + " refused: " + reply.message;
    refuseEdit(message);
    return false;
  }
  addToComponents(body);  // at `index`, the last, as in the World
  logBody(index);
  message = "spawned " + body.name + " (" + body.body_frame + ") at t = " + std::to_string(toSeconds(world_.stamp())) + " s";
  ROS_INFO("rigid_body_node: %s", message.c_str());
  return true;
}

bool SimulatorNode::remove(const std::string& name, std::string& message) {
  const std::size_t body = findBody(config_, name);
  if (body == config_.bodies.size()) {
    message = "remove: no body called '" + name + "' (list_bodies names them)";
    refuseEdit(message);
    return false;
  }
  const rigid_body::CommandReply reply = world_.removeBody(body);
  if (!reply.accepted) {
    message = "remove: " + name + " refused: " + reply.message;
    refuseEdit(message);
    return false;
  }
  removeFromComponents(body);
  message = "removed " + name + " at t = " + std::to_string(toSeconds(world_.stamp())) + " s";
  ROS_INFO("rigid_body_node: %s", message.c_str());
  return true;
}

}  // namespace rigid_body_ros
