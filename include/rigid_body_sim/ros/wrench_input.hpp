// Wrench messages into core commands: limits and finiteness checked (rejections counted by reason, warned
// at most every few seconds), the frame resolved through tf2 once, at arrival, and the result handed to the
// World stamped with its arrival. A frame that hangs below body_frame in the tf tree is part of the body:
// its wrench is held in body axes (it turns with the body); any other frame's is held in world axes. Owns the
// per-body wrench subscribers and the tf2 buffer of the other nodes' transforms (ForeignTransforms). A tf2
// lookup never waits: the transform at the message's stamp if tf2 has it, else the latest one, else the
// wrench is refused at once (a callback that waited would hold up the timer on the node's single spinner
// thread). The node's own bodies are not in the buffer: a frame that hangs below one of them (or is one)
// is placed by that body's current pose in the World, exact, with the rest of the chain from tf2.
#pragma once

#include <geometry_msgs/Wrench.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/ros.h>
#include <tf2/buffer_core.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "rigid_body_sim/BodyWrenches.h"
#include "rigid_body_sim/ros/body_list.hpp"
#include "rigid_body_sim/ros/foreign_transforms.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

/// Wrenches refused before they reached the core, by reason.
struct WrenchRejections {
  std::uint64_t non_finite = 0;      ///< a NaN or Inf component, or a frame change that overflowed
  std::uint64_t force_limit = 0;     ///< |F| above max_force
  std::uint64_t torque_limit = 0;    ///< |τ| above max_torque
  std::uint64_t unknown_frame = 0;   ///< a frame tf2 could not resolve
  std::uint64_t refused_by_core = 0; ///< the World refused the command (queue full, body without input)
  std::uint64_t unknown_body = 0;    ///< bodies/wrench items naming no body that takes wrenches
  std::uint64_t oversized = 0;       ///< bodies/wrench messages with more wrenches than the scene has bodies
  std::uint64_t total() const {
    return non_finite + force_limit + torque_limit + unknown_frame + refused_by_core + unknown_body + oversized;
  }
};

/// A message wrench in the core's terms: body- or world-fixed parts, and for a world-held wrench the point
/// its torque is about.
struct ConvertedWrench {
  rigid_body::AppliedWrench wrench;
  bool has_point = false;
  Eigen::Vector3d p_WQ = Eigen::Vector3d::Zero();
};

class WrenchInput {
 public:
  /// `now` gives the arrival time of a message on the node's clock.
  /// `own_transforms` are the node's /tf messages, left out of the tf buffer.
  WrenchInput(ros::NodeHandle& nh, const NodeConfig& config, rigid_body::World& world,
              std::function<rigid_body::Nanoseconds()> now, const OwnTransforms& own_transforms);

  /// Limits and finiteness of a wrench as sent (magnitudes are the same in any axes); counts and warns.
  bool accept(const geometry_msgs::Wrench& wrench);
  /// Resolves `frame` (world, body, or any tf2 frame; a leading '/' is dropped) for `body`; `point`, if
  /// given, is where the force acts, in `frame`. False (counted, warned) if the frame is unknown or the
  /// change of frame overflows.
  bool convert(std::size_t body, const geometry_msgs::Wrench& wrench, const std::string& frame, const ros::Time& stamp,
               const Eigen::Vector3d* point, ConvertedWrench& out);

  const WrenchRejections& rejections() const { return rejections_; }
  /// Wrench messages delivered to `body` on its topics since start-up, and how many of them were refused:
  /// the handshake a lockstep test waits on (GetState.srv).
  std::uint64_t messages(std::size_t body) const { return messages_[body]; }
  std::uint64_t refusedMessages(std::size_t body) const { return refused_messages_[body]; }

  /// The body the config now has last, at `body`: its wrench topics.
  void addBody(std::size_t body);
  /// The body at `body` is gone: its subscribers shut down, the later bodies move down one index.
  void removeBody(std::size_t body);

 private:
  void onWrench(std::size_t body, const geometry_msgs::WrenchStamped& message);
  void onWrenchUnstamped(std::size_t body, const geometry_msgs::Wrench& message);
  /// Accepts, converts and submits one message's wrench; false if any of those refused it.
  bool handleStamped(std::size_t body, const geometry_msgs::WrenchStamped& message);
  bool handleUnstamped(std::size_t body, const geometry_msgs::Wrench& message);
  void countMessage(std::size_t body, bool accepted);
  /// bodies/wrench (publish/per_body_topics: false): each item as if on its body's own wrench topic.
  void onBodyWrenches(const rigid_body_sim::BodyWrenches& message);
  bool submit(std::size_t body, const ConvertedWrench& converted);
  void warnUnknownFrame(const std::string& frame, const std::string& error);
  /// The first of this node's bodies met going up the tf tree from `frame` (`frame` itself included): the
  /// body it is attached to, if any.
  std::optional<std::size_t> bodyAbove(const std::string& frame) const;
  /// The transform from `source` to `target` at `stamp` if tf2 has it, else the latest one; throws
  /// tf2::TransformException if there is none.
  Eigen::Isometry3d lookup(const std::string& target, const std::string& source, const ros::Time& stamp) const;
  /// Where a body's published frame is now: X_WP = X_WB X_BP, from the World.
  Eigen::Isometry3d publishedPose(std::size_t body) const;

  const NodeConfig& config_;
  rigid_body::World& world_;
  std::function<rigid_body::Nanoseconds()> now_;
  WrenchRejections rejections_;
  tf2::BufferCore tf_buffer_;
  ForeignTransforms foreign_transforms_;  ///< fills tf_buffer_
  std::unordered_map<std::string, std::size_t> body_by_frame_;  ///< this node's published frames
  ros::NodeHandle nh_;
  struct WrenchTopics {
    ros::Subscriber stamped, unstamped;
  };
  BodyList<WrenchTopics> topics_;  ///< per body with wrench input and per-body topics
  ros::Subscriber scene_subscriber_;  ///< bodies/wrench, without per-body topics
  std::map<std::string, ros::WallTime> last_frame_warning_;  ///< per unknown frame (bounded)
  std::unordered_map<std::string, std::size_t> body_by_name_;  ///< for bodies/wrench
  std::vector<std::uint64_t> messages_;          ///< per body: wrench messages delivered
  std::vector<std::uint64_t> refused_messages_;  ///< per body: of those, refused
};

}  // namespace rigid_body_ros
