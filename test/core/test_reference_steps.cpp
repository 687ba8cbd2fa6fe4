// Every lane kernel (explicit Euler, rk4, semi-implicit Euler: IntegratorInfo::lane_kernel) against the
// plain scalar version of its method that its registry row names (src/integrators/reference_steps.hpp):
// the kernels arrange the arithmetic for speed (R from an unnormalised q, ω in body axes, the turns'
// product without divisions), so they must agree with the reference to rounding, not bit for bit. The
// kernels' own bit-for-bit twins (a body alone, in a batch, in wide instructions) are test_scene's.
// Value-parameterised over every method: a new method with a lane kernel is tested by its row.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "rigid_body_sim/step_terms.hpp"

using namespace rigid_body;

namespace {

class LaneKernel : public ::testing::TestWithParam<IntegratorType> {};

struct Case {
  std::string name;
  MassProperties mass;
  Eigen::Vector3d omega_B;  // initial angular velocity in body axes [rad/s]
};

Eigen::Matrix3d tilted(const Eigen::Vector3d& moments) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
  return R * moments.asDiagonal() * R.transpose();
}

// Each rotation branch of every method: principal axes tilted or not, three distinct moments, a symmetric
// top, a sphere. The fast spins (beyond semi-implicit Euler's series range at 10 ms, so its exact turns
// run) are given to bodies whose free motion is stable (a top, a sphere, the largest moment of an
// asymmetric body): near an unstable axis rounding differences grow exponentially, and no two correct
// arrangements would agree.
std::vector<Case> cases() {
  return {
      {"tilted_asymmetric", MassProperties::fromInertia(2.0, tilted({0.03, 0.05, 0.07})), {0.7, -1.3, 2.1}},
      {"principal_asymmetric", MassProperties::fromInertia(1.0, Eigen::Vector3d(0.1, 0.2, 0.25).asDiagonal()),
       {0.4, 0.9, -1.7}},
      {"asymmetric_fast_major_axis", MassProperties::fromInertia(1.0, Eigen::Vector3d(0.1, 0.2, 0.25).asDiagonal()),
       {0.05, -0.03, 60.0}},
      {"tilted_top", MassProperties::fromInertia(1.0, tilted({0.1, 0.1, 0.15})), {1.1, -0.6, 45.0}},
      {"cylinder", MassProperties::cylinder(3.0, 0.1, 0.5), {2.0, 0.5, 70.0}},
      {"sphere", MassProperties::sphere(1.5, 0.2), {-30.0, 20.0, 50.0}},
  };
}

State startOf(const MassProperties& mass, const Eigen::Vector3d& omega_B) {
  State s;
  s.p_WB = Eigen::Vector3d(0.3, -1.2, 2.5);
  s.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.2, -0.5, 1.0).normalized()));
  s.P_W = mass.mass() * Eigen::Vector3d(1.5, 0.4, -0.8);
  s.L_W = s.q_WB * (mass.inertia() * omega_B);
  return s;
}

// |a − b| ≤ tolerance (1 + |b|) for each part of the state.
void expectClose(const State& a, const State& b, double tolerance, const std::string& where) {
  const auto close = [&](const auto& x, const auto& y, const char* part) {
    EXPECT_LE((x - y).norm(), tolerance * (1.0 + y.norm())) << where << ": " << part;
  };
  close(a.p_WB, b.p_WB, "x");
  close(a.P_W, b.P_W, "P");
  close(a.L_W, b.L_W, "L");
  close(a.q_WB.coeffs(), b.q_WB.coeffs(), "q");
  EXPECT_EQ(a.t, b.t) << where;
}

}  // namespace

TEST_P(LaneKernel, AgreesWithItsScalarReferenceToRounding) {
  const IntegratorInfo& info = integratorInfo(GetParam());
  ASSERT_NE(info.reference_step, nullptr) << "a method with a lane kernel names its scalar reference";
  ForceModel forces;
  forces.gravity_W = Eigen::Vector3d(0.0, 0.0, -9.81);
  forces.linear_damping = 0.3;
  forces.angular_damping = 0.02;
  AppliedWrench input;
  input.world = {Eigen::Vector3d(1.0, -2.0, 0.5), Eigen::Vector3d(0.01, 0.02, -0.03)};
  input.body = {Eigen::Vector3d(0.3, 0.0, -0.1), Eigen::Vector3d(0.0, 0.02, 0.01)};
  // One step may differ by a few roundings of the state; 200 steps by the sum of those, carried along.
  constexpr double kOneStep = 1e-14, kManySteps = 1e-11;
  for (const Case& c : cases()) {
    for (const bool loaded : {false, true}) {  // free, or under gravity, damping and every input
      const Model model{c.mass, loaded ? forces : ForceModel()};
      const AppliedWrench u = loaded ? input : AppliedWrench();
      const State start = startOf(c.mass, c.omega_B);
      for (const bool assembled : {false, true}) {  // every term, or only those the body needs
        const StepTerms terms = assembled ? assembleTerms(c.mass, model.forces, start, loaded) : StepTerms::all();
        for (const double h : {1e-3, 1e-2}) {
          const std::string where = c.name + (loaded ? " loaded" : " free") + (assembled ? " assembled" : " all") +
                                    " h=" + std::to_string(h);
          Integrator integrator(GetParam());
          State kernel = start;
          State reference = start;
          ASSERT_EQ(integrator.step(model, terms, u, h, kernel), StepStatus::kOk) << where;
          reference = info.reference_step(model, terms, u, h, reference);
          expectClose(kernel, reference, kOneStep, where + " one step");
          for (int k = 1; k < 200; ++k) {
            ASSERT_EQ(integrator.step(model, terms, u, h, kernel), StepStatus::kOk) << where;
            reference = info.reference_step(model, terms, u, h, reference);
          }
          expectClose(kernel, reference, kManySteps, where + " 200 steps");
        }
      }
    }
  }
}

// The methods whose step is a lane kernel; the others' steps are written plainly already.
std::vector<IntegratorType> laneKernelMethods() {
  std::vector<IntegratorType> methods;
  for (const IntegratorInfo& info : integratorRegistry()) {
    if (info.lane_kernel) methods.push_back(info.type);
  }
  return methods;
}

INSTANTIATE_TEST_SUITE_P(LaneMethods, LaneKernel, ::testing::ValuesIn(laneKernelMethods()),
                         [](const ::testing::TestParamInfo<IntegratorType>& info) { return integratorName(info.param); });
