// The error model of a MEMS inertial sensor as Kalibr and RotorS state it (docs/references.md, "IMU noise"):
// each axis of the gyroscope and of the accelerometer reads the true value plus white noise n and a bias b
// that walks,
//   ỹ(t) = y(t) + b(t) + n(t),   E[n(t)n(s)] = σ_n² δ(t − s),   ḃ(t) = σ_b w(t),  w white of unit density,
// with the noise density σ_n [unit/√Hz] and the bias random walk σ_b [unit·√Hz] of a data sheet or an Allan
// deviation plot. Sampled every Δt, the white part is a Gaussian of standard deviation σ_n / √Δt and the
// bias moves by a Gaussian of standard deviation σ_b √Δt per sample.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>

namespace rigid_body {

/// One sensor's continuous-time noise parameters.
struct SensorNoise {
  double noise_density = 0.0;  ///< σ_n: gyroscope [rad/s/√Hz], accelerometer [m/s²/√Hz]
  double random_walk = 0.0;    ///< σ_b: gyroscope [rad/s²/√Hz], accelerometer [m/s³/√Hz]
  bool enabled() const { return noise_density > 0.0 || random_walk > 0.0; }
};

/// Draws the errors of a three-axis sensor sampled every `period`, from its own seeded generator: the same
/// seed gives the same errors.
class SensorNoiseModel {
 public:
  SensorNoiseModel(const SensorNoise& noise, double period, std::uint64_t seed);

  /// The next sample's error b_k + n_k: the bias first walks by σ_b √Δt, then the white part is drawn.
  Eigen::Vector3d next();
  /// The standard deviation of the white part of one sample, σ_n / √Δt (what the covariance declares).
  double whiteStddev() const { return white_stddev_; }
  const Eigen::Vector3d& bias() const { return bias_; }

 private:
  double white_stddev_;
  double walk_stddev_;
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  std::mt19937_64 generator_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace rigid_body
