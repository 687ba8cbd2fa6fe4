// A spawn request's text into a body (body_spawner.hpp): YAML read as rosparam would, the item parsed as at
// start-up, and the refusals that only a running scene can have (a name or frame taken).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "rigid_body_sim/ros/body_spawner.hpp"

using rigid_body_ros::BodyConfig;
using rigid_body_ros::NodeConfig;
using rigid_body_ros::ParameterError;
using XmlRpc::XmlRpcValue;

namespace {

// Two bodies (box, ball) over a floor, under gravity.
NodeConfig scene() {
  XmlRpcValue params;
  params["gravity"].setSize(3);
  params["gravity"][0] = 0.0;
  params["gravity"][1] = 0.0;
  params["gravity"][2] = -9.81;
  params["environment"][0]["type"] = std::string("plane");
  params["environment"][0]["name"] = std::string("floor");
  params["bodies"][0]["name"] = std::string("box");
  params["bodies"][1]["name"] = std::string("ball");
  params["bodies"][1]["shape"] = std::string("sphere");
  params["bodies"][1]["size"].setSize(1);
  params["bodies"][1]["size"][0] = 0.1;
  params["bodies"][1]["body_frame"] = std::string("ball_frame");
  return rigid_body_ros::parseConfig(params);
}

std::string refusal(const std::string& yaml) {
  try {
    rigid_body_ros::parseSpawnedBody(yaml, scene(), {});
  } catch (const ParameterError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST(BodySpawner, ReadsYamlScalarsAsRosparamDoes) {
  const XmlRpcValue value =
      rigid_body_ros::yamlToXmlRpc("{a: 1, b: 2.5, c: true, d: text, e: '3', f: [1, 2.0], g: {h: -4}, i: 1e3}");
  ASSERT_EQ(value.getType(), XmlRpcValue::TypeStruct);
  XmlRpcValue v = value;
  EXPECT_EQ(v["a"].getType(), XmlRpcValue::TypeInt);
  EXPECT_EQ(static_cast<int>(v["a"]), 1);
  EXPECT_EQ(v["b"].getType(), XmlRpcValue::TypeDouble);
  EXPECT_EQ(v["c"].getType(), XmlRpcValue::TypeBoolean);
  EXPECT_EQ(v["d"].getType(), XmlRpcValue::TypeString);
  EXPECT_EQ(v["e"].getType(), XmlRpcValue::TypeString);  // quoted: text
  EXPECT_EQ(v["f"].getType(), XmlRpcValue::TypeArray);
  EXPECT_EQ(v["f"][1].getType(), XmlRpcValue::TypeDouble);
  EXPECT_EQ(static_cast<int>(v["g"]["h"]), -4);
  EXPECT_DOUBLE_EQ(static_cast<double>(v["i"]), 1000.0);
  // An integer beyond 32 bits is a double (XmlRpc's int is 32 bits), not a wrapped int.
  XmlRpcValue big = rigid_body_ros::yamlToXmlRpc("5000000000");
  EXPECT_EQ(big.getType(), XmlRpcValue::TypeDouble);
}

TEST(BodySpawner, RefusesTextThatIsNotYamlTooLongOrTooDeep) {
  EXPECT_THROW(rigid_body_ros::yamlToXmlRpc("{name: [1, 2"), ParameterError);
  EXPECT_THROW(rigid_body_ros::yamlToXmlRpc(std::string(rigid_body_ros::kMaxSpawnYamlBytes + 1, 'a')), ParameterError);
  EXPECT_THROW(rigid_body_ros::yamlToXmlRpc(std::string(100, '[') + std::string(100, ']')), ParameterError);
  EXPECT_THROW(rigid_body_ros::yamlToXmlRpc("{[1, 2]: 3}"), ParameterError);
  EXPECT_NE(refusal("[1, 2]").find("must be a YAML map"), std::string::npos) << refusal("[1, 2]");
}

TEST(BodySpawner, ParsesABodyAsAnItemOfBodiesUnderTheScenesGravity) {
  const BodyConfig body = rigid_body_ros::parseSpawnedBody(
      "{name: crate, shape: box, size: [0.2, 0.3, 0.4], mass: 2, collision: true, "
      "initial: {position: [1, 2, 3], linear_velocity: [0, 0, 1]}}",
      scene(), {});
  EXPECT_EQ(body.name, "crate");
  EXPECT_EQ(body.body_frame, "crate");  // an item's frame defaults to its name
  EXPECT_DOUBLE_EQ(body.model.mass.mass(), 2.0);
  EXPECT_DOUBLE_EQ(body.model.forces.gravity_W.z(), -9.81);
  EXPECT_EQ(body.initial.p_WB, Eigen::Vector3d(1, 2, 3));
  EXPECT_DOUBLE_EQ(body.initial.P_W.z(), 2.0);  // P = M v
  ASSERT_TRUE(body.collision.has_value());
  EXPECT_EQ(body.collision->name, "crate");
}

TEST(BodySpawner, ABadKeyOrValueIsRefusedNamingTheKeyAndTheValue) {
  const std::string mass = refusal("{name: crate, mass: -1}");
  EXPECT_NE(mass.find("spawn: key mass = -1"), std::string::npos) << mass;
  const std::string typo = refusal("{name: crate, mas: 1}");
  EXPECT_NE(typo.find("spawn: key mas"), std::string::npos) << typo;
  const std::string nested = refusal("{name: crate, initial: {postion: [0, 0, 1]}}");
  EXPECT_NE(nested.find("initial/postion"), std::string::npos) << nested;
  const std::string no_name = refusal("{mass: 1}");
  EXPECT_NE(no_name.find("name"), std::string::npos) << no_name;
  const std::string bad_name = refusal("{name: 'two words'}");
  EXPECT_NE(bad_name.find("two words"), std::string::npos) << bad_name;
}

TEST(BodySpawner, ANameOrFrameTakenByABodyOrTheEnvironmentIsRefused) {
  EXPECT_NE(refusal("{name: box}").find("a body of that name"), std::string::npos) << refusal("{name: box}");
  // Its frame would be another body's frame (tf gives a frame one parent).
  const std::string frame = refusal("{name: crate, body_frame: ball_frame}");
  EXPECT_NE(frame.find("ball_frame"), std::string::npos) << frame;
  // A name that is another body's frame would make two frames of one name.
  EXPECT_NE(refusal("{name: ball_frame}").find("ball_frame"), std::string::npos);
  EXPECT_NE(refusal("{name: floor}").find("environment shape"), std::string::npos) << refusal("{name: floor}");
  EXPECT_NE(refusal("{name: crate, body_frame: world}").find("world"), std::string::npos);
  EXPECT_EQ(refusal("{name: crate}"), "");
}

TEST(BodySpawner, FindsABodyByNameOrTheFlatBodyByItsFrame) {
  const NodeConfig two = scene();
  EXPECT_EQ(rigid_body_ros::findBody(two, "ball"), 1u);
  EXPECT_EQ(rigid_body_ros::findBody(two, "ball_frame"), 2u);  // a named body goes by its name only
  EXPECT_EQ(rigid_body_ros::findBody(two, "nothing"), 2u);
  const NodeConfig flat = rigid_body_ros::parseConfig(XmlRpcValue());
  EXPECT_EQ(rigid_body_ros::findBody(flat, "base_link"), 0u);
  EXPECT_EQ(rigid_body_ros::findBody(flat, ""), 1u);  // no name names no body
}

// A link of a robot description, by file or by parameter, is the body the same keys make at start-up.
TEST(BodySpawner, ALinkOfARobotDescriptionIsTheBodyStartUpMakesOfIt) {
  XmlRpcValue params;
  params["urdf"] = std::string(TEST_URDF_DIR "/offset_link.urdf");
  params["link"] = std::string("base_link");
  const BodyConfig at_start = rigid_body_ros::parseConfig(params).bodies[0];
  const std::string urdf_text = [] {
    std::ifstream file(TEST_URDF_DIR "/offset_link.urdf");
    return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }();
  const rigid_body_ros::ParameterReader reader = [&](const std::string& name, std::string& value) {
    if (name != "/robot_description") return false;
    value = urdf_text;
    return true;
  };
  for (const std::string& yaml : {"{name: arm, urdf: '" + std::string(TEST_URDF_DIR) + "/offset_link.urdf', link: base_link}",
                                 std::string("{name: arm, robot_description: /robot_description, link: base_link}")}) {
    const BodyConfig spawned = rigid_body_ros::parseSpawnedBody(yaml, scene(), reader);
    EXPECT_EQ(spawned.name, "arm") << yaml;
    EXPECT_EQ(spawned.body_frame, "base_link") << yaml;  // the link's frame, as at start-up
    EXPECT_EQ(spawned.model.mass.mass(), at_start.model.mass.mass()) << yaml;
    EXPECT_EQ(spawned.model.mass.inertia(), at_start.model.mass.inertia()) << yaml;
    EXPECT_TRUE(spawned.X_BP.isApprox(at_start.X_BP, 0.0)) << yaml;
  }
  EXPECT_NE(refusal("{name: arm, robot_description: /nothing, link: base_link}"), "");
}
