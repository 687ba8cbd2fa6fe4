// rigid_body_sim/RigidBodyNodelet: the simulator as a nodelet, so that a controller nodelet in the same
// manager receives its odometry and sends its wrench as shared pointers, without serialisation (roscpp hands
// a message published as a shared pointer to an in-process subscriber as it is).
//
// The simulator keeps the standalone node's threading: its callbacks (wrenches, services, its timer) go to a
// queue of its own, served by one thread of its own, so none runs during a step and the manager's worker
// threads, shared with other nodelets, neither delay its ticks nor race with them. In lockstep that thread
// is the lockstep driver, which serves the queue between steps.
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <thread>

#include "rigid_body_sim/ros/simulator_startup.hpp"

namespace rigid_body_ros {

class RigidBodyNodelet : public nodelet::Nodelet {
 public:
  ~RigidBodyNodelet() override {
    running_ = false;
    if (driver_.joinable()) driver_.join();
    node_.reset();  // the simulator first; then the members, sim_time_ giving /use_sim_time back
  }

 private:
  // How long the timer's thread waits for a callback before it looks at running_ again [s].
  static constexpr double kServePeriod = 0.01;

  void onInit() override {
    ros::NodeHandle nh = getNodeHandle();
    ros::NodeHandle private_nh = getPrivateNodeHandle();
    nh.setCallbackQueue(&queue_);
    private_nh.setCallbackQueue(&queue_);
    node_ = startSimulator(nh, private_nh);
    // The manager reports a nodelet whose initialisation throws as failed to load (and unloads it); the
    // FATAL line above says why.
    if (!node_) throw std::runtime_error("rigid_body_sim/RigidBodyNodelet: start-up failed (see the line above)");
    if (node_->lockstep()) {
      sim_time_ = std::make_unique<SimTimeClaim>();
      node_->start(ros::Time(0));
      driver_ = std::thread([this] {
        node_->runLockstep([this] { return running_.load(); }, [this] { queue_.callAvailable(); });
      });
      return;
    }
    driver_ = std::thread([this] { serveTimer(); });
  }

  // Outside lockstep: waits for a valid ROS time (under /use_sim_time, the first /clock), starts the timer,
  // then serves the simulator's queue until unloaded.
  void serveTimer() {
    while (running_ && ros::ok() && !ros::Time::isValid()) ros::WallDuration(kServePeriod).sleep();
    if (!running_ || !ros::ok()) return;
    node_->start(ros::Time::now());
    while (running_ && ros::ok()) queue_.callAvailable(ros::WallDuration(kServePeriod));
  }

  ros::CallbackQueue queue_;
  std::unique_ptr<SimulatorNode> node_;
  std::unique_ptr<SimTimeClaim> sim_time_;
  std::atomic<bool> running_{true};
  std::thread driver_;
};

}  // namespace rigid_body_ros

PLUGINLIB_EXPORT_CLASS(rigid_body_ros::RigidBodyNodelet, nodelet::Nodelet)
