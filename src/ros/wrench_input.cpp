#include "rigid_body_sim/ros/wrench_input.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>

#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"
#include "rigid_body_sim/wrench_limits.hpp"

namespace rigid_body_ros {

namespace {
// Warnings about bad input repeat at most this often [s], however fast the input comes.
constexpr double kWarningPeriod = 2.0;
// Distinct unknown frames remembered for their own warning period; beyond this the memory starts over.
constexpr std::size_t kMaxWarnedFrames = 256;
// How far up the tf tree a frame is followed to find out whether it belongs to the body.
constexpr int kMaxTreeDepth = 64;
// Subscriber queues: a burst beyond this between two spins drops the oldest messages (roscpp's policy).
constexpr uint32_t kQueueSize = 10;

// A wrench given in a frame F fixed in the body (at X_BF), about F's origin or `point` (in F): in body axes
// about the centre of mass, F_B = R_BF F_F and τ_B = R_BF τ_F + p_BQ × F_B. It turns with the body and its
// lever arm stays fixed in body axes.
rigid_body::Wrench bodyFixedWrench(const geometry_msgs::Wrench& wrench, const Eigen::Isometry3d& X_BF,
                                   const Eigen::Vector3d* point) {
  const WrenchAtPoint at = wrenchAtPointInWorld(wrench, X_BF, point);  // "world" = B here
  rigid_body::Wrench body;
  body.force = at.wrench_W.force;
  body.torque = at.wrench_W.torque + at.p_WQ.cross(at.wrench_W.force);
  return body;
}

std::string withoutLeadingSlash(const std::string& frame) {
  const std::size_t first = frame.find_first_not_of('/');
  return first == std::string::npos ? std::string() : frame.substr(first);
}
}  // namespace

WrenchInput::WrenchInput(ros::NodeHandle& nh, const NodeConfig& config, rigid_body::World& world,
                         std::function<rigid_body::Nanoseconds()> now, const OwnTransforms& own_transforms)
    : config_(config),
      world_(world),
      now_(std::move(now)),
      foreign_transforms_(tf_buffer_, own_transforms, nh),
      nh_(nh) {
  if (!config.publish.per_body_topics) {
    // One subscriber for the whole scene; the bodies found by name.
    scene_subscriber_ = nh.subscribe<rigid_body_sim::BodyWrenches>(
        "bodies/wrench", kQueueSize, [this](const rigid_body_sim::BodyWrenches::ConstPtr& m) { onBodyWrenches(*m); });
  }
  for (std::size_t body = 0; body < config.bodies.size(); ++body) addBody(body);
}

void WrenchInput::addBody(std::size_t body) {
  const BodyConfig& body_config = config_.bodies[body];
  body_by_frame_[body_config.body_frame] = body;
  if (!config_.publish.per_body_topics) body_by_name_[body_config.name] = body;
  messages_.push_back(0);
  refused_messages_.push_back(0);
  if (!config_.publish.per_body_topics || !body_config.wrench_input) return;  // no input term: no subscriber
  // The callbacks read the body's index where the list keeps it up to date.
  auto& own = topics_.append(body);
  own.handles.stamped = nh_.subscribe<geometry_msgs::WrenchStamped>(
      body_config.topic("wrench"), kQueueSize,
      [this, &own](const geometry_msgs::WrenchStamped::ConstPtr& m) { onWrench(own.body, *m); });
  own.handles.unstamped = nh_.subscribe<geometry_msgs::Wrench>(
      body_config.topic("wrench_unstamped"), kQueueSize,
      [this, &own](const geometry_msgs::Wrench::ConstPtr& m) { onWrenchUnstamped(own.body, *m); });
}

void WrenchInput::removeBody(std::size_t body) {
  topics_.erase(body);  // its subscribers shut down (roscpp drops their queued callbacks)
  for (auto* map : {&body_by_frame_, &body_by_name_}) {
    for (auto entry = map->begin(); entry != map->end();) {
      if (entry->second == body) {
        entry = map->erase(entry);
        continue;
      }
      entry->second -= entry->second > body ? 1 : 0;
      ++entry;
    }
  }
  const auto at = static_cast<std::ptrdiff_t>(body);
  messages_.erase(messages_.begin() + at);
  refused_messages_.erase(refused_messages_.begin() + at);
}

bool WrenchInput::accept(const geometry_msgs::Wrench& wrench) {
  switch (rigid_body::checkWrench(toWrench(wrench), config_.wrench_limits)) {
    case rigid_body::WrenchVerdict::kAccepted:
      return true;
    case rigid_body::WrenchVerdict::kNonFinite:
      ++rejections_.non_finite;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench with a non-finite component (%lu so far)",
                        static_cast<unsigned long>(rejections_.non_finite));
      return false;
    case rigid_body::WrenchVerdict::kForceOverLimit:
      ++rejections_.force_limit;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench: |force| above max_force = %g N (%lu so far)",
                        config_.wrench_limits.max_force, static_cast<unsigned long>(rejections_.force_limit));
      return false;
    case rigid_body::WrenchVerdict::kTorqueOverLimit:
      ++rejections_.torque_limit;
      ROS_WARN_THROTTLE(kWarningPeriod,
                        "rigid_body_node: rejected a wrench: |torque| above max_torque = %g N m (%lu so far)",
                        config_.wrench_limits.max_torque, static_cast<unsigned long>(rejections_.torque_limit));
      return false;
  }
  return false;
}

std::optional<std::size_t> WrenchInput::bodyAbove(const std::string& frame) const {
  std::string current = frame, parent;
  // Up the tree from `frame` (a bounded walk: a tree deeper than this is not a robot's body). A body's frame
  // has no parent in the buffer (the node's own /tf stays out), so the walk ends at the first one.
  for (int depth = 0; depth < kMaxTreeDepth; ++depth) {
    const auto found = body_by_frame_.find(current);
    if (found != body_by_frame_.end()) return found->second;
    if (!tf_buffer_._getParent(current, ros::Time(0), parent) || parent == current) return std::nullopt;
    current = parent;
  }
  return std::nullopt;
}

Eigen::Isometry3d WrenchInput::lookup(const std::string& target, const std::string& source, const ros::Time& stamp) const {
  if (target == source) return Eigen::Isometry3d::Identity();
  const ros::Time when = !stamp.isZero() && tf_buffer_.canTransform(target, source, stamp, nullptr) ? stamp : ros::Time(0);
  return tf2::transformToEigen(tf_buffer_.lookupTransform(target, source, when));
}

Eigen::Isometry3d WrenchInput::publishedPose(std::size_t body) const {
  const rigid_body::State& state = world_.scene().state(body);
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = state.q_WB.toRotationMatrix();
  X_WB.translation() = state.p_WB;
  return X_WB * config_.bodies[body].X_BP;
}

void WrenchInput::warnUnknownFrame(const std::string& frame, const std::string& error) {
  const ros::WallTime now = ros::WallTime::now();
  if (last_frame_warning_.size() >= kMaxWarnedFrames) last_frame_warning_.clear();
  const auto found = last_frame_warning_.find(frame);
  if (found != last_frame_warning_.end() && (now - found->second).toSec() < kWarningPeriod) return;
  last_frame_warning_[frame] = now;
  ROS_WARN("rigid_body_node: rejected a wrench in frame '%s' (%lu unknown-frame rejections so far): %s",
           frame.c_str(), static_cast<unsigned long>(rejections_.unknown_frame), error.c_str());
}

bool WrenchInput::convert(std::size_t body, const geometry_msgs::Wrench& wrench, const std::string& frame_id,
                          const ros::Time& stamp, const Eigen::Vector3d* point, ConvertedWrench& out) {
  out = ConvertedWrench();
  rigid_body::Wrench given = toWrench(wrench);
  const std::string frame = withoutLeadingSlash(frame_id);
  if (frame.empty() && !frame_id.empty()) {  // "/" alone names no frame
    ++rejections_.unknown_frame;
    warnUnknownFrame(frame_id, "not a frame id");
    return false;
  }
  bool finite = true;
  switch (classifyWrenchFrame(frame, config_.world_frame, config_.bodies[body].body_frame)) {
    case WrenchFrame::kBody:
      if (config_.bodies[body].published_offset) {
        // The published frame is a URDF link frame P at X_BP: its axes about its origin (or the point).
        out.wrench.body = bodyFixedWrench(wrench, config_.bodies[body].X_BP, point);
        finite = out.wrench.body.isFinite();
        break;
      }
      // Body axes about the centre of mass (the body frame's origin): turns with the body.
      if (point) given.torque += point->cross(given.force);
      out.wrench.body = given;
      finite = given.isFinite();
      break;
    case WrenchFrame::kWorld:
      out.wrench.world = given;
      if (point) {
        out.has_point = true;
        out.p_WQ = *point;
      }
      break;
    case WrenchFrame::kOther: {
      // The frame's place: below one of this node's bodies (the body's pose now, then tf2 from its published
      // frame P), or elsewhere in the tree (tf2 from the world frame); at the stamp if tf2 has it, else the
      // latest transform; never a wait.
      std::optional<std::size_t> owner;
      Eigen::Isometry3d X_AF;  // from the frame F to the anchor A: P of the owner, or the world frame
      try {
        owner = bodyAbove(frame);
        X_AF = lookup(owner ? config_.bodies[*owner].body_frame : config_.world_frame, frame, stamp);
      } catch (const tf2::TransformException& exception) {
        ++rejections_.unknown_frame;
        warnUnknownFrame(frame, exception.what());
        return false;
      }
      if (owner && *owner == body) {
        // A frame of the body itself (a thruster or sensor link published relative to body_frame): the wrench
        // is fixed in the body. X_BF = X_BP X_PF (X_BP the identity but for a URDF link).
        out.wrench.body = bodyFixedWrench(wrench, config_.bodies[body].X_BP * X_AF, point);
        finite = out.wrench.body.isFinite();
        break;
      }
      // Any other frame (another body's included): held in world axes at the point where it is now.
      const Eigen::Isometry3d X_WF = owner ? publishedPose(*owner) * X_AF : X_AF;
      const WrenchAtPoint at = wrenchAtPointInWorld(wrench, X_WF, point);
      out.wrench.world = at.wrench_W;
      out.has_point = true;
      out.p_WQ = at.p_WQ;
      finite = at.wrench_W.isFinite() && at.p_WQ.allFinite();
      break;
    }
  }
  if (!finite) {
    ++rejections_.non_finite;
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench whose change of frame overflowed (%lu so far)",
                      static_cast<unsigned long>(rejections_.non_finite));
    return false;
  }
  return true;
}

bool WrenchInput::submit(std::size_t body, const ConvertedWrench& converted) {
  const rigid_body::CommandReply reply =
      world_.setWrench(body, converted.wrench, now_(), converted.has_point ? &converted.p_WQ : nullptr);
  if (!reply.accepted) {
    ++rejections_.refused_by_core;
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: wrench refused: %s", reply.message.c_str());
  }
  return reply.accepted;
}

void WrenchInput::countMessage(std::size_t body, bool accepted) {
  ++messages_[body];
  if (!accepted) ++refused_messages_[body];
}

bool WrenchInput::handleStamped(std::size_t body, const geometry_msgs::WrenchStamped& message) {
  // The wrench acts from its arrival; its stamp only chooses the transform of a foreign frame (a stamp far in
  // the past or the future, as `rostopic pub` gives under sim time, neither delays nor drops it).
  if (!accept(message.wrench)) return false;
  ConvertedWrench converted;
  if (!convert(body, message.wrench, message.header.frame_id, message.header.stamp, nullptr, converted)) return false;
  return submit(body, converted);
}

void WrenchInput::onWrench(std::size_t body, const geometry_msgs::WrenchStamped& message) {
  countMessage(body, handleStamped(body, message));
}

void WrenchInput::onBodyWrenches(const rigid_body_sim::BodyWrenches& message) {
  // A message has a use for one wrench per body at most (a later one for the same body replaces the earlier),
  // so one with more items than the scene has bodies is refused whole: each item costs a conversion and
  // perhaps a tf lookup, and a message of 300 000 items in an unknown frame held the callbacks for 1.5 s.
  if (message.wrenches.size() > config_.bodies.size()) {
    ++rejections_.oversized;
    ROS_WARN_THROTTLE(kWarningPeriod,
                      "rigid_body_node: bodies/wrench: a message of %zu wrenches for a scene of %zu bodies is refused "
                      "whole: at most one per body (%lu so far)",
                      message.wrenches.size(), config_.bodies.size(), static_cast<unsigned long>(rejections_.oversized));
    return;
  }
  for (const rigid_body_sim::BodyWrench& item : message.wrenches) {
    const auto found = body_by_name_.find(item.body);
    if (found == body_by_name_.end() || !config_.bodies[found->second].wrench_input) {
      ++rejections_.unknown_body;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: bodies/wrench: no body '%s' that takes wrenches (%lu so far)",
                        item.body.c_str(), static_cast<unsigned long>(rejections_.unknown_body));
      continue;
    }
    onWrench(found->second, item.wrench);  // counted as its body's message
  }
}

bool WrenchInput::handleUnstamped(std::size_t body, const geometry_msgs::Wrench& message) {
  // wrench_unstamped: world axes about the centre of mass (a drop-in for gazebo_ros_force users).
  if (!accept(message)) return false;
  ConvertedWrench converted;
  converted.wrench.world = toWrench(message);
  return submit(body, converted);
}

void WrenchInput::onWrenchUnstamped(std::size_t body, const geometry_msgs::Wrench& message) {
  countMessage(body, handleUnstamped(body, message));
}

}  // namespace rigid_body_ros
