// Parameter parsing and validation without a master: the private namespace as an XmlRpc struct.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "parameter_errors.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

using rigid_body_ros::BodyConfig;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::ParameterError;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue list(std::initializer_list<double> values) {
  XmlRpcValue array;
  array.setSize(static_cast<int>(values.size()));
  int i = 0;
  for (double v : values) array[i++] = v;
  return array;
}

using parameter_test::errorOf;

}  // namespace

TEST(Parameters, DefaultsAreTheDefaultScene) {
  const NodeConfig config = parseConfig(XmlRpcValue());
  EXPECT_EQ(config.rate, 100.0);
  EXPECT_EQ(config.dt, 0.001);
  EXPECT_EQ(config.integrator, rigid_body::IntegratorType::kRk4);
  EXPECT_EQ(config.world_frame, "world");
  EXPECT_EQ(config.bodies[0].body_frame, "base_link");
  EXPECT_EQ(config.bodies[0].model.mass.mass(), 1.0);
  EXPECT_NEAR(config.bodies[0].model.mass.inertia()(0, 0), (0.04 + 0.01) / 12.0, 1e-16);
  EXPECT_EQ(config.bodies[0].model.forces.gravity_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(config.wrench_timeout, 0.0);
  EXPECT_TRUE(config.publish.tf);
  EXPECT_TRUE(config.unknown_parameters.empty());
  EXPECT_TRUE(std::isinf(config.wrench_limits.max_force));  // no limit unless set
  EXPECT_EQ(config.max_energy_growth, 2.0);
  EXPECT_EQ(config.max_request_seconds, 1.0);  // a step request stops after a second of wall time
  EXPECT_EQ(config.max_tick_seconds, 0.25);
}

TEST(Parameters, ReadsEveryKey) {
  XmlRpcValue params;
  params["rate"] = 50;  // an int where a double is expected is fine
  params["dt"] = 0.002;
  params["integrator"] = std::string("semi_implicit_euler");
  params["world_frame"] = std::string("odom");
  params["body_frame"] = std::string("body");
  params["mass"] = 2.0;
  params["shape"] = std::string("cylinder");
  params["size"] = list({0.1, 1.0});
  params["gravity"] = list({0.0, 0.0, -9.81});
  params["linear_damping"] = 0.5;
  params["angular_damping"] = 0.25;
  params["wrench_timeout"] = 0.5;
  params["max_substeps"] = 20;
  params["max_request_seconds"] = 0.5;
  params["max_tick_seconds"] = 0.05;
  params["publish_tf"] = false;
  params["abs_tolerance"] = 1e-7;
  params["max_force"] = 50.0;
  params["max_torque"] = 5;
  params["max_energy_growth"] = 1.5;
  params["rel_tolerance"] = 1e-6;
  params["initial"]["position"] = list({1.0, 2.0, 3.0});
  params["initial"]["orientation"] = list({0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)});
  params["initial"]["linear_velocity"] = list({1.0, 0.0, 0.0});
  params["initial"]["angular_velocity"] = list({0.0, 0.0, 0.5});
  const NodeConfig config = parseConfig(params);
  EXPECT_EQ(config.rate, 50.0);
  EXPECT_EQ(config.dt, 0.002);
  EXPECT_EQ(config.integrator, rigid_body::IntegratorType::kSemiImplicitEuler);
  EXPECT_EQ(config.world_frame, "odom");
  EXPECT_EQ(config.bodies[0].body_frame, "body");
  EXPECT_NEAR(config.bodies[0].model.mass.inertia()(2, 2), 0.5 * 2.0 * 0.01, 1e-15);
  EXPECT_EQ(config.bodies[0].model.forces.gravity_W.z(), -9.81);
  EXPECT_EQ(config.bodies[0].model.forces.linear_damping, 0.5);
  EXPECT_EQ(config.bodies[0].model.forces.angular_damping, 0.25);
  EXPECT_EQ(config.wrench_timeout, 0.5);
  EXPECT_EQ(config.max_substeps, 20);
  EXPECT_EQ(config.max_request_seconds, 0.5);
  EXPECT_EQ(config.max_tick_seconds, 0.05);
  EXPECT_FALSE(config.publish.tf);
  EXPECT_EQ(config.integrator_settings.abs_tolerance, 1e-7);
  EXPECT_EQ(config.wrench_limits.max_force, 50.0);
  EXPECT_EQ(config.wrench_limits.max_torque, 5.0);
  EXPECT_EQ(config.max_energy_growth, 1.5);
  EXPECT_EQ(config.integrator_settings.rel_tolerance, 1e-6);
  EXPECT_EQ(config.bodies[0].initial.p_WB, Eigen::Vector3d(1.0, 2.0, 3.0));
  // v is given in world axes, ω in body axes: P = M v, L = R I ω_B.
  EXPECT_TRUE(config.bodies[0].initial.P_W.isApprox(Eigen::Vector3d(2.0, 0.0, 0.0)));
  EXPECT_TRUE(rigid_body::angularVelocity(config.bodies[0].model.mass, config.bodies[0].initial).isApprox(Eigen::Vector3d(0, 0, 0.5)));
}

TEST(Parameters, FullInertiaOverridesTheShape) {
  XmlRpcValue params;
  params["shape"] = std::string("sphere");
  params["inertia"] = list({1.0, 2.0, 2.5, 0.1, 0.0, 0.0});
  const NodeConfig config = parseConfig(params);
  EXPECT_EQ(config.bodies[0].mass_source, rigid_body_ros::MassSource::kInertia);
  EXPECT_EQ(config.bodies[0].model.mass.inertia()(0, 1), 0.1);
  EXPECT_EQ(config.bodies[0].model.mass.inertia()(1, 0), 0.1);
}

TEST(Parameters, EachInvalidValueNamesTheParameterAndTheRule) {
  struct Case {
    std::string name;
    XmlRpcValue value;
    std::string expected;  // a part of the message
  };
  const std::vector<Case> cases = {
      {"mass", XmlRpcValue(-1.0), "parameter ~mass = -1: must be a finite number > 0 [kg]"},
      {"mass", XmlRpcValue(std::string("heavy")), "parameter ~mass = 'heavy'"},
      {"rate", XmlRpcValue(0.0), "parameter ~rate = 0: must be a finite number in [0.001, 10000] [Hz]"},
      {"dt", XmlRpcValue(0.1), "parameter ~dt = 0.10000000000000001: must be a finite number in (0, 1/rate = 0.01] [s]"},
      {"integrator", XmlRpcValue(std::string("rk5")),
       "parameter ~integrator = 'rk5': must be one of: explicit_euler, semi_implicit_euler, rk4"},
      {"shape", XmlRpcValue(std::string("cone")), "parameter ~shape = 'cone': must be one of: box, sphere, cylinder"},
      {"size", list({0.4, 0.2}), "parameter ~size = [0.40000000000000002, 0.20000000000000001]: for a box, must be [x, y, z]"},
      {"size", list({0.4, -0.2, 0.1}), "for a box, must be [x, y, z] with 3 finite numbers > 0 [m]"},
      {"inertia", list({1.0, 1.0, 5.0, 0.0, 0.0, 0.0}), "parameter ~inertia = [1, 1, 5, 0, 0, 0]: inertia violates the triangle inequality"},
      {"inertia", list({1.0, 1.0}), "must be a list of 6 finite numbers"},
      {"gravity", list({0.0, 0.0}), "parameter ~gravity = [0, 0]: must be a list of 3 finite numbers"},
      {"linear_damping", XmlRpcValue(-0.1), "parameter ~linear_damping = -0.10000000000000001: must be a finite number >= 0"},
      {"angular_damping", XmlRpcValue(std::nan("")), "~angular_damping = nan: must be a finite number >= 0"},
      {"wrench_timeout", XmlRpcValue(-1), "parameter ~wrench_timeout = -1: must be a finite number >= 0 [s]"},
      {"max_substeps", XmlRpcValue(0), "parameter ~max_substeps = 0: must be an integer >= 1"},
      {"publish_tf", XmlRpcValue(std::string("yes")), "parameter ~publish_tf = 'yes': must be true or false"},
      {"max_force", XmlRpcValue(-5.0), "parameter ~max_force = -5: must be a finite number > 0 [N]"},
      {"max_torque", XmlRpcValue(std::string("lots")), "parameter ~max_torque = 'lots': must be a finite number > 0 [N m]"},
      {"max_energy_growth", XmlRpcValue(1.0), "parameter ~max_energy_growth = 1: must be a finite number > 1"},
      {"abs_tolerance", XmlRpcValue(0.0), "parameter ~abs_tolerance = 0: must be a finite number in [1e-15, 1]"},
      {"rel_tolerance", XmlRpcValue(2), "parameter ~rel_tolerance = 2: must be a finite number in [1e-15, 1]"},
      {"world_frame", XmlRpcValue(std::string("/world")), "parameter ~world_frame = '/world': must be a non-empty tf2 frame id"},
      {"body_frame", XmlRpcValue(std::string("world")), "parameter ~body_frame = 'world': must differ from ~world_frame"},
      {"marker_rate", XmlRpcValue(500.0), "parameter ~marker_rate = 500: must be a finite number in [0.001, rate = 100] [Hz]"},
  };
  for (const Case& c : cases) {
    XmlRpcValue params;
    params[c.name] = c.value;
    const std::string message = errorOf(params);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "for ~" << c.name << " got: '" << message << "'";
  }
}

TEST(Parameters, InvalidInitialStateIsRefused) {
  XmlRpcValue params;
  params["initial"]["orientation"] = list({0.0, 0.0, 0.0, 2.0});
  EXPECT_NE(errorOf(params).find("parameter ~initial/orientation = [0, 0, 0, 2]: must be a unit quaternion"),
            std::string::npos)
      << errorOf(params);
  XmlRpcValue velocity;
  velocity["initial"]["linear_velocity"] = list({0.0, std::numeric_limits<double>::infinity(), 0.0});
  EXPECT_NE(errorOf(velocity).find("~initial/linear_velocity"), std::string::npos) << errorOf(velocity);
}

// A default that comes from another parameter can be refused too; the message then names the parameter and
// the value it would have taken (reading the unset value for the message once crashed the node).
TEST(Parameters, RefusedDefaultsNameTheParameterAndTheValueTheyWouldTake) {
  for (const std::string link : {"a b", "/base", ""}) {
    XmlRpcValue params;  // body_frame defaults to the URDF link's name, read before the URDF itself
    params["urdf"] = std::string("/nonexistent/robot.urdf");
    params["link"] = link;
    const std::string message = errorOf(params);
    if (link.empty()) {
      EXPECT_NE(message.find("parameter ~link"), std::string::npos) << message;
    } else {
      EXPECT_NE(message.find("parameter ~body_frame (not set, so '" + link + "'): must be a non-empty tf2 frame id"),
                std::string::npos)
          << message;
    }
  }
  XmlRpcValue same_frame;  // the default body frame base_link as the world frame
  same_frame["world_frame"] = std::string("base_link");
  EXPECT_NE(errorOf(same_frame).find("parameter ~body_frame (not set, so 'base_link'): must differ from ~world_frame"),
            std::string::npos)
      << errorOf(same_frame);
  XmlRpcValue ground, box;  // an environment shape's default name is its type and index: plane1 here
  ground["type"] = std::string("plane");
  box["type"] = std::string("box");
  box["name"] = std::string("plane1");
  box["size"] = list({1.0, 1.0, 1.0});
  XmlRpcValue names;
  names["environment"][0] = box;
  names["environment"][1] = ground;
  EXPECT_NE(errorOf(names).find("parameter ~environment[1]/name (not set, so 'plane1'): must be unique"),
            std::string::npos)
      << errorOf(names);
  XmlRpcValue unnamed;  // an item of ~bodies without a name
  unnamed["bodies"][0]["mass"] = 1.0;
  EXPECT_NE(errorOf(unnamed).find("parameter ~bodies[0]/name (not set, so ''): must be a unique name"),
            std::string::npos)
      << errorOf(unnamed);
}

TEST(Parameters, ListsWrittenAsTextAreRead) {
  // What roscpp makes of `rosrun ... _size:="[0.5, 0.25, 2]"`: a string.
  XmlRpcValue params;
  params["size"] = std::string("[0.5, 0.25, 2]");
  params["initial"]["position"] = std::string(" [1,-2e-1, 3] ");
  const NodeConfig config = parseConfig(params);
  EXPECT_EQ(config.bodies[0].size, (std::vector<double>{0.5, 0.25, 2.0}));
  EXPECT_EQ(config.bodies[0].initial.p_WB, Eigen::Vector3d(1.0, -0.2, 3.0));
  XmlRpcValue bad;
  bad["size"] = std::string("[0.5, big, 2]");
  EXPECT_NE(errorOf(bad).find("parameter ~size = '[0.5, big, 2]': for a box"), std::string::npos) << errorOf(bad);
}

TEST(Parameters, NearlyUnitQuaternionIsNormalised) {
  XmlRpcValue params;
  params["initial"]["orientation"] = list({0.0, 0.0, 0.7071, 0.7071});
  const NodeConfig config = parseConfig(params);
  EXPECT_NEAR(config.bodies[0].initial.q_WB.norm(), 1.0, 1e-15);
}

TEST(Parameters, UnknownNamesAreReported) {
  XmlRpcValue params;
  params["mas"] = 1.0;
  params["initial"]["postion"] = list({0.0, 0.0, 0.0});
  const NodeConfig config = parseConfig(params);
  ASSERT_EQ(config.unknown_parameters.size(), 2u);
  EXPECT_EQ(config.unknown_parameters[0], "mas");
  EXPECT_EQ(config.unknown_parameters[1], "initial/postion");
}

TEST(Parameters, SamplingMoreThanTheMeshAllowsNamesSamplesAndItsLimit) {
  XmlRpcValue params;  // sphere.stl: 1 280 triangles, so at most 2e9 / 1280 = 1 562 500 samples
  params["shape"] = std::string("mesh");
  params["mesh"] = std::string(TEST_MESH_DIR "/sphere.stl");
  params["mass"] = 1.0;
  params["inertia_method"] = std::string("sampling");
  params["samples"] = 10000000;
  EXPECT_NE(errorOf(params).find("parameter ~samples = 10000000: with this mesh's 1280 triangles, must be at most 1562500"),
            std::string::npos)
      << errorOf(params);
}

TEST(Parameters, MeshBodyFromAFileOrAPackageUri) {
  XmlRpcValue params;
  params["shape"] = std::string("mesh");
  params["mesh"] = std::string(TEST_MESH_DIR "/l_bracket.obj");
  params["density"] = 2700.0;
  params["principal_axes"] = true;
  const NodeConfig config = parseConfig(params);
  EXPECT_TRUE(config.bodies[0].hasShape(rigid_body::ShapeType::kMesh));
  // (2·0.1 − 0.02)·0.02·0.005 m³ of aluminium.
  EXPECT_NEAR(config.bodies[0].model.mass.mass(), 2700.0 * 0.18 * 0.02 * 0.005, 1e-12);
  const Eigen::Matrix3d& I = config.bodies[0].model.mass.inertia();
  EXPECT_LT(std::abs(I(0, 1)), 1e-12 * I.norm());  // principal axes: diagonal
  EXPECT_GT(config.bodies[0].X_MB.translation().x(), 0.0);   // the centre of mass, in the mesh frame
  EXPECT_TRUE(config.unknown_parameters.empty());

  // The same file by package:// (rospack finds this package in the test environment).
  XmlRpcValue by_uri = params;
  by_uri["mesh"] = std::string("package://rigid_body_sim/test/meshes/l_bracket.obj");
  EXPECT_EQ(parseConfig(by_uri).bodies[0].model.mass.mass(), config.bodies[0].model.mass.mass());
  EXPECT_EQ(rigid_body_ros::resolveMeshUri("/abs/file.stl"), "/abs/file.stl");
}

TEST(Parameters, PrincipalAxesTurnTheBodyFrameAndXMBSaysHow) {
  // The same mesh with and without principal_axes: the body frame's origin is the centre of mass either way;
  // with principal axes its axes are turned by R_MB (X_MB's rotation), so that the mesh-axes tensor is
  // R_MB I_B R_MBᵀ with I_B diagonal. A transform in the wrong direction (X_BM for X_MB) fails this.
  XmlRpcValue params;
  params["shape"] = std::string("mesh");
  params["mesh"] = std::string(TEST_MESH_DIR "/l_bracket.obj");
  params["density"] = 2700.0;
  params["mesh_frame"] = std::string("bracket_mesh");
  const rigid_body_ros::BodyConfig mesh_axes = parseConfig(params).bodies[0];
  params["principal_axes"] = true;
  const rigid_body_ros::BodyConfig principal = parseConfig(params).bodies[0];
  EXPECT_TRUE(mesh_axes.X_MB.linear().isIdentity(1e-15));
  EXPECT_LT((principal.X_MB.translation() - mesh_axes.X_MB.translation()).norm(), 1e-15);
  const Eigen::Matrix3d R_MB = principal.X_MB.linear();
  const Eigen::Matrix3d& I_B = principal.model.mass.inertia();
  EXPECT_LT((I_B - Eigen::Matrix3d(I_B.diagonal().asDiagonal())).norm(), 1e-12 * I_B.norm());
  EXPECT_LT((R_MB * I_B * R_MB.transpose() - mesh_axes.model.mass.inertia()).norm(), 1e-12 * I_B.norm());
  EXPECT_NEAR(R_MB.determinant(), 1.0, 1e-12);  // a rotation, not a reflection
  EXPECT_EQ(principal.mesh_frame, "bracket_mesh");
}

TEST(Parameters, MeshProblemsNameTheParameter) {
  const auto meshParams = [](const std::string& file) {
    XmlRpcValue params;
    params["shape"] = std::string("mesh");
    params["mesh"] = std::string(TEST_MESH_DIR) + file;
    params["mass"] = 1.0;
    return params;
  };
  EXPECT_NE(errorOf(meshParams("/open_box.obj")).find("parameter ~mesh = '"), std::string::npos);
  EXPECT_NE(errorOf(meshParams("/open_box.obj")).find("mesh is not closed"), std::string::npos);
  EXPECT_NE(errorOf(meshParams("/missing.stl")).find("cannot open mesh file"), std::string::npos);
  XmlRpcValue both = meshParams("/box.obj");
  both["density"] = 1000.0;
  EXPECT_NE(errorOf(both).find("give ~mass or ~density, not both"), std::string::npos) << errorOf(both);
  XmlRpcValue no_mass;
  no_mass["shape"] = std::string("mesh");
  no_mass["mesh"] = std::string(TEST_MESH_DIR "/box.obj");
  EXPECT_NE(errorOf(no_mass).find("give ~mass [kg] or ~density"), std::string::npos) << errorOf(no_mass);
  XmlRpcValue no_file;
  no_file["shape"] = std::string("mesh");
  EXPECT_NE(errorOf(no_file).find("parameter ~mesh"), std::string::npos) << errorOf(no_file);
  XmlRpcValue method = meshParams("/box.obj");
  method["inertia_method"] = std::string("guess");
  EXPECT_NE(errorOf(method).find("parameter ~inertia_method = 'guess'"), std::string::npos);
  XmlRpcValue package = meshParams("/box.obj");
  package["mesh"] = std::string("package://no_such_package/box.stl");
  EXPECT_NE(errorOf(package).find("package 'no_such_package' not found"), std::string::npos) << errorOf(package);
  XmlRpcValue frame;
  frame["mesh_frame"] = std::string("visual");
  EXPECT_NE(errorOf(frame).find("is only for shape mesh"), std::string::npos);
  // An inside-out mesh is repaired, with a warning for the log.
  EXPECT_EQ(parseConfig(meshParams("/inside_out_box.obj")).bodies[0].mesh_warnings.size(), 1u);
}

TEST(Parameters, LockstepAndNoise) {
  XmlRpcValue params;
  params["lockstep"] = true;
  params["real_time_factor"] = 0;
  params["start_paused"] = true;
  params["noise"]["position_stddev"] = list({0.01, 0.02, 0.03});
  params["noise"]["delay"] = 0.05;
  params["noise"]["seed"] = 42;
  const NodeConfig config = parseConfig(params);
  EXPECT_TRUE(config.lockstep);
  EXPECT_EQ(config.real_time_factor, 0.0);
  EXPECT_TRUE(config.start_paused);
  EXPECT_TRUE(config.noise.enabled());
  EXPECT_EQ(config.noise.position_stddev, Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_EQ(config.noise.delay, 0.05);
  EXPECT_EQ(config.noise.seed, 42);
  EXPECT_FALSE(parseConfig(XmlRpcValue()).noise.enabled());  // off by default: no odom_noisy at all

  XmlRpcValue bad;
  bad["real_time_factor"] = -1.0;
  EXPECT_NE(errorOf(bad).find("parameter ~real_time_factor = -1: must be a finite number >= 0"), std::string::npos);
  XmlRpcValue negative;
  negative["noise"]["orientation_stddev"] = list({0.0, -0.1, 0.0});
  EXPECT_NE(errorOf(negative).find("parameter ~noise/orientation_stddev"), std::string::npos) << errorOf(negative);
  XmlRpcValue typo;
  typo["noise"]["postion_stddev"] = list({0.0, 0.0, 0.0});
  EXPECT_EQ(parseConfig(typo).unknown_parameters, std::vector<std::string>{"noise/postion_stddev"});
}

namespace {
XmlRpcValue bodyItem(const std::string& name) {
  XmlRpcValue item;
  item["name"] = name;
  return item;
}
}  // namespace

TEST(Parameters, BodiesListGivesEachBodyItsKeysAndTheSceneItsOwn) {
  XmlRpcValue params;
  params["gravity"] = XmlRpcValue();
  params["gravity"][0] = 0.0, params["gravity"][1] = 0.0, params["gravity"][2] = -9.81;
  params["publish"]["state"] = false;
  XmlRpcValue box = bodyItem("box");
  box["mass"] = 2.0;
  box["linear_damping"] = 0.5;
  XmlRpcValue ball = bodyItem("ball");
  ball["shape"] = std::string("sphere");
  ball["size"][0] = 0.2;
  ball["body_frame"] = std::string("ball_link");
  ball["wrench_input"] = false;
  ball["initial"]["position"][0] = 1.0, ball["initial"]["position"][1] = 0.0, ball["initial"]["position"][2] = 0.0;
  params["bodies"][0] = box;
  params["bodies"][1] = ball;
  const NodeConfig config = parseConfig(params);
  ASSERT_EQ(config.bodies.size(), 2u);
  EXPECT_EQ(config.bodies[0].name, "box");
  EXPECT_EQ(config.bodies[0].body_frame, "box");  // the name, unless body_frame is given
  EXPECT_EQ(config.bodies[0].topic("odom"), "box/odom");
  EXPECT_EQ(config.bodies[0].model.mass.mass(), 2.0);
  EXPECT_EQ(config.bodies[0].model.forces.linear_damping, 0.5);
  EXPECT_TRUE(config.bodies[0].wrench_input);
  EXPECT_EQ(config.bodies[1].body_frame, "ball_link");
  EXPECT_TRUE(config.bodies[1].hasShape(rigid_body::ShapeType::kSphere));
  EXPECT_FALSE(config.bodies[1].wrench_input);
  EXPECT_EQ(config.bodies[1].initial.p_WB, Eigen::Vector3d(1.0, 0.0, 0.0));
  for (const rigid_body_ros::BodyConfig& body : config.bodies) EXPECT_EQ(body.model.forces.gravity_W.z(), -9.81);  // scene-wide
  EXPECT_TRUE(config.publish.tf);
  EXPECT_TRUE(config.publish.odom);
  EXPECT_FALSE(config.publish.state);
  EXPECT_TRUE(config.unknown_parameters.empty());
  // The flat form is one body without a topic prefix.
  EXPECT_EQ(parseConfig(XmlRpcValue()).bodies.size(), 1u);
  EXPECT_EQ(parseConfig(XmlRpcValue()).bodies[0].topic("odom"), "odom");
}

TEST(Parameters, BodiesListErrorsNameTheItem) {
  XmlRpcValue bad_mass;
  bad_mass["bodies"][0] = bodyItem("a");
  bad_mass["bodies"][1] = bodyItem("b");
  bad_mass["bodies"][1]["mass"] = -1.0;
  EXPECT_EQ(errorOf(bad_mass), "parameter ~bodies[1]/mass = -1: must be a finite number > 0 [kg]");
  XmlRpcValue duplicate;
  duplicate["bodies"][0] = bodyItem("a");
  duplicate["bodies"][1] = bodyItem("a");
  EXPECT_NE(errorOf(duplicate).find("parameter ~bodies[1]/name = 'a': must be a unique name"), std::string::npos)
      << errorOf(duplicate);
  XmlRpcValue unnamed;
  unnamed["bodies"][0] = XmlRpcValue();
  unnamed["bodies"][0]["mass"] = 1.0;
  EXPECT_NE(errorOf(unnamed).find("parameter ~bodies[0]/name"), std::string::npos) << errorOf(unnamed);
  XmlRpcValue both;
  both["bodies"][0] = bodyItem("a");
  both["mass"] = 1.0;
  EXPECT_NE(errorOf(both).find("parameter ~mass = 1: is a body key"), std::string::npos) << errorOf(both);
  XmlRpcValue same_frame;
  same_frame["bodies"][0] = bodyItem("a");
  same_frame["bodies"][1] = bodyItem("b");
  same_frame["bodies"][1]["body_frame"] = std::string("a");
  EXPECT_NE(errorOf(same_frame).find("~bodies[1]/body_frame"), std::string::npos) << errorOf(same_frame);
  XmlRpcValue empty;
  empty["bodies"].setSize(0);
  EXPECT_NE(errorOf(empty).find("parameter ~bodies"), std::string::npos);
  XmlRpcValue typo;
  typo["bodies"][0] = bodyItem("a");
  typo["bodies"][0]["mas"] = 1.0;
  typo["publish"]["od0m"] = true;
  const NodeConfig config = parseConfig(typo);
  ASSERT_EQ(config.unknown_parameters.size(), 2u);
  EXPECT_EQ(config.unknown_parameters[0], "publish/od0m");
  EXPECT_EQ(config.unknown_parameters[1], "bodies[0]/mas");
}

namespace {

XmlRpcValue shapeItem(const std::string& type) {
  XmlRpcValue item;
  item["type"] = type;
  return item;
}

}  // namespace

TEST(ContactParameters, CollisionTrueIsTheBodysOwnShapeWithTheDefaultMaterial) {
  XmlRpcValue params;
  params["shape"] = std::string("box");
  params["size"] = list({0.4, 0.2, 0.1});
  params["collision"] = true;
  const NodeConfig config = parseConfig(params);
  ASSERT_TRUE(config.bodies[0].collision.has_value());
  const rigid_body::CollisionShape& shape = *config.bodies[0].collision;
  EXPECT_EQ(shape.type, rigid_body::ShapeType::kBox);
  EXPECT_EQ(shape.size, Eigen::Vector3d(0.4, 0.2, 0.1));
  EXPECT_EQ(shape.material.restitution, 0.0);
  EXPECT_EQ(shape.material.friction, 0.5);
  EXPECT_TRUE(config.contactSetup().active());
  // Absent or false: the body collides with nothing, and the scene has no contact step.
  params["collision"] = false;
  EXPECT_FALSE(parseConfig(params).bodies[0].collision.has_value());
  EXPECT_FALSE(parseConfig(params).contactSetup().active());
}

TEST(ContactParameters, ACollisionStructOverridesTheOwnShapeKeyByKey) {
  XmlRpcValue params;
  params["shape"] = std::string("sphere");
  params["size"] = list({0.1});
  params["collision"]["restitution"] = 0.8;
  NodeConfig config = parseConfig(params);
  EXPECT_EQ(config.bodies[0].collision->type, rigid_body::ShapeType::kSphere);
  EXPECT_EQ(config.bodies[0].collision->size.x(), 0.1);
  EXPECT_EQ(config.bodies[0].collision->material.restitution, 0.8);
  params["collision"]["shape"] = std::string("capsule");
  params["collision"]["size"] = list({0.05, 0.2});
  config = parseConfig(params);
  EXPECT_EQ(config.bodies[0].collision->type, rigid_body::ShapeType::kCapsule);
  EXPECT_EQ(config.bodies[0].collision->size, Eigen::Vector3d(0.05, 0.2, 0.0));
}

TEST(ContactParameters, EnvironmentShapesAreRead) {
  XmlRpcValue params;
  XmlRpcValue ground = shapeItem("plane");
  ground["normal"] = list({0.0, 0.0, 2.0});
  ground["offset"] = -1.0;
  ground["friction"] = 0.9;
  XmlRpcValue wall = shapeItem("box");
  wall["name"] = std::string("wall");
  wall["size"] = list({0.1, 2.0, 1.0});
  wall["pose"]["position"] = list({1.0, 0.0, 0.5});
  params["environment"][0] = ground;
  params["environment"][1] = wall;
  const NodeConfig config = parseConfig(params);
  ASSERT_EQ(config.environment.size(), 2u);
  EXPECT_EQ(config.environment[0].normal, Eigen::Vector3d::UnitZ());  // normalised
  EXPECT_EQ(config.environment[0].offset, -1.0);
  EXPECT_EQ(config.environment[0].material.friction, 0.9);
  EXPECT_EQ(config.environment[0].name, "plane0");
  EXPECT_EQ(config.environment[1].name, "wall");
  EXPECT_EQ(config.environment[1].pose.translation(), Eigen::Vector3d(1.0, 0.0, 0.5));
}

TEST(ContactParameters, EachInvalidContactValueNamesItsParameter) {
  struct Case {
    XmlRpcValue params;
    std::string expected;
  };
  std::vector<Case> cases;
  {
    XmlRpcValue p;
    p["collision"]["restitution"] = 1.5;
    cases.push_back({p, "parameter ~collision/restitution = 1.5: must be a number in [0, 1]"});
  }
  {
    XmlRpcValue p;
    p["collision"]["friction"] = -1.0;
    cases.push_back({p, "parameter ~collision/friction = -1: must be a finite number >= 0"});
  }
  {
    XmlRpcValue p;
    p["collision"]["colour"] = std::string("red");
    cases.push_back({p, "parameter ~collision/colour = 'red': is not a key here"});
  }
  {
    XmlRpcValue p;
    p["collision"]["shape"] = std::string("capsule");
    cases.push_back({p, "parameter ~collision/size"});
  }
  {
    XmlRpcValue p;
    p["inertia"] = list({1.0, 1.0, 1.0, 0.0, 0.0, 0.0});
    p["collision"] = true;
    cases.push_back({p, "parameter ~collision = true: needs a shape"});
  }
  {
    XmlRpcValue p;
    p["collision"] = std::string("yes");
    cases.push_back({p, "parameter ~collision = 'yes': must be true, false or a struct"});
  }
  {
    XmlRpcValue p;
    p["environment"][0] = shapeItem("cone");
    cases.push_back({p, "parameter ~environment[0]/type = 'cone': must be one of: plane, box"});
  }
  {
    XmlRpcValue p;
    XmlRpcValue plane = shapeItem("plane");
    plane["normal"] = list({0.0, 0.0, 0.0});
    p["environment"][0] = plane;
    cases.push_back({p, "parameter ~environment[0]/normal = [0, 0, 0]: must be 3 finite numbers, not all 0"});
  }
  {
    XmlRpcValue p;
    XmlRpcValue plane = shapeItem("plane");
    plane["size"] = list({1.0, 1.0, 1.0});
    p["environment"][0] = plane;
    cases.push_back({p, "parameter ~environment[0]/size = [1, 1, 1]: is not a key of a plane"});
  }
  {
    XmlRpcValue p;
    p["environment"][0] = shapeItem("box");
    cases.push_back({p, "parameter ~environment[0]/size"});
  }
  {
    XmlRpcValue p;
    XmlRpcValue ball = shapeItem("sphere");
    ball["size"] = list({0.5});
    ball["restitution"] = -0.5;
    p["environment"][0] = ball;
    cases.push_back({p, "parameter ~environment[0]/restitution = -0.5"});
  }
  {
    XmlRpcValue p;
    p["environment"] = 3;
    cases.push_back({p, "parameter ~environment = 3: must be a list of shapes"});
  }
  {
    XmlRpcValue p;
    p["collision"]["shape"] = std::string("sphere");
    p["collision"]["size"] = list({1e7});
    cases.push_back({p, "parameter ~collision/size = [10000000]: for a sphere, must be [radius] with a finite number > 0 [m], each in [1e-6, 1e6] m"});
  }
  {
    XmlRpcValue p;
    XmlRpcValue wall = shapeItem("box");
    wall["size"] = list({1.0, 1.0, 1.0});
    wall["pose"]["position"] = list({1e300, 0.0, 0.0});
    p["environment"][0] = wall;
    cases.push_back({p, "parameter ~environment[0]/pose/position"});
  }
  {
    XmlRpcValue p;
    p["contact"]["iterations"] = 0;
    cases.push_back({p, "parameter ~contact/iterations = 0"});
  }
  {
    XmlRpcValue p;
    p["contact"]["penetration_slop"] = 1.0;
    cases.push_back({p, "parameter ~contact/penetration_slop = 1: must be a finite number in [0, 0.1] [m]"});
  }
  for (const Case& c : cases) {
    const std::string message = errorOf(c.params);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "', got: '" << message << "'";
  }
}

TEST(ContactParameters, AMeshBodyCollidesAsItsHullInTheBodyFrame) {
  XmlRpcValue params;
  params["shape"] = std::string("mesh");
  params["mesh"] = std::string(TEST_MESH_DIR "/l_bracket.obj");
  params["mass"] = 1.0;
  params["collision"] = true;
  const NodeConfig config = parseConfig(params);
  ASSERT_TRUE(config.bodies[0].collision.has_value());
  const rigid_body::TriangleMesh& mesh = config.bodies[0].collision->mesh;
  ASSERT_FALSE(mesh.vertices.empty());
  // The body frame's origin is the centre of mass: the vertices' mean is near it, not at the file's origin.
  Eigen::Vector3d file_mean = Eigen::Vector3d::Zero(), body_mean = Eigen::Vector3d::Zero();
  for (const auto& v : config.bodies[0].mesh.vertices) file_mean += v;
  for (const auto& v : mesh.vertices) body_mean += v;
  file_mean /= static_cast<double>(config.bodies[0].mesh.vertices.size());
  body_mean /= static_cast<double>(mesh.vertices.size());
  EXPECT_LT((body_mean - (config.bodies[0].X_MB.inverse() * file_mean)).norm(), 1e-12);
}

// ---------------------------------------------------------------------------------------------------------
// A body from a URDF link (test/urdf/offset_link.urdf: the inertial frame offset by (0.1, −0.05, 0.02) and
// turned by rpy (0.3, 0.2, −0.4) from the link frame).

namespace {

XmlRpcValue urdfBody(const std::string& link) {
  XmlRpcValue params;
  params["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  params["link"] = link;
  return params;
}

Eigen::Quaterniond fromRpy(double roll, double pitch, double yaw) {
  // URDF's rpy: fixed-axis roll about x, then pitch about y, then yaw about z: R = Rz(yaw) Ry(pitch) Rx(roll).
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

}  // namespace

TEST(UrdfBody, TheLinksInertialGivesMassCentreAndInertiaAndTheLinkFrameIsPublished) {
  const NodeConfig config = parseConfig(urdfBody("base_link"));
  const BodyConfig& body = config.bodies[0];
  EXPECT_EQ(body.body_frame, "base_link");  // the link's name
  EXPECT_EQ(body.model.mass.mass(), 2.0);
  Eigen::Matrix3d I;
  I << 0.10, 0.005, -0.002, 0.005, 0.20, 0.004, -0.002, 0.004, 0.25;
  EXPECT_LT((body.model.mass.inertia() - I).norm(), 1e-15);  // about the centre of mass, in the inertial frame
  // X_BP = X_LB⁻¹: the link frame seen from the centre of mass.
  Eigen::Isometry3d X_LB = Eigen::Isometry3d::Identity();
  X_LB.linear() = fromRpy(0.3, 0.2, -0.4).toRotationMatrix();
  X_LB.translation() = Eigen::Vector3d(0.1, -0.05, 0.02);
  EXPECT_TRUE(body.published_offset);
  EXPECT_LT((body.X_BP.matrix() - X_LB.inverse().matrix()).norm(), 1e-12);
  // The collision box, posed in the body frame: X_BC = X_BL X_LC.
  ASSERT_TRUE(body.urdf_collision.has_value());
  EXPECT_EQ(body.urdf_collision->type, rigid_body::ShapeType::kBox);
  EXPECT_EQ(body.urdf_collision->size, Eigen::Vector3d(0.4, 0.2, 0.1));
  Eigen::Isometry3d X_LC = Eigen::Isometry3d::Identity();
  X_LC.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  EXPECT_LT((body.urdf_collision->pose.matrix() - (X_LB.inverse() * X_LC).matrix()).norm(), 1e-12);
  ASSERT_TRUE(body.visual.has_value());
  EXPECT_EQ(body.visual->type, rigid_body::ShapeType::kCylinder);
}

TEST(UrdfBody, InitialKeysPlaceTheLinkFrameAndItsOriginsVelocity) {
  // initial/* describe the link frame P; the core's state is the centre of mass's. The published frame
  // computed back from that state (conversions' publishedFrame) must give them again.
  XmlRpcValue params = urdfBody("base_link");
  params["initial"]["position"] = list({1.0, -2.0, 0.5});
  params["initial"]["orientation"] = list({0.0, 0.0, std::sin(0.35), std::cos(0.35)});
  params["initial"]["linear_velocity"] = list({0.3, 0.1, -0.2});
  params["initial"]["angular_velocity"] = list({0.5, -1.0, 2.0});
  const NodeConfig config = parseConfig(params);
  const BodyConfig& body = config.bodies[0];
  const rigid_body_ros::FrameMotion P = rigid_body_ros::publishedFrame(body.model.mass, body.initial, body.X_BP);
  EXPECT_LT((P.p_WP - Eigen::Vector3d(1.0, -2.0, 0.5)).norm(), 1e-12);
  EXPECT_LT(P.q_WP.angularDistance(Eigen::Quaterniond(std::cos(0.35), 0.0, 0.0, std::sin(0.35))), 1e-12);
  EXPECT_LT((P.v_WP_W - Eigen::Vector3d(0.3, 0.1, -0.2)).norm(), 1e-12);
  EXPECT_LT((P.q_WP.conjugate() * P.w_W - Eigen::Vector3d(0.5, -1.0, 2.0)).norm(), 1e-12);
  // The centre of mass is where the inertial origin says: p_WB = p_WP + R_WP p_LB.
  EXPECT_LT((body.initial.p_WB - (P.p_WP + P.q_WP * Eigen::Vector3d(0.1, -0.05, 0.02))).norm(), 1e-12);
}

TEST(UrdfBody, BadLinksStopTheNodeNamingTheLink) {
  EXPECT_NE(errorOf(urdfBody("elbow")).find("parameter ~link = 'elbow': names no link"), std::string::npos);
  EXPECT_NE(errorOf(urdfBody("sensor")).find("parameter ~link = 'sensor': has no <inertial>"), std::string::npos);
  EXPECT_NE(errorOf(urdfBody("impossible")).find("parameter ~link = 'impossible': has a non-physical <inertial>"),
            std::string::npos);
  XmlRpcValue with_mass = urdfBody("base_link");
  with_mass["mass"] = 3.0;
  EXPECT_NE(errorOf(with_mass).find("parameter ~mass = 3: is not a key of a body given by ~urdf"), std::string::npos);
  XmlRpcValue no_file = urdfBody("base_link");
  no_file["urdf"] = std::string("/nonexistent/robot.urdf");
  EXPECT_NE(errorOf(no_file).find("parameter ~urdf = '/nonexistent/robot.urdf': cannot open"), std::string::npos);
  XmlRpcValue device = urdfBody("base_link");
  device["urdf"] = std::string("/dev/zero");
  EXPECT_NE(errorOf(device).find("parameter ~urdf = '/dev/zero': cannot open the file '/dev/zero' (not a regular file"),
            std::string::npos);
  XmlRpcValue far = urdfBody("far");
  far["urdf"] = std::string(TEST_URDF_DIR "/bad_links.urdf");
  EXPECT_NE(errorOf(far).find("parameter ~link = 'far': has an <inertial> origin beyond 1e6 m"), std::string::npos);
  XmlRpcValue flat = urdfBody("flat_box");
  flat["urdf"] = std::string(TEST_URDF_DIR "/bad_links.urdf");
  flat["collision"] = true;
  EXPECT_NE(errorOf(flat).find("parameter ~link = 'flat_box': has an unusable <collision>"), std::string::npos);
  flat["collision"] = false;  // not used: not a problem
  EXPECT_EQ(errorOf(flat), "");
  XmlRpcValue no_link;
  no_link["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  EXPECT_NE(errorOf(no_link).find("parameter ~link"), std::string::npos);
}

TEST(UrdfBody, RobotDescriptionNamesTheParameterThatHoldsTheXml) {
  std::ifstream file(TEST_URDF_DIR "/offset_link.urdf");
  const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  XmlRpcValue params;
  params["robot_description"] = std::string("/robot_description");
  params["link"] = std::string("base_link");
  const auto reader = [&xml](const std::string& name, std::string& value) {
    if (name != "/robot_description") return false;
    value = xml;
    return true;
  };
  EXPECT_EQ(parseConfig(params, reader).bodies[0].model.mass.mass(), 2.0);
  EXPECT_NE(errorOf(params).find("parameter ~robot_description = '/robot_description': must name a parameter"),
            std::string::npos);
  // collision: true takes the link's <collision>.
  params["collision"] = true;
  const NodeConfig config = parseConfig(params, reader);
  ASSERT_TRUE(config.bodies[0].collision.has_value());
  EXPECT_EQ(config.bodies[0].collision->type, rigid_body::ShapeType::kBox);
}
