// A body from a URDF link, read without a master.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/urdf_body.hpp"

using parameter_test::errorOf;
using parameter_test::list;
using rigid_body_ros::BodyConfig;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

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
  XmlRpcValue params = urdfBody("base_link");
  params["collision"] = true;  // the link's <collision> is read for a body that collides
  const NodeConfig config = parseConfig(params);
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

namespace {

// A URDF with one link whose <collision> and <visual> are the mesh `mesh` (as written in the file).
std::string meshLinkUrdf(const std::string& mesh) {
  return "<robot name='meshed'><link name='crate'><inertial><mass value='1.0'/>"
         "<inertia ixx='0.1' ixy='0' ixz='0' iyy='0.1' iyz='0' izz='0.1'/></inertial>"
         "<collision><geometry><mesh filename='" + mesh + "'/></geometry></collision>"
         "<visual><geometry><mesh filename='" + mesh + "'/></geometry></visual></link></robot>";
}

// A fresh folder holding robot.urdf (naming meshes/box.obj relatively) and meshes/box.obj.
std::string writeRobotFolder(bool with_mesh) {
  char name[] = "/tmp/rigid_body_sim_urdf_XXXXXX";
  const std::string folder = mkdtemp(name);
  std::filesystem::create_directory(folder + "/meshes");
  if (with_mesh) std::filesystem::copy_file(TEST_MESH_DIR "/box.obj", folder + "/meshes/box.obj");
  std::ofstream(folder + "/robot.urdf") << meshLinkUrdf("meshes/box.obj");
  return folder;
}

XmlRpcValue fromDescription(bool collision) {
  XmlRpcValue params;
  params["robot_description"] = std::string("/robot_description");
  params["link"] = std::string("crate");
  params["collision"] = collision;
  return params;
}

constexpr std::size_t kHugePadding = rigid_body_ros::kMaxUrdfBytes;  // spaces: still a parseable URDF

std::string errorWith(const XmlRpcValue& params, const std::string& xml) {
  try {
    parseConfig(params, [&xml](const std::string&, std::string& value) {
      value = xml;
      return true;
    });
  } catch (const rigid_body_ros::ParameterError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

// Relative mesh paths are the URDF file's folder's (as rviz and Gazebo read them): resolved against the
// working directory, the test (run from /) would find no mesh.
TEST(UrdfBody, RelativeMeshPathsResolveAgainstTheUrdfsFolderNotTheWorkingDirectory) {
  const std::string folder = writeRobotFolder(true);
  const std::filesystem::path working = std::filesystem::current_path();
  std::filesystem::current_path("/");
  XmlRpcValue params;
  params["urdf"] = folder + "/robot.urdf";
  params["link"] = std::string("crate");
  params["collision"] = true;
  NodeConfig config;
  EXPECT_NO_THROW(config = parseConfig(params));
  std::filesystem::current_path(working);
  ASSERT_EQ(config.bodies.size(), 1u);
  ASSERT_TRUE(config.bodies[0].collision.has_value());
  EXPECT_EQ(config.bodies[0].collision->type, rigid_body::ShapeType::kMesh);
  EXPECT_EQ(config.bodies[0].collision->mesh.triangles.size(), 12u);  // box.obj: 6 faces of 2 triangles
  EXPECT_EQ(config.bodies[0].visual_mesh, "file://" + folder + "/meshes/box.obj");  // a URI rviz can open
  std::filesystem::remove_all(folder);
}

// A collision mesh is opened only for a body that collides: a missing one stops only that body.
TEST(UrdfBody, ACollisionMeshIsOpenedOnlyWhenTheBodyCollides) {
  const std::string folder = writeRobotFolder(false);
  XmlRpcValue params;
  params["urdf"] = folder + "/robot.urdf";
  params["link"] = std::string("crate");
  params["collision"] = false;
  EXPECT_EQ(errorOf(params), "");
  params["collision"] = true;
  const std::string error = errorOf(params);
  EXPECT_NE(error.find("parameter ~link = 'crate': its collision mesh 'meshes/box.obj'"), std::string::npos) << error;
  std::filesystem::remove_all(folder);
}

// Messages name the parameter the description came from: ~robot_description's text is not "~urdf".
TEST(UrdfBody, ARobotDescriptionIsNamedInItsOwnMessagesAndBoundedBeforeItIsParsed) {
  EXPECT_NE(errorWith(fromDescription(false), "<robot").find(
                "parameter ~robot_description = '/robot_description': does not parse as a URDF"),
            std::string::npos);
  // More than 16 MiB is refused unparsed: the text here would parse, so a parser that ran would name no size.
  std::string huge = meshLinkUrdf("package://rigid_body_sim/test/meshes/box.obj");
  huge.insert(huge.find("<link"), kHugePadding, ' ');
  const std::string error = errorWith(fromDescription(false), huge);
  EXPECT_NE(error.find("parameter ~robot_description = '/robot_description': holds " + std::to_string(huge.size()) +
                       " bytes, more than the 16777216"),
            std::string::npos)
      << error;
  // At the bound it is read.
  std::string at_bound = meshLinkUrdf("/nonexistent/box.obj");
  at_bound.insert(at_bound.find("<link"), rigid_body_ros::kMaxUrdfBytes - at_bound.size(), ' ');
  EXPECT_EQ(errorWith(fromDescription(false), at_bound), "");
  // A relative mesh path has no folder to resolve against in a parameter.
  EXPECT_NE(errorWith(fromDescription(true), meshLinkUrdf("meshes/box.obj"))
                .find("its mesh 'meshes/box.obj' is a relative path, and a description from ~robot_description has no folder"),
            std::string::npos);
}

TEST(UrdfBody, AUrdfFileIsBoundedAndAMissingPackageIsNotAMeshError) {
  char name[] = "/tmp/rigid_body_sim_huge_XXXXXX.urdf";
  const int fd = mkstemps(name, 5);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, static_cast<off_t>(rigid_body_ros::kMaxUrdfBytes) + 1), 0);  // sparse: costs no disk
  close(fd);
  XmlRpcValue params = urdfBody("base_link");
  params["urdf"] = std::string(name);
  EXPECT_NE(errorOf(params).find("parameter ~urdf = '" + std::string(name) + "': is not a readable file of at most 16777216"),
            std::string::npos)
      << errorOf(params);
  std::remove(name);
  params["urdf"] = std::string("package://no_such_package_here/robot.urdf");
  const std::string error = errorOf(params);
  EXPECT_NE(error.find("parameter ~urdf = 'package://no_such_package_here/robot.urdf': names a package that is not found"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find("~mesh"), std::string::npos) << error;
}
