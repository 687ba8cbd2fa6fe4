// Each class of invalid parameter makes the real node binary exit non-zero at start-up with one line that
// names the parameter. The node is started the way a user starts it, with rosrun-style _name:=value.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct Outcome {
  int exit_code = -1;
  std::string output;
};

// Runs the node with `arguments` (bounded by `timeout`, so a node that wrongly keeps running fails the test
// instead of hanging it) and returns its exit code and combined output.
Outcome runNode(const std::string& name, const std::string& arguments, int timeout = 20) {
  const std::string command = "timeout " + std::to_string(timeout) + " " RIGID_BODY_NODE_PATH " __name:=" + name + " " +
                              arguments + " 2>&1";
  Outcome outcome;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) outcome.output += buffer.data();
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

struct Case {
  const char* name;
  const char* arguments;
  const char* message;  // a part of the one-line message
};

class BadParameter : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(BadParameter, StopsTheNodeWithAMessageNamingIt) {
  const Case& c = GetParam();
  const Outcome outcome = runNode(std::string("bad_") + c.name, c.arguments);
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;  // 2: invalid parameter (124 would be the timeout)
  EXPECT_NE(outcome.output.find(c.message), std::string::npos) << outcome.output;
  EXPECT_NE(outcome.output.find("FATAL"), std::string::npos) << outcome.output;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadParameter,
    ::testing::Values(Case{"mass", "_mass:=-1", "parameter ~mass = -1: must be a finite number > 0 [kg]"},
                      Case{"mass_type", "_mass:=heavy", "parameter ~mass = 'heavy': must be a finite number > 0"},
                      Case{"integrator", "_integrator:=rk5", "parameter ~integrator = 'rk5': must be one of:"},
                      Case{"rate", "_rate:=0", "parameter ~rate = 0: must be a finite number in (0, 10000] [Hz]"},
                      Case{"dt", "_dt:=0.5", "parameter ~dt = 0.5: must be a finite number in (0, 1/rate = 0.01] [s]"},
                      Case{"size", "_size:='[0.4,0.2]'", "parameter ~size = '[0.4,0.2]': for a box, must be [x, y, z]"},
                      Case{"shape", "_shape:=cone", "parameter ~shape = 'cone'"},
                      Case{"inertia", "_inertia:='[1,1,5,0,0,0]'", "inertia violates the triangle inequality"},
                      Case{"orientation", "_initial/orientation:='[0,0,0,3]'", "parameter ~initial/orientation"},
                      Case{"damping", "_linear_damping:=-1", "parameter ~linear_damping = -1"},
                      Case{"mesh", "_shape:=mesh _mass:=1.0 _mesh:=/nonexistent/part.stl",
                           "parameter ~mesh = '/nonexistent/part.stl': cannot open mesh file"}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(GoodParameters, TheSameBinaryRunsWithValidOnes) {
  // The control case: with valid parameters the node is still running when `timeout` stops it (exit 124).
  const Outcome outcome = runNode("good", "_mass:=2.0 _rate:=20", 3);
  EXPECT_EQ(outcome.exit_code, 124) << outcome.output;
  EXPECT_EQ(outcome.output.find("FATAL"), std::string::npos) << outcome.output;
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "bad_parameters_test");
  return RUN_ALL_TESTS();
}
