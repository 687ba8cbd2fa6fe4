#include "rigid_body_sim/ros/outputs.hpp"

#include <rosgraph_msgs/Clock.h>
#include <boost/make_shared.hpp>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <optional>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {

constexpr double kWarningPeriod = 2.0;  // [s] between repeats of the same warning

// A message goes out as a shared copy: roscpp hands it as it is to a subscriber in this process (a nodelet in
// the simulator's manager) and serialises it only for subscribers in other processes; one published by value
// is serialised, and deserialised again, for every subscriber.
template <class Message>
void publishShared(const ros::Publisher& publisher, const Message& message) {
  publisher.publish(boost::make_shared<Message>(message));
}

bool finite(const geometry_msgs::Vector3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const geometry_msgs::Point& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
bool finite(const geometry_msgs::Quaternion& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
bool finite(const nav_msgs::Odometry& m) {
  return finite(m.pose.pose.position) && finite(m.pose.pose.orientation) && finite(m.twist.twist.linear) &&
         finite(m.twist.twist.angular);
}
bool finite(const rigid_body_sim::RigidBodyState& m) {
  return finite(m.pose.position) && finite(m.pose.orientation) && finite(m.twist.linear) && finite(m.twist.angular) &&
         finite(m.linear_momentum) && finite(m.angular_momentum) && finite(m.applied_wrench.force) &&
         finite(m.applied_wrench.torque) && std::isfinite(m.kinetic_energy) && std::isfinite(m.potential_energy) &&
         std::isfinite(m.quaternion_norm_error);
}

}  // namespace

Outputs::Outputs(ros::NodeHandle& nh, const NodeConfig& config, OwnTransforms& own_transforms)
    : config_(config),
      nh_(nh),
      // In lockstep at full speed the outputs come in bursts: a deeper queue lets subscribers keep up longer
      // (a subscriber slower than the simulation still misses messages; set real_time_factor then).
      queue_(config.lockstep ? 100 : 10),
      own_transforms_(own_transforms) {
  if (config.publish.tf) own_transforms_.advertise(nh);
  if (config.publish.state) states_message_.header.frame_id = config.world_frame;
  for (std::size_t body = 0; body < config.bodies.size(); ++body) addBody(body);
  if (!config.publish.per_body_topics && config.publish.odom) {
    // One topic for the whole scene, filled only while someone listens.
    array_message_.header.frame_id = config.world_frame;
    array_publisher_ = nh.advertise<rigid_body_sim::OdometryArray>(
        "bodies/odom", queue_, [this](const ros::SingleSubscriberPublisher&) { ++array_subscribers_; },
        [this](const ros::SingleSubscriberPublisher&) { --array_subscribers_; });
  }
  if (config.publish.state) {
    // One topic for the whole scene in every scene (as Gazebo's model_states), filled only while listened to.
    states_publisher_ = nh.advertise<rigid_body_sim::BodyStates>(
        "bodies/states", queue_, [this](const ros::SingleSubscriberPublisher&) { ++states_subscribers_; },
        [this](const ros::SingleSubscriberPublisher&) { --states_subscribers_; });
  }
  if (config.lockstep || config.publish.clock) clock_publisher_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
}

void Outputs::addBody(std::size_t body) {
  channels_.push_back(std::make_unique<Channel>());
  Channel& channel = *channels_[body];
  const BodyConfig& config = config_.bodies[body];
  // Ground truth: the covariances stay zero.
  channel.odom_message.header.frame_id = config_.world_frame;
  channel.odom_message.child_frame_id = config.body_frame;
  if (config_.publish.per_body_topics) advertise(channel, config, body);
  if (config_.publish.tf) {
    geometry_msgs::TransformStamped transform;
    transform.header.frame_id = config_.world_frame;
    transform.child_frame_id = config.body_frame;
    transforms_.push_back(transform);
  }
  if (config_.publish.state) {
    states_message_.name.push_back(config.body_frame);
    states_message_.pose.emplace_back();
    states_message_.twist.emplace_back();
  }
}

void Outputs::removeBody(std::size_t body) {
  const auto at = static_cast<std::ptrdiff_t>(body);
  channels_.erase(channels_.begin() + at);  // its publishers shut down with it
  if (config_.publish.tf) transforms_.erase(transforms_.begin() + at);
  if (config_.publish.state) {
    states_message_.name.erase(states_message_.name.begin() + at);
    states_message_.pose.erase(states_message_.pose.begin() + at);
    states_message_.twist.erase(states_message_.twist.begin() + at);
  }
}

void Outputs::advertise(Channel& channel, const BodyConfig& config, std::size_t body) {
  channel.state_message.header.frame_id = config_.world_frame;
  channel.state_message.child_frame_id = config.body_frame;
  channel.applied_wrench_message.header.frame_id = config_.world_frame;
  // Counts a publisher's subscribers in `count` (each channel has its own place on the heap: an edit of the
  // body list moves the pointers, not the channels).
  const auto advertise = [&](auto message, const std::string& topic, int Channel::*count) {
    Channel* const counted = &channel;
    const ros::SubscriberStatusCallback connected = [counted, count](const ros::SingleSubscriberPublisher&) {
      ++(counted->*count);
    };
    const ros::SubscriberStatusCallback disconnected = [counted, count](const ros::SingleSubscriberPublisher&) {
      --(counted->*count);
    };
    return nh_.advertise<decltype(message)>(config.topic(topic), queue_, connected, disconnected);
  };
  if (config_.publish.odom) channel.odom = advertise(nav_msgs::Odometry(), "odom", &Channel::odom_subscribers);
  if (config_.publish.state) {
    channel.state = advertise(rigid_body_sim::RigidBodyState(), "state", &Channel::state_subscribers);
  }
  if (config_.publish.applied_wrench) {
    channel.applied_wrench =
        advertise(geometry_msgs::WrenchStamped(), "applied_wrench", &Channel::applied_wrench_subscribers);
  }
  if (config.collision) {
    channel.contacts_message.header.frame_id = config_.world_frame;
    channel.contacts_message.body_frame = config.body_frame;
    channel.contacts = advertise(rigid_body_sim::Contacts(), "contacts", &Channel::contacts_subscribers);
  }
  if (config_.noise.enabled()) {
    channel.noise = std::make_unique<OdometryNoise>(nh_, config.topic("odom_noisy"), queue_, config_.noise,
                                                    config_.rate, body);  // one stream per body
  }
}

void Outputs::setNoise(const NoiseConfig& noise) {
  for (const auto& channel : channels_) {
    if (channel->noise) channel->noise->setStddevs(noise);
  }
}

void Outputs::publishStaticFrames(const ros::Time& stamp, std::vector<geometry_msgs::TransformStamped> others) {
  std::vector<geometry_msgs::TransformStamped> mesh_frames = std::move(others);
  for (const BodyConfig& config : config_.bodies) {
    if (config.mesh_frame.empty()) continue;
    // The mesh's own frame relative to the body frame, X_BM = X_MB⁻¹, so visuals can hang on it.
    geometry_msgs::TransformStamped X_BM = tf2::eigenToTransform(Eigen::Affine3d(config.X_MB.inverse().matrix()));
    X_BM.header.stamp = stamp;
    X_BM.header.frame_id = config.body_frame;
    X_BM.child_frame_id = config.mesh_frame;
    mesh_frames.push_back(X_BM);
  }
  // None: nothing to latch, unless a removal took the last one away (a late listener then gets none).
  if (mesh_frames.empty() && !mesh_frame_broadcaster_) return;
  mesh_frame_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  mesh_frame_broadcaster_->sendTransform(mesh_frames);
}

void Outputs::publishClock(const rigid_body::World& world) {
  rosgraph_msgs::Clock clock;
  clock.clock = toRosTime(world.stamp());
  publishShared(clock_publisher_, clock);
}

void Outputs::publish(const rigid_body::World& world) {
  const ros::Time stamp = toRosTime(world.stamp());
  if (world.counters().resets != resets_seen_) {
    resets_seen_ = world.counters().resets;
    for (const auto& channel : channels_) channel->max_norm_error = 0.0;
  }
  const rigid_body::Nanoseconds now = world.stamp();
  const auto dueAt = [now](OutputSchedule& schedule, double rate) {
    return rate <= 0.0 || schedule.due(now, rigid_body::toNanoseconds(1.0 / rate));
  };
  Due due;
  due.tf = config_.publish.tf && dueAt(tf_schedule_, config_.publish.tf_rate);
  due.odom = dueAt(odom_schedule_, config_.publish.odom_rate);
  due.state = dueAt(state_schedule_, config_.publish.state_rate);
  for (std::size_t body = 0; body < channels_.size(); ++body) publishBody(world, body, stamp, due);
  if (due.tf) own_transforms_.publish(transforms_);  // every body in one tf message
  if (due.odom && array_subscribers_ > 0) publishArray(world, stamp);
  if (due.state && states_subscribers_ > 0) publishStates(world, stamp);
}

void Outputs::publishStates(const rigid_body::World& world, const ros::Time& stamp) {
  const rigid_body::Scene& scene = world.scene();
  states_message_.header.stamp = stamp;
  for (std::size_t body = 0; body < channels_.size(); ++body) {
    // The published frame (a URDF link frame, else the body frame itself), exactly as tf and odom have it.
    const rigid_body::MassProperties& mass = scene.model(body).mass;
    const FrameMotion frame = config_.bodies[body].published_offset
                                  ? publishedFrame(mass, scene.state(body), config_.bodies[body].X_BP)
                                  : bodyFrame(mass, scene.state(body));
    if (!frame.v_WP_W.allFinite() || !frame.w_W.allFinite()) {  // a finite state can still overflow P/M
      ++withheld_;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: bodies/states withheld: a non-finite velocity of %s",
                        config_.bodies[body].body_frame.c_str());
      return;
    }
    fillBodyState(frame, states_message_.pose[body], states_message_.twist[body]);
  }
  publishShared(states_publisher_, states_message_);
}

void Outputs::publishArray(const rigid_body::World& world, const ros::Time& stamp) {
  const rigid_body::Scene& scene = world.scene();
  array_message_.header.stamp = stamp;
  array_message_.bodies.resize(channels_.size());
  for (std::size_t body = 0; body < channels_.size(); ++body) {
    nav_msgs::Odometry& odom = channels_[body]->odom_message;
    odom.header.stamp = stamp;
    if (config_.bodies[body].published_offset) {
      fillOdometry(publishedFrame(scene.model(body).mass, scene.state(body), config_.bodies[body].X_BP), odom);
    } else {
      fillOdometry(scene.model(body).mass, scene.state(body), odom);
    }
    if (!finite(odom)) {
      ++withheld_;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: bodies/odom withheld: a non-finite velocity of %s",
                        config_.bodies[body].body_frame.c_str());
      return;
    }
    array_message_.bodies[body] = odom;
  }
  publishShared(array_publisher_, array_message_);
}

void Outputs::publishContacts(const rigid_body::World& world, std::size_t body, const ros::Time& stamp) {
  Channel& channel = *channels_[body];
  rigid_body_sim::Contacts& message = channel.contacts_message;
  message.header.stamp = stamp;
  const std::vector<rigid_body::Contact>& contacts = world.scene().contacts(body);
  message.contacts.resize(contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const rigid_body::Contact& contact = contacts[i];
    rigid_body_sim::Contact& out = message.contacts[i];
    out.other = contact.other.is_body ? config_.bodies[contact.other.index].body_frame
                                      : config_.environment[contact.other.index].name;
    out.position = tf2::toMsg(contact.position_W);
    tf2::toMsg(contact.normal_W, out.normal);
    out.penetration = contact.penetration;
    out.normal_impulse = contact.normal_impulse;
    tf2::toMsg(contact.friction_impulse_W, out.friction_impulse);
  }
  channel.contacts.publish(message);
}

void Outputs::publishBody(const rigid_body::World& world, std::size_t body, const ros::Time& stamp, const Due& due) {
  Channel& channel = *channels_[body];
  if (channel.contacts_subscribers > 0) publishContacts(world, body, stamp);
  const rigid_body::Scene& scene = world.scene();
  const rigid_body::State& state = scene.state(body);  // finite: the scene keeps the last good state
  channel.max_norm_error = std::max(channel.max_norm_error, std::abs(rigid_body::quaternionNormError(state)));
  // A URDF body publishes its link frame: its pose and twist made once for tf, odometry and state.
  std::optional<FrameMotion> frame;
  if (config_.bodies[body].published_offset) {
    frame = publishedFrame(scene.model(body).mass, state, config_.bodies[body].X_BP);
  }
  if (due.tf) {
    transforms_[body].header.stamp = stamp;
    if (frame) {
      fillTransform(*frame, transforms_[body]);
    } else {
      fillTransform(state, transforms_[body]);
    }
  }
  const bool odom = due.odom && channel.odom_subscribers > 0;
  if (odom || (due.odom && channel.noise)) {
    channel.odom_message.header.stamp = stamp;
    if (frame) {
      fillOdometry(*frame, channel.odom_message);
    } else {
      fillOdometry(scene.model(body).mass, state, channel.odom_message);
    }
    if (!finite(channel.odom_message)) {
      ++withheld_;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %s: odometry withheld: a non-finite velocity",
                        config_.bodies[body].body_frame.c_str());
    } else {
      if (odom) publishShared(channel.odom, channel.odom_message);
      if (channel.noise) channel.noise->publish(channel.odom_message, stamp);
    }
  }
  const bool state_wanted = due.state && channel.state_subscribers > 0;
  const bool applied_wrench = due.state && channel.applied_wrench_subscribers > 0;
  if (state_wanted || applied_wrench) {
    channel.state_message.header.stamp = stamp;
    if (frame) {
      fillStateMessage(scene.model(body), state, *frame, scene.input(body), channel.state_message);
    } else {
      fillStateMessage(scene.model(body), state, scene.input(body), channel.state_message);
    }
    channel.state_message.contacts = static_cast<std::uint32_t>(scene.contactCount(body));
    if (!finite(channel.state_message)) {
      ++withheld_;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %s: state withheld: a non-finite field (energy overflow?)",
                        config_.bodies[body].body_frame.c_str());
      return;
    }
    if (state_wanted) publishShared(channel.state, channel.state_message);
  }
  if (applied_wrench) {
    channel.applied_wrench_message.header.stamp = stamp;
    channel.applied_wrench_message.wrench = channel.state_message.applied_wrench;  // world axes, about the CoM
    publishShared(channel.applied_wrench, channel.applied_wrench_message);
  }
}

}  // namespace rigid_body_ros
