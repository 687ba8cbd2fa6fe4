// The scenes of the work-precision part of the accuracy report, each with its reference solution.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/state.hpp"

namespace accuracy_report {

/// What the error of a run is measured on.
enum class ErrorMetric {
  kOrientation,  ///< θ = 2 atan2(|vec(q_ref⁻¹q)|, |w(q_ref⁻¹q)|) [rad]
  kPosition,     ///< ‖x − x_ref‖ [m]
};

struct Scene {
  std::string name;         ///< file-name friendly, e.g. "dzhanibekov"
  std::string description;  ///< for the report
  rigid_body::Model model;
  rigid_body::State initial;
  rigid_body::AppliedWrench input;
  double duration;  ///< T [s]
  ErrorMetric metric;
  rigid_body::State reference;  ///< the exact (or converged) state at T
};

/// The five scenes: ballistic under gravity, symmetric top, asymmetric body, the Dzhanibekov T handle over
/// two flips, an off-centre push on a box.
std::vector<Scene> workPrecisionScenes();

/// The asymmetric body I = (1, 2, 3), m₀ = (1, 0.5, 2) over `duration` with its closed-form reference.
Scene asymmetricScene(double duration);

/// A torque-free body with principal moments I along the body axes and body momentum m0, with its
/// closed-form reference at `duration` (I₁ < I₂ < I₃).
Scene torqueFreeScene(const std::string& name, const std::string& description, const Eigen::Vector3d& I,
                      const Eigen::Vector3d& m0, double duration);

/// --substitute CLAIMED:RUN: every run of the report that names method CLAIMED integrates with method RUN
/// instead, while the rows still say CLAIMED. A mutation check: a lower-order method put in a method's place
/// must fail that method's claims (test_accuracy_report does it for every method that has a lower order).
void substitute(rigid_body::IntegratorType claimed, rigid_body::IntegratorType run);

/// The method a run of `type` uses: `type` itself unless substituted.
rigid_body::IntegratorType runType(rigid_body::IntegratorType type);

/// The integrator a run of `type` uses: `type` itself unless substituted.
rigid_body::Integrator makeIntegrator(rigid_body::IntegratorType type,
                                      const rigid_body::IntegratorSettings& settings = rigid_body::IntegratorSettings());

/// Runs `scene` with `integrator` at step h; returns the final state (t = T).
rigid_body::State runScene(const Scene& scene, rigid_body::Integrator& integrator, double h);

/// The error of `state` against the scene's reference, by the scene's metric.
double errorOf(const Scene& scene, const rigid_body::State& state);

/// "orientation error [rad]" or "position error [m]".
std::string metricLabel(ErrorMetric metric);

}  // namespace accuracy_report
