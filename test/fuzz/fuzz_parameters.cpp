// Seeded fuzzing of the start-up parameters (scripts/fuzz_inputs.sh; not a test of the suite): random private
// namespaces of the node's own keys and sections, values of every XmlRpc type from the everyday to NaN,
// 2^31 − 1 and odd strings, nested up to four deep; a third of them take their body from a robot description
// (~robot_description), the test URDFs damaged (tokens such as nan, 1e308, -1, "<link", cut short). Each is
// parsed as the node parses its namespace; what parses becomes a World that runs 20 updates. Must not happen (exit 1): an exception other than
// ParameterError out of parseConfig, any exception out of a World built from an accepted configuration, a
// non-finite state. A crash is a finding too (run it under AddressSanitizer, as the script does).
//
// Usage: fuzz_parameters ITERATIONS SEED
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <random>
#include <string>
#include <vector>

#include <console_bridge/console.h>

#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"
#include "rigid_body_sim/world.hpp"

namespace {

using rigid_body_ros::NodeConfig;
using XmlRpc::XmlRpcValue;

const std::vector<std::string> kKeys = {
    "rate", "marker_rate", "dt", "integrator", "world_frame", "gravity", "wrench_timeout", "max_force",
    "max_torque", "max_energy_growth", "max_substeps", "max_body_steps_per_tick", "max_body_steps_per_request",
    "threads", "lockstep", "real_time_factor", "start_paused", "mass", "inertia", "shape", "size", "mesh",
    "density", "inertia_method", "samples", "seed", "principal_axes", "scale", "linear_damping",
    "angular_damping", "body_frame", "name", "wrench_input", "abs_tolerance", "rel_tolerance", "mesh_frame",
    "max_mesh_bytes", "urdf", "link", "friction", "restitution", "offset", "normal", "type", "position",
    "orientation", "linear_velocity", "angular_velocity", "iterations", "per_body_topics", "tf", "odom"};
const std::vector<std::string> kSections = {"initial", "publish", "noise", "contact", "collision", "pose",
                                            "bodies", "environment"};
const std::vector<std::string> kStrings = {
    "", "rk4", "explicit_euler", "semi_implicit_euler", "dopri5", "implicit_midpoint", "box", "sphere",
    "cylinder", "capsule", "mesh", "plane", "exact", "sampling", "bounding_box", "a b", "/x", "world",
    "base_link", "true", "1e9", "nan", "[1, 2, 3]", "[nan, 0, 0]", "[1e308, 1e308, 1e308]", "\xff\xfe",
    "package://nope/x.stl", "/nonexistent/x.obj", "/dev/zero", TEST_MESH_DIR "/box.obj",
    TEST_MESH_DIR "/l_bracket.obj", TEST_MESH_DIR "/open_box.obj", TEST_MESH_DIR};

const std::vector<std::string> kUrdfs = {TEST_URDF_DIR "/offset_link.urdf", TEST_URDF_DIR "/bad_links.urdf"};
const std::vector<std::string> kLinks = {"base_link", "sensor", "impossible", "", "nope"};
const std::vector<std::string> kUrdfTokens = {"nan", "inf", "-1", "0", "1e308", "-1e308", "1e-320", " ", "\"",
                                              "<", ">", "/>", "<link name=\"x\"/>", "<inertial>", "</inertial>",
                                              "<mesh filename=\"/dev/zero\"/>", "e", "-"};

std::string slurp(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

class Fuzzer {
 public:
  explicit Fuzzer(std::uint64_t seed) : rng_(seed) {}

  /// A robot description: a test URDF with a few damages (tokens inserted, bytes removed, cut short).
  std::string urdf() {
    std::string xml = slurp(kUrdfs[pick(kUrdfs.size())]);
    const int edits = pick(6);
    for (int e = 0; e < edits && !xml.empty(); ++e) {
      const std::size_t at = rng_() % xml.size();
      switch (pick(3)) {
        case 0:
          xml.insert(at, kUrdfTokens[pick(kUrdfTokens.size())]);
          break;
        case 1:
          xml.erase(at, 1 + pick(8));
          break;
        default:
          if (pick(4) == 0) xml.resize(at);
      }
    }
    return xml;
  }

  /// Whether this set names a robot description, and its link.
  bool robotDescription(XmlRpcValue& params) {
    if (pick(3) != 0) return false;
    params["robot_description"] = std::string("robot_description");
    params["link"] = kLinks[pick(kLinks.size())];
    return true;
  }

  XmlRpcValue parameters() {
    XmlRpcValue params;
    const int keys = 1 + pick(4);
    for (int i = 0; i < keys; ++i) {
      if (pick(3) == 0) {
        const std::string& section = kSections[pick(kSections.size())];
        if (section == "bodies" || section == "environment") {
          XmlRpcValue items;
          const int n = pick(3);
          items.setSize(n);
          for (int j = 0; j < n; ++j) items[j] = pick(4) ? structOf(1) : value(1);
          params[section] = items;
        } else {
          params[section] = structOf(1);
        }
      } else {
        params[kKeys[pick(kKeys.size())]] = value(0);
      }
    }
    return params;
  }

 private:
  int pick(std::size_t n) { return static_cast<int>(rng_() % n); }

  XmlRpcValue scalar() {
    static const int kInts[] = {0, 1, -1, 2, 3, 100, 2147483647, -2147483647 - 1, 1000000, 7};
    static const double kDoubles[] = {0.0, -0.0, 1.0, -1.0, 1e-300, 1e300, 1e308, -1e308,
                                      std::numeric_limits<double>::quiet_NaN(), HUGE_VAL, -HUGE_VAL, 0.001, 0.5,
                                      2.0, 1e-9, 5e-324, 100.0, 9.81, -9.81, 1e6};
    switch (pick(8)) {
      case 0:
        return XmlRpcValue(pick(2) == 1);
      case 1:
        return XmlRpcValue(kInts[pick(10)]);
      case 2:
        return XmlRpcValue(kDoubles[pick(20)]);
      default:
        return XmlRpcValue(kStrings[pick(kStrings.size())]);
    }
  }

  XmlRpcValue listOf(int depth) {
    XmlRpcValue list;
    const int n = pick(6);
    list.setSize(n);
    for (int i = 0; i < n; ++i) list[i] = pick(5) == 0 ? value(depth + 1) : scalar();
    return list;
  }

  XmlRpcValue structOf(int depth) {
    XmlRpcValue s;
    const int n = 1 + pick(6);
    for (int i = 0; i < n; ++i) s[kKeys[pick(kKeys.size())]] = value(depth + 1);
    return s;
  }

  XmlRpcValue value(int depth) {
    const int r = pick(10);
    if (depth > 3 || r < 5) return scalar();
    return r < 8 ? listOf(depth) : structOf(depth);
  }

  std::mt19937_64 rng_;
};

bool finiteState(const rigid_body::State& s) {
  return s.p_WB.allFinite() && s.q_WB.coeffs().allFinite() && s.P_W.allFinite() && s.L_W.allFinite();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_parameters ITERATIONS SEED\n");
    return 2;
  }
  const long iterations = std::atol(argv[1]);
  // urdfdom says what it makes of each damaged description (through console_bridge): not the findings.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  Fuzzer fuzzer(std::strtoull(argv[2], nullptr, 10));
  long accepted = 0, refused = 0, findings = 0;
  for (long i = 0; i < iterations; ++i) {
    XmlRpcValue params = fuzzer.parameters();
    const std::string xml = fuzzer.robotDescription(params) ? fuzzer.urdf() : std::string();
    const rigid_body_ros::ParameterReader reader = [&xml](const std::string& name, std::string& value) {
      if (name != "robot_description" || xml.empty()) return false;
      value = xml;
      return true;
    };
    NodeConfig config;
    try {
      config = rigid_body_ros::parseConfig(params, reader);
    } catch (const rigid_body_ros::ParameterError&) {
      ++refused;
      continue;
    } catch (const std::exception& error) {
      ++findings;
      std::printf("FINDING: parseConfig threw a non-ParameterError: %s\n  %s\n", error.what(), params.toXml().c_str());
      continue;
    }
    ++accepted;
    try {
      std::vector<rigid_body::BodyDefinition> bodies;
      for (const rigid_body_ros::BodyConfig& body : config.bodies) bodies.push_back({body.model, body.initial, body.wrench_input});
      rigid_body::World world(bodies, config.integrator, config.integrator_settings, rigid_body_ros::worldSettings(config),
                              rigid_body::StepAssembly::kLeaveOut, config.contactSetup());
      world.start(0);
      for (int k = 1; k <= 20; ++k) world.update(k * rigid_body::Nanoseconds(10000000));
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        if (!finiteState(world.scene().state(b))) {
          ++findings;
          std::printf("FINDING: non-finite state of body %zu\n  %s\n", b, params.toXml().c_str());
        }
      }
    } catch (const std::exception& error) {
      ++findings;
      std::printf("FINDING: an accepted configuration's World threw: %s\n  %s\n", error.what(), params.toXml().c_str());
    }
  }
  std::printf("fuzz_parameters: %ld sets, %ld accepted and run, %ld refused, %ld findings\n", iterations, accepted,
              refused, findings);
  return findings == 0 ? 0 : 1;
}
