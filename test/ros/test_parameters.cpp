// Parameter parsing and validation without a master: the private namespace as an XmlRpc struct.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

using rigid_body_ros::BodyConfig;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::ParameterError;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

using parameter_test::errorOf;
using parameter_test::list;

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
  EXPECT_EQ(config.max_tick_seconds, 0.2);
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
  // The mesh's own frame under the body frame: one name for both (or the world's) would make tf a loop.
  XmlRpcValue same = meshParams("/box.obj");
  same["body_frame"] = std::string("crate");
  same["mesh_frame"] = std::string("crate");
  EXPECT_NE(errorOf(same).find("parameter ~mesh_frame = 'crate': must differ from body_frame"), std::string::npos)
      << errorOf(same);
  same["mesh_frame"] = std::string("world");
  EXPECT_NE(errorOf(same).find("parameter ~mesh_frame = 'world': must differ"), std::string::npos) << errorOf(same);
  same["mesh_frame"] = std::string("crate_mesh");
  EXPECT_EQ(errorOf(same), "");
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

TEST(Parameters, AnOutputRateAboveTheTickRateOrNegativeIsRefused) {
  for (const char* key : {"tf_rate", "odom_rate", "state_rate"}) {
    for (const double bad : {150.0, -1.0, 1e-4}) {
      XmlRpcValue params;
      params["publish"][key] = bad;
      EXPECT_NE(errorOf(params).find(std::string("parameter ~publish/") + key + " = "), std::string::npos) << key;
      EXPECT_NE(errorOf(params).find("must be 0 (every tick) or a finite number in [0.001, rate = 100] [Hz]"),
                std::string::npos)
          << errorOf(params);
    }
    XmlRpcValue params;
    params["publish"][key] = 100.0;  // the tick rate itself is allowed
    EXPECT_EQ(errorOf(params), "") << key;
  }
}
