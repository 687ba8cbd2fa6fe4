// Each class of invalid parameter makes the real node binary exit non-zero at start-up with one line that
// names the parameter. The node is started the way a user starts it, with rosrun-style _name:=value.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <functional>
#include <string>

namespace {

struct Outcome {
  int exit_code = -1;
  std::string output;
};

// Runs the node with `arguments` (bounded by `timeout`, so a node that wrongly keeps running fails the test
// instead of hanging it) and returns its exit code and combined output.
// `signal` is what `timeout` sends (TERM, or INT as Ctrl-C); `while_running` is called once the node started.
Outcome runNode(const std::string& name, const std::string& arguments, int timeout = 20,
                const std::string& signal = "TERM", const std::function<void()>& while_running = [] {}) {
  const std::string command = "timeout -s " + signal + " " + std::to_string(timeout) + " " RIGID_BODY_NODE_PATH
                              " __name:=" + name + " " + arguments + " 2>&1";
  Outcome outcome;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  while_running();
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) outcome.output += buffer.data();
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

// Waits (bounded) until /use_sim_time is present on the master.
bool waitForSimTimeParameter() {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!ros::param::has("/use_sim_time")) {
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.01).sleep();
  }
  return true;
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
                      Case{"rate", "_rate:=0", "parameter ~rate = 0: must be a finite number in [0.001, 10000] [Hz]"},
                      Case{"dt", "_dt:=0.5", "parameter ~dt = 0.5: must be a finite number in (0, 1/rate = 0.01] [s]"},
                      Case{"size", "_size:='[0.4,0.2]'", "parameter ~size = '[0.4,0.2]': for a box, must be [x, y, z]"},
                      Case{"shape", "_shape:=cone", "parameter ~shape = 'cone'"},
                      Case{"inertia", "_inertia:='[1,1,5,0,0,0]'", "inertia violates the triangle inequality"},
                      Case{"orientation", "_initial/orientation:='[0,0,0,3]'", "parameter ~initial/orientation"},
                      Case{"damping", "_linear_damping:=-1", "parameter ~linear_damping = -1"},
                      Case{"mesh", "_shape:=mesh _mass:=1.0 _mesh:=/nonexistent/part.stl",
                           "parameter ~mesh = '/nonexistent/part.stl': cannot open mesh file"},
                      // Mass and size each valid, together an inertia that overflows, underflows or has no inverse.
                      Case{"box_inertia_overflow", "_mass:=1e300 _size:='[1e10,1,1]'", "parameter ~size = '[1e10,1,1]': with ~mass = 1e+300 gives no usable inertia"},
                      Case{"sphere_inertia_overflow", "_shape:=sphere _size:='[1e200]'", "parameter ~size = '[1e200]': with ~mass = 1 gives no usable inertia"},
                      Case{"inertia_underflow", "_mass:=1e-300 _size:='[1e-100,1e-100,1e-100]'", "parameter ~size"},
                      Case{"subnormal_mass", "_mass:=1e-320", "gives no usable inertia"},
                      Case{"cylinder_inertia_overflow", "_shape:=cylinder _mass:=1e308 _size:='[1e5,1e5]'", "parameter ~size"},
                      // Settings that would leave the node silent or stalled.
                      Case{"dt_tiny", "_dt:=1e-300", "parameter ~dt = 1e-300: must be >= 1e-6 [s]"},
                      Case{"rate_tiny", "_rate:=1e-300", "parameter ~rate = 1e-300: must be a finite number in [0.001, 10000] [Hz]"},
                      Case{"noise_delay", "_noise/delay:=1e9", "parameter ~noise/delay = 1000000000: must be a finite number in [0, 3600]"},
                      Case{"max_substeps_type", "_max_substeps:=1e9", "parameter ~max_substeps"},
                      Case{"request_bound", "_max_body_steps_per_request:=0", "parameter ~max_body_steps_per_request = 0"},
                      Case{"request_seconds", "_max_request_seconds:=0", "parameter ~max_request_seconds = 0: must be a finite number in (0, 3600]"},
                      Case{"tick_seconds", "_max_tick_seconds:=1e9", "parameter ~max_tick_seconds = 1000000000: must be a finite number in (0, 3600]"},
                      // Struct keys of the wrong type, and keys that mean nothing for the shape.
                      Case{"publish_type", "_publish:=5", "parameter ~publish = 5: must be a struct of"},
                      Case{"noise_type", "_noise:=loud", "parameter ~noise = 'loud': must be a struct of"},
                      Case{"initial_type", "_initial:='[1,2,3]'", "parameter ~initial = '[1,2,3]': must be a struct of"},
                      Case{"samples_on_a_box", "_samples:=0", "parameter ~samples = 0: is only for shape mesh"},
                      // Mesh files that are not what they say.
                      Case{"mesh_device", "_shape:=mesh _mass:=1.0 _mesh:=/tmp/rigid_body_sim_zero.stl",
                           "is not a regular file"},
                      Case{"mesh_fifo", "_shape:=mesh _mass:=1.0 _mesh:=/tmp/rigid_body_sim_fifo.stl",
                           "is not a regular file"},
                      Case{"mesh_too_large", "_shape:=mesh _mass:=1.0 _mesh:=" TEST_MESH_DIR "/sphere.stl _max_mesh_bytes:=1000",
                           "more than the limit of 1000"},
                      Case{"mesh_bad_index", "_shape:=mesh _mass:=1.0 _mesh:=/tmp/rigid_body_sim_bad_index.obj",
                           "names no vertex"},
                      // Contact: a material out of range stops the node like any other parameter.
                      Case{"restitution", "_collision/restitution:=1.5",
                           "parameter ~collision/restitution = 1.5: must be a number in [0, 1]"},
                      Case{"friction", "_collision/friction:=-0.1", "parameter ~collision/friction = -0.10000000000000001"},
                      Case{"contact_iterations", "_contact/iterations:=0", "parameter ~contact/iterations = 0"},
                      // A URDF link that cannot be a body.
                      Case{"urdf_no_link", "_urdf:=" TEST_URDF_DIR "/offset_link.urdf _link:=elbow",
                           "parameter ~link = 'elbow': names no link of the robot description"},
                      Case{"urdf_no_inertial", "_urdf:=" TEST_URDF_DIR "/offset_link.urdf _link:=sensor",
                           "parameter ~link = 'sensor': has no <inertial>"},
                      // A default taken from another parameter and refused: the body frame from a link named "/arm".
                      Case{"urdf_link_not_a_frame", "_urdf:=" TEST_URDF_DIR "/offset_link.urdf _link:=/arm",
                           "parameter ~body_frame (not set, so '/arm'): must be a non-empty tf2 frame id"},
                      Case{"samples_huge", "_shape:=mesh _mass:=1.0 _mesh:=" TEST_MESH_DIR "/box.obj _inertia_method:=sampling _samples:=2147483647",
                           "parameter ~samples = 2147483647: must be an integer in [1, 10000000]"}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(GoodParameters, TheSameBinaryRunsWithValidOnes) {
  // The control case: with valid parameters the node is still running when `timeout` stops it (exit 124).
  const Outcome outcome = runNode("good", "_mass:=2.0 _rate:=20", 3);
  EXPECT_EQ(outcome.exit_code, 124) << outcome.output;
  EXPECT_EQ(outcome.output.find("FATAL"), std::string::npos) << outcome.output;
}

TEST(SimulatedTime, PublishClockIsRefusedUnderUseSimTime) {
  // Under /use_sim_time the node follows another /clock: publishing its own would feed it back to itself.
  ros::param::set("/use_sim_time", true);
  const Outcome outcome = runNode("clocked", "_publish/clock:=true");
  ros::param::del("/use_sim_time");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find("parameter ~publish/clock = true"), std::string::npos) << outcome.output;
}

TEST(SimulatedTime, ALockstepNodeDeletesTheUseSimTimeItSetWhenItExits) {
  // Ctrl-C (INT) and kill (TERM): both end the loop, and the parameter the node set is gone afterwards, so
  // that a later node on this master is on wall time again.
  for (const char* signal : {"INT", "TERM"}) {
    ros::param::del("/use_sim_time");
    bool set_while_running = false;
    const Outcome outcome = runNode(std::string("lockstep_") + signal, "_lockstep:=true _real_time_factor:=1.0", 3,
                                    signal, [&] { set_while_running = waitForSimTimeParameter(); });
    EXPECT_TRUE(set_while_running) << signal;
    EXPECT_EQ(outcome.exit_code, 124) << signal << ": " << outcome.output;  // stopped by the signal, not failed
    EXPECT_FALSE(ros::param::has("/use_sim_time")) << signal << ": " << outcome.output;
  }
}

TEST(SimulatedTime, ALockstepNodeLeavesAUseSimTimeSetBySomeoneElse) {
  ros::param::set("/use_sim_time", true);
  const Outcome outcome = runNode("lockstep_kept", "_lockstep:=true", 2, "INT");
  bool value = false;
  EXPECT_TRUE(ros::param::get("/use_sim_time", value)) << outcome.output;
  EXPECT_TRUE(value);
  ros::param::del("/use_sim_time");
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // The special files of the mesh cases: a device behind a .stl name, a FIFO (opening it would block for
  // ever), an OBJ whose face names vertex 0.
  std::remove("/tmp/rigid_body_sim_zero.stl");
  std::remove("/tmp/rigid_body_sim_fifo.stl");
  if (symlink("/dev/zero", "/tmp/rigid_body_sim_zero.stl") != 0 || mkfifo("/tmp/rigid_body_sim_fifo.stl", 0600) != 0) {
    std::perror("cannot make the special mesh files");
    return 1;
  }
  std::FILE* obj = std::fopen("/tmp/rigid_body_sim_bad_index.obj", "w");
  std::fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 0 1 2\n", obj);
  std::fclose(obj);
  ros::init(argc, argv, "bad_parameters_test");
  return RUN_ALL_TESTS();
}
