#include "rigid_body_sim/ros/parameters.hpp"

#include "parameter_values.hpp"

#include <ros/node_handle.h>
#include <ros/package.h>
#include <ros/param.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/mesh_mass_properties.hpp"
#include "rigid_body_sim/number_format.hpp"
#include "rigid_body_sim/ros/contact_parameters.hpp"
#include "rigid_body_sim/ros/imu_parameters.hpp"
#include "rigid_body_sim/ros/parameter_schema.hpp"
#include "rigid_body_sim/ros/urdf_body.hpp"
#include "rigid_body_sim/shape_registry.hpp"

namespace rigid_body_ros {

namespace {

using namespace parameter_values;

// Sampling draws this many points at most (each costs a ray test against every triangle).
constexpr std::uint64_t kMaxSamples = 10000000;
// The largest mesh file the limit may be raised to [bytes].
constexpr double kMaxMeshBytesLimit = 4e9;
// The smallest physics step [s]: a million steps per simulated second.
constexpr double kMinDt = 1e-6;
// The slowest output with a rate of its own [Hz] (markers, tf, odometry, state), as the schema's ~rate.
constexpr double kMinOutputRate = 1e-3;

// The keys of one body (flat at the top level, or in each item of ~bodies): the body schema's.
const std::set<std::string> kBodyNames = bodySchemaKeys("");
// The scene-wide scalar keys come from the schema (parameter_schema.cpp); these group others.
const std::set<std::string> kSceneGroups = {"bodies", "publish", "noise", "environment", "contact",
                                            // The live parameters' namespace (dynamic_reconfigure writes its
                                            // values there); not read at start-up.
                                            kLiveNamespace};
const std::set<std::string> kInitialNames = bodySchemaKeys("initial/");

// ~max_mesh_bytes: the largest mesh (or URDF) file a body reads.
std::size_t readMaxMeshBytes(const XmlRpcValue& params) {
  return static_cast<std::size_t>(
      readNumber(params, "max_mesh_bytes", static_cast<double>(rigid_body::kDefaultMaxMeshBytes),
                 [](double b) { return b >= 1.0 && b <= kMaxMeshBytesLimit; },
                 "must be a number of bytes in [1, 4e9] (the largest mesh file read)"));
}

// shape: mesh. The body frame is the mesh's centre of mass, with the mesh's axes or its principal axes.
rigid_body::MassProperties readMeshMassProperties(const XmlRpcValue& params, BodyConfig& config) {
  const std::string uri = readString(params, "mesh", "", "must be a mesh file path or package:// URI (.stl, .obj)");
  if (uri.empty()) {
    failAt(params, "mesh", XmlRpcValue(uri), "must be set for shape mesh: a file path or package:// URI (.stl, .obj)");
  }
  config.mesh_path = resolveMeshUri(uri);
  config.mesh_uri = uri;
  rigid_body::MeshMassOptions options;
  const double scale = readNumber(params, "scale", 1.0, [](double s) { return s > 0.0; },
                                  "must be a finite number > 0 (mesh units to metres)");
  config.mesh_scale = scale;
  const bool has_mass = find(params, "mass") != nullptr, has_density = find(params, "density") != nullptr;
  if (has_mass && has_density) failAt(params, "density", XmlRpcValue(), "give ~mass or ~density, not both");
  if (!has_mass && !has_density) {
    fail("mass", XmlRpcValue(std::string()), "for shape mesh, give ~mass [kg] or ~density [kg/m^3]");
  }
  options.mass = readNumber(params, "mass", 0.0, [](double m) { return m > 0.0; }, "must be a finite number > 0 [kg]");
  options.density = readNumber(params, "density", 0.0, [](double d) { return d > 0.0; },
                               "must be a finite number > 0 [kg/m^3]");
  const std::string method_allowed = "must be one of: exact, sampling, bounding_box, oriented_bounding_box";
  const std::string method = readString(params, "inertia_method", "exact", method_allowed);
  try {
    options.method = rigid_body::inertiaMethodFromName(method);
  } catch (const std::invalid_argument&) {
    failAt(params, "inertia_method", XmlRpcValue(method), method_allowed);
  }
  options.samples = static_cast<std::uint64_t>(
      readInteger(params, "samples", static_cast<int>(options.samples), 1,
                  "must be an integer in [1, 10000000] (points drawn for inertia_method sampling)"));
  if (options.samples > kMaxSamples) {
    failAt(params, "samples", XmlRpcValue(), "must be an integer in [1, 10000000] (points drawn for inertia_method sampling)");
  }
  const std::size_t max_bytes = readMaxMeshBytes(params);
  const bool principal_axes = readBool(params, "principal_axes", false);
  try {
    config.mesh = rigid_body::transformed(rigid_body::loadMesh(config.mesh_path, max_bytes), scale);
    const std::size_t triangles = config.mesh.triangles.size();
    if (options.method == rigid_body::InertiaMethod::kSampling &&
        rigid_body::samplingTests(triangles, options) > rigid_body::kMaxSamplingTests) {
      failAt(params, "samples", XmlRpcValue(static_cast<int>(options.samples)),
             "with this mesh's " + std::to_string(triangles) + " triangles, must be at most " +
                 std::to_string(rigid_body::kMaxSamplingTests / std::max<std::size_t>(1, triangles)) +
                 " (samples x triangles ray-triangle tests at most " + std::to_string(rigid_body::kMaxSamplingTests) +
                 ", ~10 s of start-up), or use inertia_method exact");
    }
    const rigid_body::MeshMassProperties properties = rigid_body::meshMassProperties(config.mesh, options);
    config.mesh_warnings = properties.warnings;
    const rigid_body::MeshBody body = rigid_body::meshBody(properties, principal_axes);
    config.X_MB = body.X_MB;
    config.size.clear();
    return body.mass;
  } catch (const rigid_body::MeshError& error) {
    failAt(params, "mesh", XmlRpcValue(uri), error.what());
  } catch (const rigid_body::InvalidMassProperties& error) {
    failAt(params, "mesh", XmlRpcValue(uri), std::string("gives no physical inertia: ") + error.what());
  }
}

// A shape a body may take as its own: one with a solid's formula, or a mesh (its triangles give the rest).
bool bodyShape(const rigid_body::ShapeInfo& info) {
  return info.solid != nullptr || info.type == rigid_body::ShapeType::kMesh;
}

rigid_body::MassProperties readMassProperties(const XmlRpcValue& params, BodyConfig& config,
                                              const ParameterReader& reader) {
  if (find(params, "urdf") || find(params, "robot_description")) {
    return readUrdfBody(params, config, reader, readMaxMeshBytes(params));
  }
  const std::string shape_allowed =
      "must be one of: " + rigid_body::shapeNames([](const rigid_body::ShapeInfo& s) { return bodyShape(s); }) +
      " (or give ~inertia)";
  const auto body_shape = [&] {
    const std::string name = readString(params, "shape", "box", shape_allowed);
    const std::optional<rigid_body::ShapeType> type = rigid_body::shapeFromName(name);
    if (!type || !bodyShape(rigid_body::shapeInfo(*type))) failAt(params, "shape", XmlRpcValue(name), shape_allowed);
    return *type;
  };
  if (!find(params, "inertia") && body_shape() == rigid_body::ShapeType::kMesh) {
    config.shape = rigid_body::ShapeType::kMesh;
    return readMeshMassProperties(params, config);
  }
  const double mass = readNumber(params, "mass", 1.0, [](double m) { return m > 0.0; }, "must be a finite number > 0 [kg]");
  if (find(params, "inertia")) {
    const std::vector<double> i = readNumbers(params, "inertia", {}, 6,
                                              "must be a list of 6 finite numbers [ixx, iyy, izz, ixy, ixz, iyz] [kg m^2]");
    Eigen::Matrix3d I;
    I << i[0], i[3], i[4],  //
        i[3], i[1], i[5],   //
        i[4], i[5], i[2];
    config.mass_source = MassSource::kInertia;
    config.size.clear();
    try {
      return rigid_body::MassProperties::fromInertia(mass, I);
    } catch (const rigid_body::InvalidMassProperties& error) {
      failAt(params, "inertia", XmlRpcValue(),
             std::string(error.what()) + " (a symmetric positive-definite tensor about the centre of mass)");
    }
  }
  config.shape = body_shape();
  const rigid_body::ShapeInfo& info = rigid_body::shapeInfo(config.shape);
  const std::string size_allowed = rigid_body::sizeRule(config.shape);
  const std::vector<double> fallback(info.default_size.data(), info.default_size.data() + info.size_count);
  config.size = readNumbers(params, "size", fallback, static_cast<std::size_t>(info.size_count), size_allowed);
  for (double s : config.size) {
    if (!(s > 0.0)) failAt(params, "size", XmlRpcValue(), size_allowed);
  }
  // The keys of shape mesh mean nothing here: a typo or a forgotten shape, not something to ignore.
  for (const char* key : {"mesh", "scale", "density", "inertia_method", "samples", "principal_axes", "max_mesh_bytes"}) {
    if (find(params, key)) failAt(params, key, XmlRpcValue(), "is only for shape mesh");
  }
  // Mass and size together may give an inertia that overflows, underflows or cannot be inverted.
  try {
    Eigen::Vector3d size = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < config.size.size(); ++k) size[static_cast<int>(k)] = config.size[k];
    return info.solid(mass, size);
  } catch (const rigid_body::InvalidMassProperties& error) {
    const XmlRpcValue* size = find(params, "size");
    const XmlRpcValue* given_mass = find(params, "mass");
    fail(size ? "size" : "mass", size ? *size : given_mass ? *given_mass : XmlRpcValue(mass),
         "with ~mass = " + rigid_body::formatNumber(mass) + " gives no usable inertia: " + error.what());
  }
}

// One body's keys in `params` (the top level in the flat form, an item of ~bodies otherwise); the scene's
// gravity is already in config.gravity_W.
BodyConfig parseBody(const XmlRpcValue& params, const NodeConfig& scene, const std::string& default_frame,
                     std::vector<std::string>& unknown, const ParameterReader& reader) {
  requireStruct(params, "initial", "position, orientation, linear_velocity, angular_velocity");
  BodyConfig body;
  // A link of a robot description publishes its own frame, under the link's name unless body_frame says.
  const bool urdf = find(params, "urdf") || find(params, "robot_description");
  const std::string link = urdf ? readString(params, "link", "", "must be the name of a link of the robot description") : "";
  body.body_frame = readFrame(params, "body_frame", urdf && !link.empty() ? link : default_frame);
  if (scene.world_frame == body.body_frame) {
    failAt(params, "body_frame", XmlRpcValue(body.body_frame), "must differ from ~world_frame");
  }
  body.model.mass = readMassProperties(params, body, reader);
  body.model.forces.gravity_W = scene.gravity_W;
  body.model.forces.linear_damping = readNumber(params, "linear_damping", 0.0, [](double c) { return c >= 0.0; },
                                                "must be a finite number >= 0 [N s/m]");
  body.model.forces.angular_damping = readNumber(params, "angular_damping", 0.0, [](double c) { return c >= 0.0; },
                                                 "must be a finite number >= 0 [N m s/rad]");
  body.wrench_input = readBool(params, "wrench_input", true);

  const Eigen::Vector3d position = readVector3(params, "initial/position", "[m]");
  const Eigen::Quaterniond orientation = readQuaternion(params, "initial/orientation");
  body.initial_linear_velocity_W = readVector3(params, "initial/linear_velocity", "[m/s], world axes");
  body.initial_angular_velocity_B = readVector3(params, "initial/angular_velocity", "[rad/s], body axes");
  if (body.published_offset) {
    // initial/* place and move the published (link) frame P: X_WB = X_WP X_PB, ω in P's axes, and the centre
    // of mass moves at v_B = v_P + ω × (p_WB − p_WP).
    Eigen::Isometry3d X_WP = Eigen::Isometry3d::Identity();
    X_WP.linear() = orientation.normalized().toRotationMatrix();
    X_WP.translation() = position;
    const Eigen::Isometry3d X_WB = X_WP * body.X_BP.inverse();
    const Eigen::Vector3d w_W = X_WP.linear() * body.initial_angular_velocity_B;
    const Eigen::Vector3d v_B = body.initial_linear_velocity_W + w_W.cross(X_WB.translation() - position);
    body.initial = rigid_body::stateFromVelocities(body.model.mass, X_WB.translation(), Eigen::Quaterniond(X_WB.linear()),
                                                   v_B, X_WB.linear().transpose() * w_W);
  } else {
    body.initial = rigid_body::stateFromVelocities(body.model.mass, position, orientation,
                                                   body.initial_linear_velocity_W, body.initial_angular_velocity_B);
  }
  body.mesh_frame = readString(params, "mesh_frame", "", "must be a tf2 frame id");
  if (!body.mesh_frame.empty()) {
    if (!body.hasShape(rigid_body::ShapeType::kMesh)) failAt(params, "mesh_frame", XmlRpcValue(body.mesh_frame), "is only for shape mesh");
    body.mesh_frame = readFrame(params, "mesh_frame", "");
    // Its own tf frame, fixed in the body: one name for two frames would make tf's tree a loop.
    if (body.mesh_frame == body.body_frame || body.mesh_frame == scene.world_frame) {
      failAt(params, "mesh_frame", XmlRpcValue(body.mesh_frame), "must differ from body_frame and from world_frame");
    }
  }
  if (const XmlRpcValue* initial = find(params, "initial")) collectUnknown(*initial, "initial/", kInitialNames, unknown);
  body.collision = readCollision(params, body);
  if (body.collision) body.collision->name = body.body_frame;
  body.imu = readImu(params, body, scene, unknown);
  return body;
}

// "parameter ~mass = ...: ..." of a body item becomes "parameter ~bodies[2]/mass = ...: ...".
ParameterError inBodyItem(const ParameterError& error, int index) {
  const std::string prefix = "parameter ~";
  std::string message = error.what();
  if (message.compare(0, prefix.size(), prefix) == 0) {
    message.insert(prefix.size(), "bodies[" + std::to_string(index) + "]/");
  }
  return ParameterError(message);
}

// A body name is a relative ROS name of one segment: a letter, then letters, digits and underscores.
bool isBodyName(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name.front()))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::vector<BodyConfig> parseBodies(const XmlRpcValue& params, const NodeConfig& scene,
                                    std::vector<std::string>& unknown, const ParameterReader& reader) {
  const XmlRpcValue* list = find(params, "bodies");
  if (!list) {
    std::vector<BodyConfig> bodies = {parseBody(params, scene, "base_link", unknown, reader)};
    if (find(params, "name")) failAt(params, "name", XmlRpcValue(), "is a key of the items of ~bodies only");
    return bodies;
  }
  const std::string allowed = "must be a non-empty list of bodies, each a struct with at least 'name'";
  if (list->getType() != XmlRpcValue::TypeArray || list->size() == 0) fail("bodies", *list, allowed);
  // The flat body keys and ~bodies are two ways of saying the same thing: one of them, not both.
  XmlRpcValue top = params;
  for (const auto& member : top) {
    if (kBodyNames.count(member.first)) {
      fail(member.first, member.second, "is a body key: with ~bodies, give it in each item of the list");
    }
  }
  std::vector<BodyConfig> bodies;
  std::set<std::string> names, frames;
  for (int i = 0; i < list->size(); ++i) {
    const XmlRpcValue& item = (*list)[i];
    if (item.getType() != XmlRpcValue::TypeStruct) {
      throw ParameterError("parameter ~bodies[" + std::to_string(i) + "] = " + render(item) +
                           ": must be a struct with the keys of one body");
    }
    try {
      const std::string name = readString(item, "name", "", "must be the body's name (letters, digits, '_')");
      if (!isBodyName(name) || !names.insert(name).second) {
        failAt(item, "name", XmlRpcValue(name),
               "must be a unique name of letters, digits and '_' that starts with a letter");
      }
      BodyConfig body = parseBody(item, scene, name, unknown, reader);
      body.name = name;
      if (body.collision) body.collision->name = name;
      if (!frames.insert(body.body_frame).second) {
        fail("body_frame", XmlRpcValue(body.body_frame), "must differ from every other body's body_frame");
      }
      std::vector<std::string> item_unknown;
      collectUnknown(item, "", kBodyNames, item_unknown);
      for (const std::string& key : item_unknown) unknown.push_back("bodies[" + std::to_string(i) + "]/" + key);
      bodies.push_back(body);
    } catch (const ParameterError& error) {
      throw inBodyItem(error, i);
    }
  }
  return bodies;
}

// dt and the integrator (rate and the tolerances are the schema's).
void readTiming(const XmlRpcValue& params, NodeConfig& config) {
  const double max_dt = 1.0 / config.rate;
  std::ostringstream dt_allowed;
  dt_allowed << "must be a finite number in (0, 1/rate = " << max_dt << "] [s]";
  config.dt = readNumber(params, "dt", config.dt, [max_dt](double dt) { return dt > 0.0 && dt <= max_dt * (1 + 1e-12); },
                         dt_allowed.str());
  // The clock counts nanoseconds and a tick must stay a bounded amount of work: no step below a microsecond.
  if (config.dt < kMinDt) failAt(params, "dt", XmlRpcValue(), "must be >= 1e-6 [s] (at most a million steps per second)");
  const std::string integrator_allowed = "must be one of: " + rigid_body::integratorNameList();
  const std::string integrator = readString(params, "integrator", "rk4", integrator_allowed);
  try {
    config.integrator = rigid_body::integratorFromName(integrator);
  } catch (const std::invalid_argument&) {
    failAt(params, "integrator", XmlRpcValue(), integrator_allowed);
  }
}

// The outputs whose rule involves another key (the others are the schema's).
void readOutputs(const XmlRpcValue& params, NodeConfig& config) {
  // publish_tf is the older spelling of publish/tf; publish/tf wins when both are set.
  config.publish.tf = readBool(params, "publish/tf", readBool(params, "publish_tf", true));
  std::ostringstream rate_allowed;
  rate_allowed << "must be 0 (every tick) or a finite number in [0.001, rate = " << config.rate << "] [Hz]";
  const auto outputRate = [&](const char* key) {
    const auto allowed = [&](double r) { return r == 0.0 || (r >= kMinOutputRate && r <= config.rate); };
    return readNumber(params, key, 0.0, allowed, rate_allowed.str());
  };
  config.publish.tf_rate = outputRate("publish/tf_rate");
  config.publish.odom_rate = outputRate("publish/odom_rate");
  config.publish.state_rate = outputRate("publish/state_rate");
  const double default_marker_rate = std::min(20.0, config.rate);
  std::ostringstream marker_allowed;
  marker_allowed << "must be a finite number in [0.001, rate = " << config.rate << "] [Hz]";
  config.marker_rate = readNumber(params, "marker_rate", default_marker_rate,
                                  [&](double r) { return r >= kMinOutputRate && r <= config.rate; },
                                  marker_allowed.str());
}

// The noise's standard deviations (its seed and delay are the schema's).
void readNoise(const XmlRpcValue& params, NoiseConfig& noise) {
  const auto readStddev = [&](const std::string& name, const std::string& unit) {
    const Eigen::Vector3d v = readVector3(params, "noise/" + name, unit);
    if ((v.array() < 0.0).any()) failAt(params, "noise/" + name, XmlRpcValue(), "must be 3 numbers >= 0 " + unit);
    return v;
  };
  noise.position_stddev = readStddev("position_stddev", "[m]");
  noise.orientation_stddev = readStddev("orientation_stddev", "[rad]");
  noise.linear_velocity_stddev = readStddev("linear_velocity_stddev", "[m/s]");
  noise.angular_velocity_stddev = readStddev("angular_velocity_stddev", "[rad/s]");
}

// Names set but not known, top level first, then the bodies'.
std::vector<std::string> unknownNames(const XmlRpcValue& params, const std::vector<std::string>& unknown_in_bodies) {
  std::vector<std::string> unknown;
  std::set<std::string> top_level = schemaKeys("");
  top_level.insert(kSceneGroups.begin(), kSceneGroups.end());
  if (!find(params, "bodies")) top_level.insert(kBodyNames.begin(), kBodyNames.end());
  collectUnknown(params, "", top_level, unknown);
  if (const XmlRpcValue* noise = find(params, "noise")) collectUnknown(*noise, "noise/", schemaKeys("noise/"), unknown);
  if (const XmlRpcValue* publish = find(params, "publish")) {
    collectUnknown(*publish, "publish/", schemaKeys("publish/"), unknown);
  }
  if (const XmlRpcValue* contact = find(params, "contact")) {
    collectUnknown(*contact, "contact/", schemaKeys("contact/"), unknown);
  }
  unknown.insert(unknown.end(), unknown_in_bodies.begin(), unknown_in_bodies.end());
  return unknown;
}

// Contacts, markers and diagnostics name the other side of a contact by its name: a body and an
// environment shape of one name would be told apart by nothing.
void refuseBodyNamedLikeTheEnvironment(const NodeConfig& config) {
  for (std::size_t i = 0; i < config.environment.size(); ++i) {
    const std::string& shape = config.environment[i].name;
    for (const BodyConfig& body : config.bodies) {
      if (shape != body.name && shape != body.body_frame) continue;
      fail("environment[" + std::to_string(i) + "]/name", XmlRpcValue(shape),
           "is also the name (or body_frame) of a body: contacts and markers name both sides by it, so it must "
           "be unique in the scene");
    }
  }
}

}  // namespace

NodeConfig parseConfig(const XmlRpcValue& params, const ParameterReader& reader) {
  NodeConfig config;
  if (params.getType() != XmlRpcValue::TypeStruct && params.getType() != XmlRpcValue::TypeInvalid) {
    throw ParameterError("the private namespace ~ = " + render(params) +
                         ": must hold the node's parameters as named keys (a struct), not a single value");
  }
  requireStruct(params, "publish", "tf, odom, state, applied_wrench, body_services, per_body_topics (true or false)");
  requireStruct(params, "noise", "position_stddev, orientation_stddev, linear_velocity_stddev, angular_velocity_stddev, seed, delay");
  requireStruct(params, "contact", "iterations, iterations_dt, position_iterations, restitution_threshold, penetration_slop, "
                                   "position_correction, event_location, continuous, sleep, sleep_time, reuse_points");
  readSchemaParameters(params, config);
  readTiming(params, config);
  config.world_frame = readFrame(params, "world_frame", config.world_frame);
  config.gravity_W = readVector3(params, "gravity", "[m/s^2]");
  std::vector<std::string> unknown_in_bodies;  // reported after the top-level names
  config.bodies = parseBodies(params, config, unknown_in_bodies, reader);
  readOutputs(params, config);
  readNoise(params, config.noise);
  config.environment = readEnvironment(params, rigid_body::kDefaultMaxMeshBytes);
  refuseBodyNamedLikeTheEnvironment(config);
  config.unknown_parameters = unknownNames(params, unknown_in_bodies);
  return config;
}

BodyConfig parseBodyItem(const XmlRpcValue& item, const NodeConfig& scene, std::vector<std::string>& unknown,
                         const ParameterReader& reader) {
  XmlRpcValue params;
  params["bodies"].setSize(1);
  params["bodies"][0] = item;
  return parseBodies(params, scene, unknown, reader).front();
}

bool isKnownParameter(const std::string& key) {
  const std::size_t slash = key.find('/');
  if (slash == std::string::npos) {
    return schemaKeys("").count(key) > 0 || kSceneGroups.count(key) > 0 || kBodyNames.count(key) > 0;
  }
  const std::string group = key.substr(0, slash), rest = key.substr(slash + 1);
  if (group == "publish" || group == "noise" || group == "contact") return schemaKeys(group + "/").count(rest) > 0;
  if (group == "initial" || group == "imu") return bodySchemaKeys(group + "/").count(rest) > 0;
  return false;
}

std::string resolveMeshUri(const std::string& uri) {
  const std::string scheme = "package://";
  if (uri.compare(0, scheme.size(), scheme) != 0) return uri;
  const std::string rest = uri.substr(scheme.size());
  const std::string package = rest.substr(0, rest.find('/'));
  const std::string path = ros::package::getPath(package);
  if (path.empty()) {
    throw ParameterError("parameter ~mesh = '" + uri + "': package '" + package + "' not found (is its workspace sourced?)");
  }
  return path + rest.substr(package.size());
}

ParameterReader parameterServerReader() {
  return [](const std::string& name, std::string& value) { return ros::param::get(name, value); };
}

NodeConfig loadConfig(const ros::NodeHandle& private_nh) {
  XmlRpcValue params;
  if (!ros::param::get(private_nh.getNamespace(), params)) params = XmlRpcValue();
  return parseConfig(params, parameterServerReader());
}

std::string BodyConfig::shapeLabel() const {
  switch (mass_source) {
    case MassSource::kShape:
      return rigid_body::shapeTypeName(shape);
    case MassSource::kInertia:
      return "inertia";
    case MassSource::kUrdf:
      return "urdf";
  }
  return "unknown";
}

rigid_body::ContactSetup NodeConfig::contactSetup() const {
  rigid_body::ContactSetup setup;
  setup.environment = environment;
  setup.settings = contact;
  for (const BodyConfig& body : bodies) setup.bodies.push_back(body.collision);
  return setup;
}

std::string NodeConfig::describe() const {
  std::ostringstream out;
  out << "integrator " << rigid_body::integratorName(integrator) << ", world frame " << world_frame << ", gravity ["
      << gravity_W.transpose() << "] m/s^2, " << bodies.size() << (bodies.size() == 1 ? " body" : " bodies") << ", "
      << describeSchemaParameters(*this);
  for (const BodyConfig& body : bodies) {
    const Eigen::Vector3d& I = body.model.mass.principalMoments();
    out << "\n  body '" << (body.name.empty() ? "(flat)" : body.name) << "': frame " << body.body_frame << ", mass "
        << body.model.mass.mass() << " kg, shape " << body.shapeLabel()
        << (body.mesh_path.empty() ? "" : " '" + body.mesh_path + "'") << ", principal moments [" << I.x() << ", "
        << I.y() << ", " << I.z() << "] kg m^2, damping " << body.model.forces.linear_damping << " N s/m, "
        << body.model.forces.angular_damping << " N m s/rad, wrench input "
        << (body.wrench_input ? "true" : "false");
    if (body.collision) {
      out << ", collision " << rigid_body::shapeTypeName(body.collision->type) << " (restitution "
          << body.collision->material.restitution << ", friction " << body.collision->material.friction << ")";
    }
  }
  for (const rigid_body::CollisionShape& shape : environment) {
    out << "\n  environment '" << shape.name << "': " << rigid_body::shapeTypeName(shape.type) << " (restitution "
        << shape.material.restitution << ", friction " << shape.material.friction << ")";
  }
  return out.str();
}

}  // namespace rigid_body_ros
