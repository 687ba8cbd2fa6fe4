// What the contact section's scenes share (contact_report.cpp, contact_cases.cpp): the methods compared, and
// short ways to make shapes, bodies and a scene of the reference kind.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"
#include "scenes.hpp"

namespace accuracy_report {

using rigid_body::BodyDefinition;
using rigid_body::CollisionShape;
using rigid_body::ContactSettings;
using rigid_body::ContactSetup;
using rigid_body::IntegratorType;
using rigid_body::MassProperties;
using rigid_body::ShapeType;
using rigid_body::State;

inline constexpr double kG = 9.81;
inline constexpr double kPi = 3.14159265358979323846;
inline const Eigen::Vector3d kDown(0.0, 0.0, -kG);
// The methods the contact section compares: the two first-order ones (the game engines' choice), a symplectic
// second-order one and rk4 (the default).
inline const std::vector<IntegratorType> kMethods = {IntegratorType::kExplicitEuler, IntegratorType::kSemiImplicitEuler,
                                                      IntegratorType::kSymplecticSplitting, IntegratorType::kRk4};

inline CollisionShape shape(ShapeType type, const Eigen::Vector3d& size, double friction, double restitution) {
  return rigid_body::reference::collisionShape(type, size, friction, restitution);
}

inline CollisionShape plane(const Eigen::Vector3d& normal, double friction) {
  return rigid_body::reference::groundPlane(normal, friction);
}

inline BodyDefinition body(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                           const Eigen::Vector3d& v, const Eigen::Vector3d& w_B, const Eigen::Vector3d& gravity) {
  return rigid_body::reference::contactBody(mass, p, q, v, w_B, gravity);
}

inline rigid_body::Scene makeScene(const std::vector<BodyDefinition>& bodies, ContactSetup setup, IntegratorType type,
                                   double dt, const ContactSettings& settings) {
  setup.settings = settings;
  return rigid_body::Scene(bodies, runType(type), dt, rigid_body::IntegratorSettings(),
                           rigid_body::StepAssembly::kLeaveOut, setup);
}

inline std::int64_t stepsFor(double duration, double dt) { return static_cast<std::int64_t>(std::llround(duration / dt)); }

}  // namespace accuracy_report
