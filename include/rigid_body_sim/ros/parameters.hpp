// The node's private parameters, read in one pass into a plain config and validated before anything
// else exists. Every failure is one line that names the parameter, the value and what is allowed.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/contact.hpp"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/imu.hpp"
#include "rigid_body_sim/imu_noise.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/wrench_limits.hpp"

namespace ros {
class NodeHandle;
}

namespace rigid_body_ros {

/// The private sub-namespace of the live parameters (dynamic_reconfigure), ~live: apart from the start-up ones.
inline constexpr const char* kLiveNamespace = "live";

/// An invalid parameter; what() is the whole message, e.g.
/// "parameter ~mass = -1: must be a finite number > 0 [kg]".
class ParameterError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Optional Gaussian noise on a copy of the odometry (odom_noisy); all zero: no noisy copy at all.
struct NoiseConfig {
  Eigen::Vector3d position_stddev = Eigen::Vector3d::Zero();          ///< [m], world axes
  Eigen::Vector3d orientation_stddev = Eigen::Vector3d::Zero();       ///< [rad], small rotation about world axes
  Eigen::Vector3d linear_velocity_stddev = Eigen::Vector3d::Zero();   ///< [m/s], body axes
  Eigen::Vector3d angular_velocity_stddev = Eigen::Vector3d::Zero();  ///< [rad/s], body axes
  int seed = 1;                                                        ///< the generator's seed (reproducible)
  double delay = 0.0;                                                  ///< publication delay [s]
  bool enabled() const {
    return !(position_stddev.isZero(0.0) && orientation_stddev.isZero(0.0) && linear_velocity_stddev.isZero(0.0) &&
             angular_velocity_stddev.isZero(0.0));
  }
};

/// An IMU on a body (a body's `imu` key): where it sits, how often it reads and how it errs.
struct ImuConfig {
  std::string frame;  ///< the sensor's tf frame (header.frame_id of NAME/imu), below body_frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();              ///< in the published frame [m]
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< sensor axes in the published frame
  double rate = 0.0;                 ///< [Hz], at most the node's rate (0 until read: the node's rate)
  rigid_body::SensorNoise gyro;      ///< [rad/s/√Hz], [rad/s²/√Hz]
  rigid_body::SensorNoise accel;     ///< [m/s²/√Hz], [m/s³/√Hz]
  double orientation_stddev = 0.0;   ///< [rad] white noise on the orientation, about the sensor's axes
  int seed = 1;                      ///< the noise generators' seed (reproducible)
  rigid_body::ImuMount mount;        ///< the sensor in the body frame B at the centre of mass (from the above)
};

/// Where a body's mass properties come from.
enum class MassSource {
  kShape,    ///< a uniform solid of `shape` and `size` (a shape with a formula, or a mesh's triangles)
  kInertia,  ///< ~mass and ~inertia given directly: the body has no shape of its own
  kUrdf,     ///< a link of a robot description
};

/// One body of the scene: the keys of the flat one-body form, or of one item of ~bodies.
struct BodyConfig {
  std::string name;                               ///< topic prefix NAME/ ("" in the flat form: no prefix)
  std::string body_frame = "base_link";
  MassSource mass_source = MassSource::kShape;
  /// With MassSource::kShape: a shape with a solid's formula (rigid_body::ShapeInfo::solid) or a mesh.
  rigid_body::ShapeType shape = rigid_body::ShapeType::kBox;
  std::vector<double> size = {0.4, 0.2, 0.1};     ///< shape dimensions [m] (ShapeInfo::size_meaning)
  /// The shape's name, or "inertia" / "urdf" for a body without one of its own: for logs.
  std::string shapeLabel() const;
  /// Whether the body's mass properties come from `shape` being `type`.
  bool hasShape(rigid_body::ShapeType type) const { return mass_source == MassSource::kShape && shape == type; }
  rigid_body::Model model;                        ///< mass properties and force models (the scene's gravity)
  rigid_body::State initial;                      ///< the state at start-up and after reset
  Eigen::Vector3d initial_linear_velocity_W = Eigen::Vector3d::Zero();   ///< [m/s], world axes
  Eigen::Vector3d initial_angular_velocity_B = Eigen::Vector3d::Zero();  ///< [rad/s], body axes
  bool wrench_input = true;  ///< subscribes NAME/wrench (and takes apply_wrench); false: no input term at all
  // shape: mesh
  std::string mesh_path;             ///< the resolved file of mesh
  std::string mesh_uri;              ///< mesh as given (a package:// URI or a path), for rviz
  double mesh_scale = 1.0;           ///< scale: mesh units to metres
  std::string mesh_frame;            ///< if set, a static tf body_frame → mesh_frame is published
  Eigen::Isometry3d X_MB = Eigen::Isometry3d::Identity();  ///< pose of the body frame in the mesh frame
  std::vector<std::string> mesh_warnings;  ///< repairs made to the mesh, for the start-up log
  rigid_body::TriangleMesh mesh;           ///< the mesh as read and scaled, in its own frame M
  /// `collision`: the body's collision shape in the body frame, or none (it collides with nothing)
  std::optional<rigid_body::CollisionShape> collision;
  // shape: urdf (a link of a robot description)
  std::string link;                                          ///< the link's name
  /// The published frame P (body_frame: tf, odometry, state) in the body frame B at the centre of mass: the
  /// link frame of a URDF body, B itself otherwise (identity).
  Eigen::Isometry3d X_BP = Eigen::Isometry3d::Identity();
  bool published_offset = false;                             ///< X_BP is not the identity
  std::optional<rigid_body::CollisionShape> urdf_collision;  ///< the link's <collision>, posed in B
  std::string urdf_collision_problem;                        ///< why the link's <collision> cannot be used
  std::optional<rigid_body::CollisionShape> visual;          ///< the link's <visual> primitive, posed in P
  std::string visual_mesh;                                   ///< a mesh <visual>'s filename
  double visual_mesh_scale = 1.0;
  Eigen::Isometry3d X_PV = Eigen::Isometry3d::Identity();    ///< a mesh <visual>'s pose in P

  std::optional<ImuConfig> imu;  ///< `imu`: a sensor on the body, publishing NAME/imu
  /// NAME/ + `topic`, or `topic` alone in the flat form.
  std::string topic(const std::string& topic) const { return name.empty() ? topic : name + "/" + topic; }
};

/// Which outputs the scene publishes (~publish/...): a publisher exists only for an enabled output.
struct PublishConfig {
  bool tf = true;              ///< world_frame → body_frame of every body, one tf message per tick
  bool odom = true;            ///< NAME/odom
  bool state = true;           ///< NAME/state
  bool applied_wrench = true;  ///< NAME/applied_wrench
  /// NAME/get_state, NAME/get_properties, NAME/set_state, NAME/apply_wrench: four registrations per body
  /// with the master (~1 ms each), which a large scene that does not use them can leave out
  bool body_services = true;
  /// false: no per-body topics or services at all; the scene's odometry goes out as one OdometryArray on
  /// bodies/odom and wrenches come in as BodyWrenches on bodies/wrench (a few registrations with the master
  /// instead of ~6 per body: what lets a scene of 10 000 bodies start in seconds)
  bool per_body_topics = true;
  /// /clock at every publication also outside lockstep (the simulation's stamps, on ROS time), for tools that
  /// expect one; refused under /use_sim_time, where the node follows /clock itself
  bool clock = false;
  /// Rates of their own [Hz], at most `rate`, on a grid of simulated time (OutputSchedule); 0: every tick.
  double tf_rate = 0.0;
  double odom_rate = 0.0;    ///< NAME/odom, odom_noisy and bodies/odom
  double state_rate = 0.0;   ///< NAME/state and NAME/applied_wrench
};

/// Everything the node needs: the scene-wide settings and its bodies, with the defaults of the README's
/// parameter table.
struct NodeConfig {
  double rate = 100.0;  ///< timer and publish rate [Hz]
  double marker_rate = 20.0;  ///< rviz markers' rate [Hz], at most rate (published only while subscribed)
  double dt = 0.001;    ///< fixed physics step [s]
  rigid_body::IntegratorType integrator = rigid_body::IntegratorType::kRk4;
  rigid_body::IntegratorSettings integrator_settings;  ///< abs_tolerance, rel_tolerance (dopri5)
  std::string world_frame = "world";
  Eigen::Vector3d gravity_W = Eigen::Vector3d::Zero();  ///< [m/s^2], every body's
  std::vector<BodyConfig> bodies = {BodyConfig()};       ///< the flat form's one body, or ~bodies
  double wrench_timeout = 0.0;       ///< [s]; 0: a wrench holds until the next one
  rigid_body::WrenchLimits wrench_limits;  ///< max_force [N], max_torque [N m]; infinite when not set
  double max_energy_growth = 2.0;    ///< divergence guard: energy factor per tick with no wrench commanded
  std::int64_t max_substeps = 1000;  ///< steps one tick may integrate per body; the rest is dropped and counted
  std::int64_t max_body_steps_per_tick = 2000000;     ///< the same cap in body-steps (steps × bodies) per tick
  std::int64_t max_body_steps_per_request = 2000000;  ///< the most body-steps one step request may ask for
  double max_request_seconds = 1.0;  ///< [s] the wall time one step request may take; it stops there and says so
  double max_tick_seconds = 0.2;     ///< [s] the wall time one tick may integrate for; the rest is dropped, counted
  std::size_t threads = 0;  ///< the scene's stepping threads (0: as many as cores; used from 65 bodies on)
  PublishConfig publish;
  bool lockstep = false;          ///< the node owns simulated time and publishes /clock
  double real_time_factor = 1.0;  ///< lockstep pace: simulated seconds per wall second; 0 = as fast as possible
  bool start_paused = false;      ///< start paused (pause/unpause/step services)
  NoiseConfig noise;              ///< every body's odom_noisy (each body draws from its own generator)
  std::vector<rigid_body::CollisionShape> environment;  ///< ~environment: static shapes
  rigid_body::ContactSettings contact;                  ///< ~contact/: the solver's settings
  /// The core's contact description: the environment and each body's collision shape.
  rigid_body::ContactSetup contactSetup() const;
  std::vector<std::string> unknown_parameters;  ///< names set but not known (typos), for a warning

  /// One line with the effective scene-wide values, and one per body, for the start-up log.
  std::string describe() const;
};

/// Reads a parameter of the ROS parameter server as text (for ~robot_description, which names one); false
/// when it is not set or not text.
using ParameterReader = std::function<bool(const std::string& name, std::string& value)>;

/// The ParameterReader of the ROS parameter server (ros::param::get).
ParameterReader parameterServerReader();

/// Parses and validates the private namespace given as an XmlRpc struct (an invalid, i.e. unset, value
/// means "all defaults"). Throws ParameterError on the first invalid parameter. Names the node does not
/// know (e.g. "mas", "initial/postion") go to unknown_parameters. `reader` resolves ~robot_description.
NodeConfig parseConfig(const XmlRpc::XmlRpcValue& params, const ParameterReader& reader = ParameterReader());

/// One item of ~bodies on its own (a body spawned at run time) for the scene-wide values of `scene` (its
/// gravity and world frame): as parseConfig reads an item, errors named "parameter ~bodies[0]/KEY = ...".
/// Unknown keys go to `unknown` as "bodies[0]/KEY".
BodyConfig parseBodyItem(const XmlRpc::XmlRpcValue& item, const NodeConfig& scene, std::vector<std::string>& unknown,
                         const ParameterReader& reader);

/// Whether the node reads `key` (a/b for nested keys: publish/tf, initial/position, contact/iterations):
/// the scene's and a body's keys, the groups, and the keys within publish, noise, initial and contact.
bool isKnownParameter(const std::string& key);

/// A ~mesh value as a file path: "package://PKG/rel" becomes PKG's path (rospack) + "/rel"; anything else is
/// returned as it is. Throws ParameterError if the package is unknown.
std::string resolveMeshUri(const std::string& uri);

/// Reads the private namespace of `private_nh` and parses it.
NodeConfig loadConfig(const ros::NodeHandle& private_nh);

}  // namespace rigid_body_ros
