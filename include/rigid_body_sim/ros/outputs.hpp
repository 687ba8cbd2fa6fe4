// The state out: per body NAME/odom, NAME/state, NAME/applied_wrench and NAME/odom_noisy, every body's
// transform in one tf message per tick, /clock in lockstep, the static mesh frames. tf, odometry and state
// go out every tick or at rates of their own (publish/tf_rate, odom_rate, state_rate: OutputSchedule).
// bodies/states carries every body's pose and twist in one message, in every scene. Only enabled outputs
// have a publisher, and an output nobody listens to is not even filled (roscpp finds a publication by a
// linear search over every advertised topic, so 1000 bodies' unheard odometry alone cost O(N²) a tick).
// Constant fields (frame ids, covariances) are filled once; a message with a non-finite field is never sent.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "rigid_body_sim/BodyStates.h"
#include "rigid_body_sim/Contacts.h"
#include "rigid_body_sim/OdometryArray.h"
#include "rigid_body_sim/RigidBodyState.h"
#include "rigid_body_sim/ros/odometry_noise.hpp"
#include "rigid_body_sim/ros/output_schedule.hpp"
#include "rigid_body_sim/ros/own_transforms.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class Outputs {
 public:
  /// Every body's pose goes out on /tf through `own_transforms`.
  Outputs(ros::NodeHandle& nh, const NodeConfig& config, OwnTransforms& own_transforms);

  /// The static tf body_frame → mesh_frame of the bodies that have one, and `others` (the sensors' frames), in
  /// one latched message: a second static broadcaster of the node would replace the first's.
  void publishStaticFrames(const ros::Time& stamp, std::vector<geometry_msgs::TransformStamped> others);
  /// Every body's enabled outputs, stamped with the world's stamp.
  void publish(const rigid_body::World& world);
  /// /clock at the world's stamp (lockstep, or publish/clock).
  void publishClock(const rigid_body::World& world);

  /// Messages withheld because a field was not finite (e.g. a kinetic energy that overflowed).
  std::uint64_t withheld() const { return withheld_; }
  /// New noise standard deviations for every body's odom_noisy (nothing if the node started without noise).
  void setNoise(const NoiseConfig& noise);

  /// Largest ||q| − 1| published for a body since the last reset.
  double maxNormError(std::size_t body) const { return channels_[body]->max_norm_error; }

  /// The body the config now has last, at `body`: its topics, tf and a place at the end of the arrays.
  void addBody(std::size_t body);
  /// The body at `body` is gone: its publishers shut down, the later bodies move down one index. Call before
  /// the config drops it.
  void removeBody(std::size_t body);

 private:
  struct Channel {
    ros::Publisher odom;
    ros::Publisher state;
    ros::Publisher applied_wrench;
    ros::Publisher contacts;               ///< only for a body with a collision shape
    std::unique_ptr<OdometryNoise> noise;  ///< only with noise
    int contacts_subscribers = 0;
    int odom_subscribers = 0;
    int state_subscribers = 0;
    int applied_wrench_subscribers = 0;
    double max_norm_error = 0.0;
    nav_msgs::Odometry odom_message;
    rigid_body_sim::RigidBodyState state_message;
    geometry_msgs::WrenchStamped applied_wrench_message;
    rigid_body_sim::Contacts contacts_message;
  };
  void publishContacts(const rigid_body::World& world, std::size_t body, const ros::Time& stamp);

  void advertise(Channel& channel, const BodyConfig& config, std::size_t body);
  /// bodies/odom: every body's odometry in one message (publish/per_body_topics: false).
  void publishArray(const rigid_body::World& world, const ros::Time& stamp);
  /// bodies/states: every body's pose and world-axes twist in one message (every scene, with publish/state).
  void publishStates(const rigid_body::World& world, const ros::Time& stamp);
  /// Which of a tick's outputs are due (their rates: PublishConfig).
  struct Due {
    bool tf = true;
    bool odom = true;
    bool state = true;
  };
  void publishBody(const rigid_body::World& world, std::size_t body, const ros::Time& stamp, const Due& due);

  const NodeConfig& config_;
  ros::NodeHandle nh_;
  uint32_t queue_;
  std::vector<std::unique_ptr<Channel>> channels_;  ///< on the heap: the subscriber-count callbacks hold pointers
  OwnTransforms& own_transforms_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> mesh_frame_broadcaster_;
  std::vector<geometry_msgs::TransformStamped> transforms_;  ///< one per body when tf is published
  ros::Publisher clock_publisher_;                             ///< lockstep or publish/clock only
  ros::Publisher array_publisher_;                             ///< bodies/odom, without per-body topics
  int array_subscribers_ = 0;
  rigid_body_sim::OdometryArray array_message_;
  ros::Publisher states_publisher_;  ///< bodies/states, with publish/state
  int states_subscribers_ = 0;
  rigid_body_sim::BodyStates states_message_;
  std::uint64_t withheld_ = 0;
  OutputSchedule tf_schedule_, odom_schedule_, state_schedule_;
  std::uint64_t resets_seen_ = 0;  ///< the World's reset count when max_norm_error was last cleared
};

}  // namespace rigid_body_ros
