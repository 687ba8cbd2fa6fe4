#include <gtest/gtest.h>

#include <cmath>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/kinematics.hpp"

using namespace rigid_body;

TEST(Forces, ForceAtPointGivesMomentArmTorque) {
  State state;
  state.p_WB = Eigen::Vector3d(1.0, 2.0, 3.0);
  const Eigen::Vector3d force(0.0, 0.0, 10.0);
  const Eigen::Vector3d point(1.5, 2.0, 3.0);  // 0.5 m along +x from the centre of mass
  const Wrench wrench = forceAtPoint(force, point, state);
  EXPECT_TRUE(wrench.force.isApprox(force));
  // τ = (p − x) × F = (0.5, 0, 0) × (0, 0, 10) = (0, −5, 0)
  EXPECT_NEAR(wrench.torque.x(), 0.0, 1e-15);
  EXPECT_NEAR(wrench.torque.y(), -5.0, 1e-15);
  EXPECT_NEAR(wrench.torque.z(), 0.0, 1e-15);
}

TEST(Forces, ForceAtBodyPointTurnsWithTheBody) {
  State state;
  state.p_WB = Eigen::Vector3d(0.0, 0.0, 1.0);
  state.q_WB = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());  // body x points along world y
  const Wrench wrench = forceAtBodyPoint(Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(1.0, 0.0, 0.0), state);
  // The body point (1,0,0) is at world offset (0,1,0): τ = (0,1,0) × (0,0,2) = (2,0,0).
  EXPECT_TRUE(wrench.torque.isApprox(Eigen::Vector3d(2.0, 0.0, 0.0), 1e-15));
}

TEST(Forces, TotalWrenchSumsInputGravityAndDamping) {
  Model model{MassProperties::sphere(2.0, 0.1), ForceModel{Eigen::Vector3d(0, 0, -9.81), 0.5, 0.25}};
  State state = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(),
                                    Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
                                    Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 4.0));
  AppliedWrench input;
  input.world.force = Eigen::Vector3d(1.0, 0.0, 0.0);
  input.body.force = Eigen::Vector3d(1.0, 0.0, 0.0);   // world +y after the 90° yaw
  input.body.torque = Eigen::Vector3d(0.0, 0.0, 3.0);  // the yaw axis is shared by body and world
  const Wrench total = totalWrench(model, StepTerms::all(), motionOf(model.mass, state), input);
  // F = (1,0,0) + (0,1,0) + 2·(0,0,−9.81) − 0.5·(1,0,0)
  EXPECT_TRUE(total.force.isApprox(Eigen::Vector3d(0.5, 1.0, -19.62), 1e-14));
  // τ = (0,0,3) − 0.25·(0,0,4)
  EXPECT_TRUE(total.torque.isApprox(Eigen::Vector3d(0.0, 0.0, 2.0), 1e-14));
}

TEST(Kinematics, EnergyAndVelocitiesFromMomenta) {
  const MassProperties box = MassProperties::box(2.0, Eigen::Vector3d(1.0, 2.0, 3.0));
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d v(1.0, -2.0, 0.5), w_B(0.3, -0.2, 0.1);
  const State state = stateFromVelocities(box, Eigen::Vector3d::Zero(), q, v, w_B);
  EXPECT_TRUE(linearVelocity(box, state).isApprox(v, 1e-15));
  EXPECT_TRUE(angularVelocity(box, state).isApprox(q * w_B, 1e-14));
  const double expected = 0.5 * 2.0 * v.squaredNorm() + 0.5 * w_B.dot(box.inertia() * w_B);
  EXPECT_NEAR(kineticEnergy(box, state), expected, 1e-14);
  ForceModel gravity;
  gravity.gravity_W = Eigen::Vector3d(0, 0, -9.81);
  State raised = state;
  raised.p_WB.z() = 2.0;
  EXPECT_NEAR(potentialEnergy(box, gravity, raised), 2.0 * 9.81 * 2.0, 1e-13);
}

TEST(Kinematics, WorldInverseInertiaIsTheGeneralFormulaAndTheIsotropicShortcutAgrees) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d L(0.3, -1.2, 2.0);
  const MassProperties box = MassProperties::box(2.0, Eigen::Vector3d(0.4, 0.2, 0.1));
  EXPECT_FALSE(box.isIsotropic());
  const Eigen::Matrix3d I_W = R * box.inertia() * R.transpose();
  EXPECT_TRUE(applyWorldInverseInertia(box, StepTerms::all(), R, L).isApprox(I_W.inverse() * L, 1e-13));
  // The sphere takes the shortcut ω = L/I₀; the general path gives the same to rounding.
  const MassProperties sphere = MassProperties::sphere(2.0, 0.3);
  ASSERT_TRUE(sphere.isIsotropic());
  const Eigen::Vector3d general = R * (sphere.inverseInertia() * (R.transpose() * L));
  StepTerms isotropic = StepTerms::all();
  isotropic.world_inertia = assembleTerms(sphere, ForceModel{}, State(), true).world_inertia;
  ASSERT_FALSE(isotropic.world_inertia);
  EXPECT_TRUE(applyWorldInverseInertia(sphere, isotropic, R, L).isApprox(general, 1e-15));
  // Nearly isotropic is not isotropic: no shortcut.
  EXPECT_FALSE(MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 1.0, 1.0 + 1e-9).asDiagonal().toDenseMatrix())
                   .isIsotropic());
}
