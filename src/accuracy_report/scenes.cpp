#include "scenes.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace accuracy_report {

using namespace rigid_body;

namespace {

using reference::torqueFreeStart;

const Eigen::Quaterniond& kQ0 = reference::testOrientation();

// Exempt from the triangle inequality: the report uses Principia's published top I = (3, 3, 9).
Model principalBody(const Eigen::Vector3d& moments) {
  return reference::principalBody(moments, 1.0, InertiaCheck::kPositiveDefiniteOnly);
}

}  // namespace

Scene torqueFreeScene(const std::string& name, const std::string& description, const Eigen::Vector3d& I,
                      const Eigen::Vector3d& m0, double duration) {
  Scene scene{name, description, principalBody(I), torqueFreeStart(m0), AppliedWrench(), duration,
              ErrorMetric::kOrientation, State()};
  scene.reference = scene.initial;
  scene.reference.q_WB = reference::TorqueFreeBody(I, m0, kQ0).orientation(duration);
  scene.reference.t = duration;
  return scene;
}


namespace {
std::map<IntegratorType, IntegratorType>& substitutions() {
  static std::map<IntegratorType, IntegratorType> map;
  return map;
}
}  // namespace

void substitute(IntegratorType claimed, IntegratorType run) { substitutions()[claimed] = run; }

IntegratorType runType(IntegratorType type) {
  const auto found = substitutions().find(type);
  return found == substitutions().end() ? type : found->second;
}

Integrator makeIntegrator(IntegratorType type, const IntegratorSettings& settings) {
  return Integrator(runType(type), settings);
}

Scene asymmetricScene(double duration) {
  return torqueFreeScene("asymmetric", "torque-free asymmetric body I = (1, 2, 3), m0 = (1, 0.5, 2)",
                         Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 0.5, 2), duration);
}

std::vector<Scene> workPrecisionScenes() {
  std::vector<Scene> scenes;

  // Ballistic: 2 kg box thrown at (3, 0, 5) m/s under gravity, 5 s. x(t) = x0 + v0 t + g t²/2.
  Scene ballistic{"ballistic", "2 kg box thrown under gravity, 5 s",
                  Model{MassProperties::box(2.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}},
                  State(), AppliedWrench(), 5.0, ErrorMetric::kPosition, State()};
  ballistic.model.forces.gravity_W = Eigen::Vector3d(0, 0, -9.81);
  ballistic.initial.P_W = 2.0 * Eigen::Vector3d(3.0, 0.0, 5.0);
  ballistic.reference.p_WB = reference::ballisticPosition(Eigen::Vector3d::Zero(), Eigen::Vector3d(3, 0, 5),
                                                          2.0 * Eigen::Vector3d(0, 0, -9.81), 2.0, 5.0);
  scenes.push_back(ballistic);

  // Symmetric top, Principia's I = (3, 3, 9) (a numerical test body: 9 > 3 + 3), m0 = (0, 5, 7).
  {
    const Eigen::Vector3d I(3, 3, 9), m0(0, 5, 7);
    Scene top{"symmetric_top", "torque-free symmetric top I = (3, 3, 9), m0 = (0, 5, 7), 5 s", principalBody(I),
              torqueFreeStart(m0), AppliedWrench(), 5.0, ErrorMetric::kOrientation, State()};
    top.reference.q_WB = reference::symmetricTop(3, 9, kQ0, kQ0 * m0, 5.0);
    scenes.push_back(top);
  }

  Scene asymmetric = asymmetricScene(20.0);
  asymmetric.description += ", 20 s";
  scenes.push_back(asymmetric);

  // The T handle: first flip at 7.86 s, the second 13.45 s later; 25 s covers both.
  scenes.push_back(torqueFreeScene("dzhanibekov",
                                   "Dzhanibekov T handle I = (1, 2, 3), m0 = (0.1, 2, 0.1), two flips, 25 s",
                                   Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.1, 2, 0.1), 25.0));

  // An off-centre push: 1 N along body x at the body point (0, 0.1, 0.05) of the default box, 5 s.
  // The torque (0, 0.05, −0.1) N m is off every principal axis, so the box tumbles in 3-D (a point in the
  // x–y plane would give a planar spin that kick–drift–kick methods integrate exactly).
  // No closed form: the reference integrates another formulation of the same physics with code of its own
  // (reference::bodyFixedPush: Euler's equations in body axes), so a wrong lever arm or frame in the step's
  // momentum form would show up as an error here instead of being copied into the reference.
  {
    Scene push{"off_centre_push", "default box pushed off centre: 1 N along body x at body (0, 0.1, 0.05), 5 s",
               Model{MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1)), ForceModel{}},
               State(), AppliedWrench(), 5.0, ErrorMetric::kOrientation, State()};
    push.input.body.force = Eigen::Vector3d(1.0, 0.0, 0.0);
    push.input.body.torque = Eigen::Vector3d(0.0, 0.1, 0.05).cross(push.input.body.force);
    push.reference = reference::bodyFixedPush(push.model.mass, Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.1, 0.05),
                                        push.duration, 1e-5);
    scenes.push_back(push);
  }
  return scenes;
}

State runScene(const Scene& scene, Integrator& integrator, double h) {
  State state = scene.initial;
  const long steps = std::lround(scene.duration / h);
  for (long k = 0; k < steps; ++k) {
    if (integrator.step(scene.model, scene.input, h, state) != StepStatus::kOk) break;
  }
  return state;
}

double errorOf(const Scene& scene, const State& state) {
  // A run that failed before T (or produced a non-finite state) has no finite error.
  if (!isFinite(state) || std::abs(state.t - scene.duration) > 1e-9 * scene.duration) {
    return std::numeric_limits<double>::infinity();
  }
  if (scene.metric == ErrorMetric::kPosition) return (state.p_WB - scene.reference.p_WB).norm();
  return rotationAngleBetween(state.q_WB, scene.reference.q_WB);
}

std::string metricLabel(ErrorMetric metric) {
  return metric == ErrorMetric::kPosition ? "position error [m]" : "orientation error [rad]";
}

}  // namespace accuracy_report
