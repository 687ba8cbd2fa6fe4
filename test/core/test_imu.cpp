// The IMU against closed forms (docs/references.md, "An accelerometer off the centre of mass", "IMU noise"):
// at rest on the ground and on an incline at the edge of sticking it reads +g upward, held up by a wrench
// too; in free fall zero; off the centre of a spinning body the centripetal ω²r, during a spin-up also the
// tangential αr; a tumbling body's reading equals the derivative of its sensor point's velocity; and the
// noise's statistics match its densities.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rigid_body_sim/imu.hpp"
#include "rigid_body_sim/imu_noise.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);

ImuReading readingOf(const Scene& scene, std::size_t body, const ImuMount& mount) {
  const Wrench contact = contactWrench(scene.contacts(body), scene.state(body).p_WB, scene.dt());
  return imuReading(scene.model(body), scene.state(body), scene.input(body), contact, mount);
}

ImuMount mountAt(const Eigen::Vector3d& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  ImuMount mount;
  mount.p_BS_B = p;
  mount.q_BS = q;
  return mount;
}

Model freeModel(const MassProperties& mass, const Eigen::Vector3d& gravity) {
  Model model{mass, ForceModel()};
  model.forces.gravity_W = gravity;
  return model;
}

// A sensor turned a quarter turn about the body's x axis: its y axis is the body's z axis.
const Eigen::Quaterniond kQuarterTurnAboutX(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX()));

}  // namespace

TEST(Imu, BoxRestingOnTheGroundReadsPlusGUpwardInTheSensorAxes) {
  const Eigen::Vector3d size(0.4, 0.3, 0.2);
  ContactSetup setup;
  setup.environment = {reference::groundPlane(Eigen::Vector3d::UnitZ(), 0.6)};
  setup.bodies = {reference::collisionShape(ShapeType::kBox, size, 0.6, 0.0)};
  Scene scene({reference::contactBody(MassProperties::box(2.0, size), Eigen::Vector3d(0, 0, 0.1),
                                      Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                      kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  scene.step(500);
  // The sensor sits off the centre, on the top face, turned: at rest no lever-arm term, and the ground's
  // reaction M g up is (0, g, 0) in its axes. Leaving out the contact reads 0, adding gravity 2g or −g.
  const ImuReading reading = readingOf(scene, 0, mountAt(Eigen::Vector3d(0.15, -0.1, 0.1), kQuarterTurnAboutX));
  EXPECT_NEAR(reading.specific_force_S.x(), 0.0, 0.01 * kG);
  EXPECT_NEAR(reading.specific_force_S.y(), kG, 0.01 * kG);
  EXPECT_NEAR(reading.specific_force_S.z(), 0.0, 0.01 * kG);
  EXPECT_LT(reading.angular_velocity_S.norm(), 1e-3);
}

TEST(Imu, BoxStickingOnAnInclineNearTheFrictionAngleReadsPlusGUpward) {
  // tan θ = 0.9 μ: friction carries M g sin θ along the slope. The reading is +g along the world's up in every
  // case; counting only the normal impulses would read g cos θ along the plane's normal instead.
  const double mu = 0.5, theta = std::atan(0.9 * mu);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d size(0.3, 0.3, 0.2);
  ContactSetup setup;
  setup.environment = {reference::groundPlane(q * Eigen::Vector3d::UnitZ(), mu)};
  setup.bodies = {reference::collisionShape(ShapeType::kBox, size, mu, 0.0)};
  Scene scene({reference::contactBody(MassProperties::box(1.0, size), q * Eigen::Vector3d(0, 0, 0.1), q,
                                      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
  scene.setRecordContacts(true);
  scene.step(1000);
  ASSERT_LT(linearVelocity(scene.model(0).mass, scene.state(0)).norm(), 1e-3) << "the box should stick";
  const ImuReading reading = readingOf(scene, 0, mountAt(Eigen::Vector3d::Zero()));
  const Eigen::Vector3d expected = reading.q_WS.conjugate() * Eigen::Vector3d(0, 0, kG);
  EXPECT_LT((reading.specific_force_S - expected).norm(), 0.01 * kG)
      << "read " << reading.specific_force_S.transpose() << ", expected " << expected.transpose();
}

TEST(Imu, BodyHeldUpByAWrenchReadsPlusGUpwardAndInFreeFallReadsZero) {
  const MassProperties mass = MassProperties::box(3.0, Eigen::Vector3d(0.5, 0.2, 0.1));
  const Model model = freeModel(mass, kDown);
  const Eigen::Quaterniond q_WB(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const State state = stateFromVelocities(mass, Eigen::Vector3d(1, 2, 3), q_WB, Eigen::Vector3d(0.5, 0, -2),
                                          Eigen::Vector3d::Zero());
  const ImuMount mount = mountAt(Eigen::Vector3d(0.2, 0.05, -0.03), kQuarterTurnAboutX);
  AppliedWrench held;
  held.world.force = Eigen::Vector3d(0, 0, 3.0 * kG);
  const ImuReading holding = imuReading(model, state, held, Wrench(), mount);
  const Eigen::Vector3d up_S = holding.q_WS.conjugate() * Eigen::Vector3d(0, 0, kG);
  EXPECT_LT((holding.specific_force_S - up_S).norm(), 1e-12);
  // Free fall: every point of a body that does not turn accelerates with g, and the sensor feels nothing.
  const ImuReading falling = imuReading(model, state, AppliedWrench(), Wrench(), mount);
  EXPECT_LT(falling.specific_force_S.norm(), 1e-12);
  // The same force in body axes (turned with the body) reads the same.
  AppliedWrench held_in_body;
  held_in_body.body.force = q_WB.conjugate() * held.world.force;
  EXPECT_LT((imuReading(model, state, held_in_body, Wrench(), mount).specific_force_S - up_S).norm(), 1e-12);
}

TEST(Imu, SensorOffTheCentreOfASpinningBodyReadsTheCentripetalOmegaSquaredR) {
  // Spin about the principal z axis at ω, no gravity: the point at r on the x axis moves on a circle and
  // its acceleration is ω² r towards the axis, −x in the co-turning sensor's axes at every instant.
  const double omega = 7.0, r = 0.3;
  const MassProperties mass = MassProperties::box(1.0, Eigen::Vector3d(0.8, 0.4, 0.2));
  Scene scene({{freeModel(mass, Eigen::Vector3d::Zero()),
                stateFromVelocities(mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                                    Eigen::Vector3d(0, 0, omega)),
                true}},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, ContactSetup());
  const ImuMount mount = mountAt(Eigen::Vector3d(r, 0, 0), kQuarterTurnAboutX);
  for (int i = 0; i < 5; ++i) {
    scene.step(137);
    const ImuReading reading = readingOf(scene, 0, mount);
    // In the sensor's axes: x_S = x_B, y_S = z_B, z_S = −y_B.
    EXPECT_NEAR(reading.specific_force_S.x(), -omega * omega * r, 1e-9);
    EXPECT_NEAR(reading.specific_force_S.y(), 0.0, 1e-9);
    EXPECT_NEAR(reading.specific_force_S.z(), 0.0, 1e-9);
    EXPECT_NEAR(reading.angular_velocity_S.y(), omega, 1e-9);
    EXPECT_NEAR(reading.angular_velocity_S.x(), 0.0, 1e-9);
    EXPECT_NEAR(reading.angular_velocity_S.z(), 0.0, 1e-9);
  }
}

TEST(Imu, SpinUpByAConstantTorqueAddsTheTangentialAlphaR) {
  // From rest, τ about the principal z axis: α = τ / I_z, ω(t) = α t. At r on the body's x axis the sensor
  // reads −ω² r along x and α r along y (body axes).
  const double tau = 0.4, r = 0.25;
  const MassProperties mass = MassProperties::box(2.0, Eigen::Vector3d(0.6, 0.3, 0.2));
  const double alpha = tau / mass.inertia()(2, 2);
  Scene scene({{freeModel(mass, Eigen::Vector3d::Zero()), stateFromVelocities(mass, Eigen::Vector3d::Zero(),
                                                                              Eigen::Quaterniond::Identity(),
                                                                              Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
                true}},
              IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, ContactSetup());
  AppliedWrench torque;
  torque.body.torque = Eigen::Vector3d(0, 0, tau);
  scene.setInput(0, torque);
  scene.step(800);
  const double omega = alpha * 0.8;
  const ImuReading reading = readingOf(scene, 0, mountAt(Eigen::Vector3d(r, 0, 0)));
  EXPECT_NEAR(reading.specific_force_S.x(), -omega * omega * r, 1e-9);
  EXPECT_NEAR(reading.specific_force_S.y(), alpha * r, 1e-9);
  EXPECT_NEAR(reading.specific_force_S.z(), 0.0, 1e-9);
  EXPECT_NEAR(reading.angular_velocity_S.z(), omega, 1e-9);
}

TEST(Imu, TumblingBodysReadingIsTheDerivativeOfItsSensorPointsVelocity) {
  // A torque-free asymmetric body tumbling off its principal axes under gravity and a pushing force: the
  // reading must be R_SW (d v_S/dt − g), v_S = v + ω × r, which a central difference of the integrated motion
  // gives to O(h²). Catches a wrong sign of α or of the gyroscopic term ω × L, and α = I⁻¹ τ alone.
  const MassProperties mass = MassProperties::box(1.5, Eigen::Vector3d(0.7, 0.35, 0.15));
  const Model model = freeModel(mass, kDown);
  const Eigen::Vector3d r(0.2, -0.15, 0.1);
  AppliedWrench push;
  push.world.force = Eigen::Vector3d(1.0, -2.0, 0.5);
  push.world.torque = Eigen::Vector3d(0.05, 0.02, -0.03);
  Scene scene({{model, stateFromVelocities(mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                           Eigen::Vector3d::Zero(), Eigen::Vector3d(3.0, 0.5, 4.0)),
                true}},
              IntegratorType::kRk4, 1e-5, IntegratorSettings(), StepAssembly::kLeaveOut, ContactSetup());
  scene.setInput(0, push);
  const auto sensorVelocity = [&](const State& s) {
    const Eigen::Vector3d w = angularVelocity(mass, s);
    return Eigen::Vector3d(linearVelocity(mass, s) + w.cross(s.q_WB.normalized() * r));
  };
  scene.step(12345);
  const Eigen::Vector3d before = sensorVelocity(scene.state(0));
  scene.step(1);
  const State middle = scene.state(0);
  scene.step(1);
  const Eigen::Vector3d after = sensorVelocity(scene.state(0));
  const Eigen::Vector3d expected_W = (after - before) / (2.0 * scene.dt()) - kDown;
  const ImuReading reading = imuReading(model, middle, push, Wrench(), mountAt(r));
  const Eigen::Vector3d read_W = reading.q_WS * reading.specific_force_S;
  // The difference's error is h² |d³v_S/dt³| / 6 ≈ 1e-10 |ω|³ |r| ~ 1e-8: a wrong term is ~|ω|²|r| ~ 1.
  EXPECT_LT((read_W - expected_W).norm(), 1e-5) << "read " << read_W.transpose() << ", expected "
                                                 << expected_W.transpose();
}

TEST(Imu, ContactWrenchIsTheMeanOfTheImpulsesAndTheirMoments) {
  Contact a;
  a.position_W = Eigen::Vector3d(1, 0, 0);
  a.normal_W = Eigen::Vector3d(0, 0, 1);
  a.normal_impulse = 0.02;
  a.friction_impulse_W = Eigen::Vector3d(0, 0.01, 0);
  Contact b = a;
  b.position_W = Eigen::Vector3d(-1, 0, 0);
  b.friction_impulse_W = Eigen::Vector3d(0, -0.01, 0);
  const Wrench wrench = contactWrench({a, b}, Eigen::Vector3d(0, 0, 0.5), 0.01);
  EXPECT_LT((wrench.force - Eigen::Vector3d(0, 0, 4.0)).norm(), 1e-12);
  // (±1, 0, −0.5) × (0, ±0.01, 0.02) / h, summed: the normal parts cancel in y, the friction parts add in z.
  EXPECT_LT((wrench.torque - Eigen::Vector3d(0, 0, 2.0)).norm(), 1e-12);
}

// --- The noise model -------------------------------------------------------------------------------------

namespace {

struct SampleMoments {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d variance = Eigen::Vector3d::Zero();
};

SampleMoments momentsOf(const std::vector<Eigen::Vector3d>& samples) {
  SampleMoments m;
  for (const Eigen::Vector3d& s : samples) m.mean += s;
  m.mean /= static_cast<double>(samples.size());
  for (const Eigen::Vector3d& s : samples) m.variance += (s - m.mean).cwiseAbs2();
  m.variance /= static_cast<double>(samples.size() - 1);
  return m;
}

constexpr int kSamples = 200000;
// The relative standard error of a sample variance of N Gaussian draws is √(2/N) (0.32 % here): five of it.
const double kVarianceTolerance = 5.0 * std::sqrt(2.0 / kSamples);

}  // namespace

TEST(ImuNoise, WhiteNoiseHasTheVarianceOfItsDensityOverThePeriod) {
  const double density = 0.003, period = 1.0 / 400.0;  // σ_n [unit/√Hz] at 400 Hz
  SensorNoiseModel noise({density, 0.0}, period, 42);
  std::vector<Eigen::Vector3d> samples;
  for (int i = 0; i < kSamples; ++i) samples.push_back(noise.next());
  const SampleMoments m = momentsOf(samples);
  const double variance = density * density / period;
  EXPECT_DOUBLE_EQ(noise.whiteStddev() * noise.whiteStddev(), variance);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(m.variance(axis) / variance, 1.0, kVarianceTolerance) << "axis " << axis;
    EXPECT_NEAR(m.mean(axis), 0.0, 5.0 * std::sqrt(variance / kSamples)) << "axis " << axis;
  }
}

TEST(ImuNoise, BiasWalksWithTheVarianceOfItsRandomWalkTimesThePeriod) {
  // With both parts: y_k − y_{k−1} = w_k + n_k − n_{k−1}, of variance σ_b² Δt + 2 σ_n² / Δt.
  const double density = 0.002, walk = 0.05, period = 1.0 / 200.0;
  SensorNoiseModel noise({density, walk}, period, 7);
  std::vector<Eigen::Vector3d> steps;
  Eigen::Vector3d previous = noise.next();
  for (int i = 0; i < kSamples; ++i) {
    const Eigen::Vector3d sample = noise.next();
    steps.push_back(sample - previous);
    previous = sample;
  }
  const double variance = walk * walk * period + 2.0 * density * density / period;
  const SampleMoments m = momentsOf(steps);
  // Differences of neighbours are correlated (lag one, −σ_n²/Δt each): the estimate's error is about twice
  // that of independent draws.
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(m.variance(axis) / variance, 1.0, 2.0 * kVarianceTolerance);
  // And the bias alone: its steps are independent draws of σ_b √Δt.
  SensorNoiseModel bias_only({0.0, walk}, period, 8);
  std::vector<Eigen::Vector3d> bias_steps;
  Eigen::Vector3d last = bias_only.next();
  for (int i = 0; i < kSamples; ++i) {
    const Eigen::Vector3d sample = bias_only.next();
    bias_steps.push_back(sample - last);
    last = sample;
    ASSERT_EQ(sample, bias_only.bias()) << "without white noise the error is the bias";
  }
  const SampleMoments b = momentsOf(bias_steps);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(b.variance(axis) / (walk * walk * period), 1.0, kVarianceTolerance) << "axis " << axis;
  }
}

TEST(ImuNoise, SameSeedSameErrorsAndNoNoiseNoError) {
  SensorNoiseModel a({0.01, 0.001}, 0.01, 3), b({0.01, 0.001}, 0.01, 3), c({0.01, 0.001}, 0.01, 4);
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d x = a.next();
    EXPECT_EQ(x, b.next());
    differs = differs || x != c.next();
  }
  EXPECT_TRUE(differs);
  SensorNoiseModel quiet({0.0, 0.0}, 0.01, 3);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(quiet.next(), Eigen::Vector3d::Zero());
}
