// rviz markers (visualization_msgs/MarkerArray on `markers`): each body's shape in its body frame, the
// environment's static shapes and, with contact, the contact points and normals. Published only while
// subscribed, at ~marker_rate (simulated time); marker ids are stable from tick to tick.
#pragma once

#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <vector>

#include "rigid_body_sim/ros/output_schedule.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class Markers {
 public:
  Markers(ros::NodeHandle& nh, const NodeConfig& config);

  /// Publishes the markers if someone subscribes and 1/marker_rate has passed since the last ones.
  void publish(const rigid_body::World& world);

  /// The config's body list changed (a spawn or a removal; it had `bodies_before` bodies): the markers are
  /// made again, and those of ids no body has now are deleted with the next publication.
  void bodiesChanged(std::size_t bodies_before);

  /// The markers of the scene as they stand (for tests and for publish).
  const visualization_msgs::MarkerArray& build(const rigid_body::World& world, const ros::Time& stamp);

 private:
  void rebuild();
  void addBodies();
  visualization_msgs::Marker bodyMarker(std::size_t body) const;
  void addEnvironment();

  const NodeConfig& config_;
  ros::Publisher publisher_;
  int subscribers_ = 0;
  OutputSchedule schedule_;  ///< at marker_rate
  visualization_msgs::MarkerArray array_;  ///< bodies, environment, then the two contact markers
  std::size_t contact_points_ = 0;         ///< index of the contact points' marker in array_ (if any)
  std::vector<int> removed_ids_;           ///< body marker ids to delete with the next publication
};

}  // namespace rigid_body_ros
