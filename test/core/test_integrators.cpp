// The integrators against closed forms (docs/references.md §2.4, §2.5, §2.6) and invariants.
// Value-parameterised over every method, so a new method is tested by being added to allIntegrators().
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/rotation.hpp"

using namespace rigid_body;

namespace {

State run(Integrator integrator, const Model& model, const AppliedWrench& input, double h, int steps,
          State state) {
  for (int k = 0; k < steps; ++k) {
    const StepStatus status = integrator.step(model, input, h, state);
    EXPECT_EQ(status, StepStatus::kOk) << "step " << k;
    if (status != StepStatus::kOk) break;
  }
  return state;
}

class EveryIntegrator : public ::testing::TestWithParam<IntegratorType> {};

// A bound on the global error of a short test run for each class of method: order 1, order 2, and the
// rest (order 4, or dopri5 at its default tolerance of 1e-9 per step).
double boundFor(IntegratorType type, double first_order, double second_order, double higher_order) {
  const int order = nominalOrder(type);
  return order == 1 ? first_order : order == 2 ? second_order : higher_order;
}

}  // namespace

TEST_P(EveryIntegrator, ConstantForceGivesTheKnownDiscreteParabola) {
  // docs/references.md §2.4: explicit Euler x_n = x(t_n) − F h t_n/(2m), semi-implicit + F h t_n/(2m),
  // order ≥ 2 exact to rounding.
  const double m = 2.0, h = 0.01;
  const int n = 200;
  const Model model{MassProperties::box(m, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  const Eigen::Vector3d x0(1.0, -2.0, 0.5), v0(0.3, 0.0, -1.0), F(4.0, -2.0, 1.0);
  State start;
  start.p_WB = x0;
  start.P_W = m * v0;
  AppliedWrench input;
  input.world.force = F;
  const State end = run(Integrator(GetParam()), model, input, h, n, start);
  const double t = n * h;
  const Eigen::Vector3d exact = x0 + v0 * t + F * t * t / (2.0 * m);
  Eigen::Vector3d expected = exact;
  if (GetParam() == IntegratorType::kExplicitEuler) expected -= F * h * t / (2.0 * m);
  if (GetParam() == IntegratorType::kSemiImplicitEuler) expected += F * h * t / (2.0 * m);
  EXPECT_LT((end.p_WB - expected).norm(), 1e-12 * exact.norm()) << end.p_WB.transpose();
  EXPECT_LT((end.P_W - (m * v0 + F * t)).norm(), 1e-12 * F.norm() * t);  // Ṗ = F: every method is exact
  EXPECT_NEAR(end.t, t, 1e-12);
  // A force through the centre of mass does not turn the body.
  EXPECT_EQ(rotationAngleBetween(end.q_WB, start.q_WB), 0.0);
}

// The registry's constant-force weight, which the contact step trusts to undo a resting body's fall, is the
// method's own: one step from rest under a constant acceleration a moves x by c h² a (every method's P is
// exact, so a wrong row — say ½ for semi-implicit Euler — is off by half a step's fall).
TEST_P(EveryIntegrator, RegistryRowDescribesTheMethod) {
  const IntegratorInfo& info = integratorInfo(GetParam());
  EXPECT_EQ(info.type, GetParam());
  EXPECT_EQ(integratorFromName(info.name), GetParam());
  const double m = 2.0, h = 0.01;
  const Model model{MassProperties::box(m, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  AppliedWrench input;
  input.world.force = Eigen::Vector3d(4.0, -2.0, 1.0);
  State state;
  Integrator integrator(GetParam());
  ASSERT_EQ(integrator.step(model, input, h, state), StepStatus::kOk);
  const Eigen::Vector3d a = input.world.force / m;
  EXPECT_LT((state.p_WB - info.constant_force_weight * h * h * a).norm(), 1e-15) << state.p_WB.transpose();
}

TEST_P(EveryIntegrator, TorqueFreeSpinAboutAPrincipalAxisKeepsOmega) {
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d w_B = 2.0 * Eigen::Vector3d::Unit(axis);
    const State start = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(),
                                            Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized())),
                                            Eigen::Vector3d::Zero(), w_B);
    const State end = run(Integrator(GetParam()), model, AppliedWrench(), 0.001, 5000, start);
    const Eigen::Vector3d w_end_B = end.q_WB.conjugate() * angularVelocity(model.mass, end);
    EXPECT_LT((w_end_B - w_B).norm(), 1e-10) << "axis " << axis << ": " << w_end_B.transpose();
    // And the body turned by |ω| t about that axis. Explicit Euler's normalised step q + ½hωq and the
    // midpoint's Cayley map both turn by 2 atan(|ω|h/2) instead of |ω|h, short by (|ω|h)³/12 a step:
    // 6.7e-10 × 5000 steps = 3.3e-6 rad here. The exponential-based methods are exact about an axis;
    // dopri5 measured 2.9e-9 at its default tolerance.
    const Eigen::Quaterniond expected = start.q_WB * quaternionExp(w_B * end.t);
    const double bound = boundFor(GetParam(), 4e-6, 4e-6, 1e-8);
    EXPECT_LT(rotationAngleBetween(end.q_WB, expected), bound) << "axis " << axis;
  }
}

TEST_P(EveryIntegrator, SphereUnderBodyTorqueFollowsTheClosedForm) {
  // docs/references.md §2.5: I = I₀𝟙, ω_b0 = 0, constant body torque: q(t) = q₀ ⊗ exp(θ(t) n), θ = |τ| t²/(2 I₀).
  const Model model{MassProperties::sphere(5.0, 0.2), ForceModel{}};
  const double I0 = model.mass.inertia()(0, 0);
  const Eigen::Vector3d tau_B(0.02, -0.01, 0.03);
  State start;
  start.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d(0, 1, 1).normalized()));
  AppliedWrench input;
  input.body.torque = tau_B;
  const double h = 0.001, T = 2.0;
  const State end = run(Integrator(GetParam()), model, input, h, static_cast<int>(std::lround(T / h)), start);
  const double theta = tau_B.norm() * T * T / (2.0 * I0);
  const Eigen::Quaterniond expected = start.q_WB * quaternionExp(theta * tau_B.normalized());
  const double error = rotationAngleBetween(end.q_WB, expected);
  // First order: error ~ θ̇ h; second order: measured 3.4e-8 (implicit midpoint); rk4 to rounding,
  // dopri5 measured 4.7e-9 at its default tolerance.
  const double bound = boundFor(GetParam(), 2.0 * (theta / T) * h, 1e-7, 1e-8);
  EXPECT_LT(error, bound) << "θ(T) = " << theta;
  // The body turns about n = τ̂, which R leaves fixed, so L_W(t) = R₀ τ_b t for every method.
  const Eigen::Vector3d expected_L = start.q_WB * (tau_B * T);
  EXPECT_LT((end.L_W - expected_L).norm(), 1e-12 * expected_L.norm());
}

TEST_P(EveryIntegrator, BodyFrameForceOnARotatedBodyActsRotated) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}};
  State start;
  start.q_WB = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());  // body x = world y
  AppliedWrench input;
  input.body.force = Eigen::Vector3d(2.0, 0.0, 0.0);
  const State end = run(Integrator(GetParam()), model, input, 0.01, 100, start);
  EXPECT_TRUE(end.P_W.isApprox(Eigen::Vector3d(0.0, 2.0, 0.0), 1e-12)) << end.P_W.transpose();
}

TEST_P(EveryIntegrator, LinearDampingDecaysAtTheExactRateWithinTheMethodOrder) {
  // docs/references.md §2.6: v(t) = v₀ e^(−ct/m).
  const double m = 2.0, c = 1.0, h = 0.001, T = 1.0;
  Model model{MassProperties::sphere(m, 0.1), ForceModel{}};
  model.forces.linear_damping = c;
  State start;
  start.P_W = m * Eigen::Vector3d(1.0, 0.0, 0.0);
  const State end = run(Integrator(GetParam()), model, AppliedWrench(), h, 1000, start);
  const double exact = std::exp(-c * T / m);
  // Order 1: (c/m) h; order 2: Buss's Taylor step measured 1.3e-8 (the splitting methods treat damping
  // exactly); dopri5 measured 1.3e-10 at its default tolerance.
  const double bound = boundFor(GetParam(), (c / m) * h, 5e-8, 1e-9);
  EXPECT_NEAR(end.P_W.x() / m, exact, bound);
}

TEST_P(EveryIntegrator, WorldAngularMomentumOfATorqueFreeBodyNeverChanges) {
  // The momentum form: L̇ = τ = 0, so every method leaves L bit for bit, whatever its orientation error.
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  const State start = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.25, 2.0 / 3.0));
  const State end = run(Integrator(GetParam()), model, AppliedWrench(), 0.01, 10000, start);
  EXPECT_EQ(end.L_W, start.L_W);
  EXPECT_LT(std::abs(quaternionNormError(end)), 1e-15);
}

TEST_P(EveryIntegrator, ZeroStepLeavesTheStateAndInvalidStepsAreRefused) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d::Ones()), ForceModel{}};
  State state = stateFromVelocities(model.mass, Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond::Identity(),
                                    Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1));
  const State before = state;
  Integrator integrator(GetParam());
  EXPECT_EQ(integrator.step(model, AppliedWrench(), 0.0, state), StepStatus::kOk);
  EXPECT_EQ(state.p_WB, before.p_WB);
  EXPECT_EQ(state.q_WB.coeffs(), before.q_WB.coeffs());
  for (double h : {-0.001, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(integrator.step(model, AppliedWrench(), h, state), StepStatus::kInvalidStep) << h;
    EXPECT_EQ(state.p_WB, before.p_WB);
  }
}

TEST_P(EveryIntegrator, NonFiniteResultLeavesTheStateUnchanged) {
  const Model model{MassProperties::box(1.0, Eigen::Vector3d::Ones()), ForceModel{}};
  State state;
  state.P_W = Eigen::Vector3d(1.0, 0.0, 0.0);
  const State before = state;
  AppliedWrench input;
  input.world.force.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Integrator(GetParam()).step(model, input, 0.01, state), StepStatus::kNonFinite);
  EXPECT_EQ(state.P_W, before.P_W);
  EXPECT_EQ(state.t, before.t);
  // 1e308 N overflows the momentum to inf: refused the same way.
  input.world.force = Eigen::Vector3d(1e308, 0.0, 0.0);
  state.P_W = Eigen::Vector3d(1e308, 0.0, 0.0);
  EXPECT_EQ(Integrator(GetParam()).step(model, input, 10.0, state), StepStatus::kNonFinite);
  EXPECT_TRUE(isFinite(state));
}

TEST_P(EveryIntegrator, AHugeSpinEitherFailsTheStepOrKeepsAUnitQuaternion) {
  // ω ~ 1e300 rad/s: an additive update makes q's components overflow, and normalising them divides by
  // infinity: the zero quaternion, finite but no rotation. Such a step must fail, never return that q.
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  for (double L : {1e150, 1e300, 1.7e308}) {
    State state;
    state.L_W = Eigen::Vector3d(L, 0.5 * L, 0.0);
    const State before = state;
    const StepStatus status = Integrator(GetParam()).step(model, AppliedWrench(), 0.01, state);
    if (status == StepStatus::kOk) {
      EXPECT_NEAR(state.q_WB.norm(), 1.0, 1e-12) << L;
      EXPECT_TRUE(isFinite(state)) << L;
    } else {
      EXPECT_TRUE(status == StepStatus::kNonFinite || status == StepStatus::kNotConverged) << L;
      EXPECT_EQ(state.q_WB.coeffs(), before.q_WB.coeffs()) << L;  // unchanged
    }
  }
}

TEST_P(EveryIntegrator, ZeroAndTinyAngularVelocityStayFinite) {
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  for (double w : {0.0, 1e-300, 1e-12}) {
    State state = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                      Eigen::Vector3d::Zero(), Eigen::Vector3d(w, w, w));
    ASSERT_EQ(Integrator(GetParam()).step(model, AppliedWrench(), 0.001, state), StepStatus::kOk) << w;
    EXPECT_TRUE(isFinite(state)) << w;
    EXPECT_NEAR(state.q_WB.norm(), 1.0, 1e-15) << w;
  }
}

TEST_P(EveryIntegrator, KeepsAUnitQuaternionToRoundingAtEverySpinRate) {
  // A step's q before normalisation is off unit by ε, from ~1e-16 (slow spin, RK4: ~(h|ω|/2)⁶/72) to ~0.1
  // (fast spin, explicit Euler: (h|ω|)²/4); whatever the way to 1/|q| (near 1, a Newton step or a series),
  // the committed q must be unit to rounding at every ε, the near ranges' edges included. Two bodies:
  // principal axes along the body axes and not (semi-implicit Euler turns the second into and out of them).
  Eigen::Matrix3d full;
  full << 0.02, 0.001, -0.002, 0.001, 0.05, 0.003, -0.002, 0.003, 0.06;
  for (const Model& model :
       {Model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()), ForceModel{}},
        Model{MassProperties::fromInertia(1.5, full), ForceModel{}}}) {
    for (double w = 1e-3; w < 600.0; w *= 1.3) {
      State state = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(),
                                        Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 3).normalized())),
                                        Eigen::Vector3d::Zero(), w * Eigen::Vector3d(0.3, 1.0, -0.2).normalized());
      Integrator integrator(GetParam());
      for (int k = 0; k < 20; ++k) {
        ASSERT_EQ(integrator.step(model, AppliedWrench(), 0.001, state), StepStatus::kOk) << w;
        ASSERT_NEAR(state.q_WB.norm(), 1.0, 1e-15) << "|w| = " << w << " rad/s, step " << k;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, EveryIntegrator, ::testing::ValuesIn(allIntegrators()),
                         [](const ::testing::TestParamInfo<IntegratorType>& info) {
                           return integratorName(info.param);
                         });

TEST(Rk4, TorqueFreeAsymmetricBodyKeepsEnergyOverALongRun) {
  // I = (1, 2, 3), m₀ = (1, 0.5, 2): the asymmetric scene of the accuracy report, 10⁵ steps of 1 ms.
  const Model model{MassProperties::fromInertia(1.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix()),
                    ForceModel{}};
  const State start = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.25, 2.0 / 3.0));
  const double energy0 = kineticEnergy(model.mass, start);
  State state = start;
  Integrator rk4(IntegratorType::kRk4);
  double worst_energy = 0.0;
  for (int k = 0; k < 100000; ++k) {
    ASSERT_EQ(rk4.step(model, AppliedWrench(), 0.001, state), StepStatus::kOk);
    worst_energy = std::max(worst_energy, std::abs(kineticEnergy(model.mass, state) - energy0) / energy0);
  }
  // Measured 2.0e-14 (RK4's local error is O(h⁵) per step); the bound leaves a factor of 50.
  EXPECT_LT(worst_energy, 1e-12);
  EXPECT_NEAR(state.L_W.norm(), start.L_W.norm(), 1e-15 * start.L_W.norm());
  // The Casimir |m| = |Rᵀ L| stays |L| because R stays orthonormal.
  const Eigen::Vector3d m_B = state.q_WB.conjugate() * state.L_W;
  EXPECT_NEAR(m_B.norm(), start.L_W.norm(), 1e-13);
}

TEST(IntegratorNames, RoundTripAndUnknownNamesListTheValidOnes) {
  for (IntegratorType type : allIntegrators()) EXPECT_EQ(integratorFromName(integratorName(type)), type);
  try {
    integratorFromName("rk5");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("rk5"), std::string::npos);
    EXPECT_NE(message.find("explicit_euler, semi_implicit_euler, rk4"), std::string::npos) << message;
  }
}
