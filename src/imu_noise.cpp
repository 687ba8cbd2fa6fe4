#include "rigid_body_sim/imu_noise.hpp"

#include <cmath>

namespace rigid_body {

SensorNoiseModel::SensorNoiseModel(const SensorNoise& noise, double period, std::uint64_t seed)
    : white_stddev_(noise.noise_density / std::sqrt(period)),
      walk_stddev_(noise.random_walk * std::sqrt(period)),
      generator_(seed) {}

Eigen::Vector3d SensorNoiseModel::next() {
  Eigen::Vector3d error;
  for (int axis = 0; axis < 3; ++axis) {
    // Both draws are made even for a zero σ, so that turning one part on leaves the other's sequence as it was.
    bias_(axis) += walk_stddev_ * normal_(generator_);
    error(axis) = bias_(axis) + white_stddev_ * normal_(generator_);
  }
  return error;
}

}  // namespace rigid_body
