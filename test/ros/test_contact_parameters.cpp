// The contact parameters without a master: collision, environment and the solver's keys.
#include <gtest/gtest.h>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

using parameter_test::errorOf;
using parameter_test::list;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue shapeItem(const std::string& type) {
  XmlRpcValue item;
  item["type"] = type;
  return item;
}

// Parameters whose environment is the one item.
XmlRpcValue environmentOf(const XmlRpcValue& item) {
  XmlRpcValue params;
  params["environment"][0] = item;
  return params;
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
    cases.push_back({environmentOf(shapeItem("cone")), "parameter ~environment[0]/type = 'cone': must be one of: plane, box"});
  }
  {
    XmlRpcValue plane = shapeItem("plane");
    plane["normal"] = list({0.0, 0.0, 0.0});
    cases.push_back({environmentOf(plane), "parameter ~environment[0]/normal = [0, 0, 0]: must be 3 finite numbers, not all 0"});
  }
  {
    XmlRpcValue plane = shapeItem("plane");
    plane["size"] = list({1.0, 1.0, 1.0});
    cases.push_back({environmentOf(plane), "parameter ~environment[0]/size = [1, 1, 1]: is not a key of a plane"});
  }
  {
    cases.push_back({environmentOf(shapeItem("box")), "parameter ~environment[0]/size"});
  }
  {
    XmlRpcValue ball = shapeItem("sphere");
    ball["size"] = list({0.5});
    ball["restitution"] = -0.5;
    cases.push_back({environmentOf(ball), "parameter ~environment[0]/restitution = -0.5"});
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
    XmlRpcValue wall = shapeItem("box");
    wall["size"] = list({1.0, 1.0, 1.0});
    wall["pose"]["position"] = list({1e300, 0.0, 0.0});
    cases.push_back({environmentOf(wall), "parameter ~environment[0]/pose/position"});
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

// Contacts name both sides: an empty name names nothing, and a body and a shape of one name are the same
// to a reader of contacts. Refused in the flat form (body_frame) and in a list (name and body_frame).
TEST(ContactParameters, EnvironmentNamesAreNonEmptyAndNoBodysName) {
  XmlRpcValue empty = shapeItem("plane");
  empty["name"] = std::string("");
  EXPECT_NE(errorOf(environmentOf(empty)).find("parameter ~environment[0]/name = '': must be a non-empty name"),
            std::string::npos)
      << errorOf(environmentOf(empty));
  XmlRpcValue flat = environmentOf(shapeItem("plane"));
  flat["body_frame"] = std::string("plane0");  // the plane's default name
  EXPECT_NE(errorOf(flat).find("parameter ~environment[0]/name = 'plane0': is also the name (or body_frame) of a body"),
            std::string::npos)
      << errorOf(flat);
  XmlRpcValue listed = environmentOf(shapeItem("plane"));
  listed["environment"][0]["name"] = std::string("crate");
  listed["bodies"][0]["name"] = std::string("crate");
  listed["bodies"][1]["name"] = std::string("other");
  listed["bodies"][1]["initial"]["position"] = list({2.0, 0.0, 0.0});
  EXPECT_NE(errorOf(listed).find("parameter ~environment[0]/name = 'crate': is also the name"), std::string::npos)
      << errorOf(listed);
  listed["bodies"][0]["name"] = std::string("box");
  listed["bodies"][0]["body_frame"] = std::string("crate");
  EXPECT_NE(errorOf(listed).find("parameter ~environment[0]/name = 'crate': is also the name"), std::string::npos)
      << errorOf(listed);
  listed["environment"][0]["name"] = std::string("floor");
  EXPECT_EQ(errorOf(listed), "");
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
