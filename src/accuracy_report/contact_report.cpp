#include "contact_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/number_format.hpp"
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

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);
// The CPU time of one measurement is taken over repeats until at least this much has passed [s].
constexpr double kMinMeasuredCpu = 0.01;

// The methods the contact section compares: the two first-order ones (the game engines' choice), a symplectic
// second-order one and rk4 (the default).
const std::vector<IntegratorType> kMethods = {IntegratorType::kExplicitEuler, IntegratorType::kSemiImplicitEuler,
                                               IntegratorType::kSymplecticSplitting, IntegratorType::kRk4};

struct Setting {
  std::string name;
  bool event_location;
  int iterations;
};
const std::vector<Setting> kSettings = {{"located, 20 iterations", true, 20},
                                        {"at step end, 20 iterations", false, 20},
                                        {"located, 5 iterations", true, 5}};

CollisionShape shape(ShapeType type, const Eigen::Vector3d& size, double friction, double restitution) {
  return rigid_body::reference::collisionShape(type, size, friction, restitution);
}

CollisionShape plane(const Eigen::Vector3d& normal, double friction) {
  return rigid_body::reference::groundPlane(normal, friction);
}

BodyDefinition body(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                    const Eigen::Vector3d& v, const Eigen::Vector3d& w_B, const Eigen::Vector3d& gravity) {
  return rigid_body::reference::contactBody(mass, p, q, v, w_B, gravity);
}

rigid_body::Scene makeScene(const std::vector<BodyDefinition>& bodies, ContactSetup setup, IntegratorType type,
                            double dt, const ContactSettings& settings) {
  setup.settings = settings;
  return rigid_body::Scene(bodies, runType(type), dt, rigid_body::IntegratorSettings(),
                           rigid_body::StepAssembly::kLeaveOut, setup);
}

std::int64_t stepsFor(double duration, double dt) { return static_cast<std::int64_t>(std::llround(duration / dt)); }

// A closed-form contact scene: it builds its scene, runs it and returns its error.
struct ClosedFormCase {
  std::string name;
  std::string metric;
  std::function<double(IntegratorType, double, const ContactSettings&)> run;
};

// docs/references.md §4.1: apexes e^(2n) h0 after bounces n = 1…3 (z + v²/2g as v_z turns negative).
double bounce(IntegratorType type, double dt, const ContactSettings& settings) {
  const double radius = 0.1, h0 = 1.0, e = 0.5;
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
  setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, e)};
  rigid_body::Scene scene = makeScene({body(MassProperties::sphere(1.0, radius), Eigen::Vector3d(0, 0, radius + h0),
                                            Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(),
                                            Eigen::Vector3d::Zero(), kDown)},
                                      setup, type, dt, settings);
  double previous_vz = 0.0, error = 0.0;
  int bounces = 0;
  for (std::int64_t i = 0, n = stepsFor(1.2, dt); i < n && bounces < 3; ++i) {
    scene.step(1);
    const double vz = scene.state().P_W.z();
    if (previous_vz > 0.0 && vz <= 0.0) {
      ++bounces;
      const double apex = scene.state().p_WB.z() - radius + vz * vz / (2.0 * kG);
      const double expected = std::pow(e, 2.0 * bounces) * h0;
      error = std::max(error, std::abs(apex - expected) / expected);
    }
    previous_vz = vz;
  }
  return bounces == 3 ? error : std::numeric_limits<double>::infinity();
}

// §4.2: a block sliding from v0 stops after v0²/(2μg).
double slide(IntegratorType type, double dt, const ContactSettings& settings) {
  const double mu = 0.4, v0 = 2.0;
  const Eigen::Vector3d size(0.2, 0.2, 0.1);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), mu)};
  setup.bodies = {shape(ShapeType::kBox, size, mu, 0.0)};
  rigid_body::Scene scene = makeScene({body(MassProperties::box(2.0, size), Eigen::Vector3d(0, 0, 0.05),
                                            Eigen::Quaterniond::Identity(), Eigen::Vector3d(v0, 0, 0),
                                            Eigen::Vector3d::Zero(), kDown)},
                                      setup, type, dt, settings);
  scene.step(stepsFor(0.8, dt));
  const double expected = v0 * v0 / (2.0 * mu * kG);
  return std::abs(scene.state().p_WB.x() - expected) / expected;
}

// §4.3 and §4.4: the distance down an incline after 1 s, sliding (a = g(sin θ − μ cos θ)) or rolling
// (a = 5/7 g sin θ).
double incline(IntegratorType type, double dt, const ContactSettings& settings, bool rolling) {
  const double theta = (rolling ? 25.0 : 20.0) * kPi / 180.0, mu = rolling ? 0.6 : 0.2;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d n = q * Eigen::Vector3d::UnitZ(), down = q * Eigen::Vector3d::UnitX();
  ContactSetup setup;
  setup.environment = {plane(n, mu)};
  const Eigen::Vector3d box(0.2, 0.2, 0.1);
  setup.bodies = {rolling ? shape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), mu, 0.0)
                          : shape(ShapeType::kBox, box, mu, 0.0)};
  const Eigen::Vector3d start = (rolling ? 0.1 : 0.05) * n;
  rigid_body::Scene scene =
      makeScene({body(rolling ? MassProperties::sphere(1.0, 0.1) : MassProperties::box(1.0, box), start,
                      rolling ? Eigen::Quaterniond::Identity() : q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
                setup, type, dt, settings);
  scene.step(stepsFor(1.0, dt));
  const double a = rolling ? 5.0 / 7.0 * kG * std::sin(theta) : kG * (std::sin(theta) - mu * std::cos(theta));
  return std::abs((scene.state().p_WB - start).dot(down) - 0.5 * a) / (0.5 * a);
}

// §4.5: equal spheres, e = 1, exchange velocities; where they are 1 s later shows when they did.
double headOn(IntegratorType type, double dt, const ContactSettings& settings) {
  const MassProperties ball = MassProperties::sphere(1.0, 0.1);
  ContactSetup setup;
  setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.0, 1.0),
                  shape(ShapeType::kSphere, Eigen::Vector3d(0.1, 0, 0), 0.0, 1.0)};
  const Eigen::Vector3d va(1.5, 0, 0), vb(-0.5, 0, 0);
  rigid_body::Scene scene = makeScene(
      {body(ball, Eigen::Vector3d(-0.5, 0, 0), Eigen::Quaterniond::Identity(), va, Eigen::Vector3d::Zero(),
            Eigen::Vector3d::Zero()),
       body(ball, Eigen::Vector3d(0.5, 0, 0), Eigen::Quaterniond::Identity(), vb, Eigen::Vector3d::Zero(),
            Eigen::Vector3d::Zero())},
      setup, type, dt, settings);
  scene.step(stepsFor(1.0, dt));
  // They meet at t = 0.4 s (0.8 m closing at 2 m/s) at x = 0.1 and 0.3 and leave with each other's velocity.
  const double x_a = 0.1 + vb.x() * 0.6, x_b = 0.3 + va.x() * 0.6;
  return std::abs(scene.state(0).p_WB.x() - x_a) + std::abs(scene.state(1).p_WB.x() - x_b);
}

// §4.6: a tilted capsule rod dropped from rest, momenta 50 ms after its impact against the impulse formula.
double rodImpact(IntegratorType type, double dt, const ContactSettings& settings) {
  const double r = 0.02, l = 1.0, m = 2.0, e = 0.5, drop = 0.2;
  const MassProperties rod = MassProperties::cylinder(m, r, l + 2.0 * r);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(30.0 * kPi / 180.0, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0)};
  setup.bodies = {shape(ShapeType::kCapsule, Eigen::Vector3d(r, l, 0), 0.0, e)};
  rigid_body::Scene scene = makeScene({body(rod, Eigen::Vector3d(0, 0, 0.5 * l * axis.z() + r + drop), q,
                                            Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
                                      setup, type, dt, settings);
  const double impact = std::sqrt(2.0 * drop / kG), end = impact + 0.05;
  scene.step(stepsFor(end, dt));
  const double t_end = static_cast<double>(stepsFor(end, dt)) * dt;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ(), lever = -0.5 * l * axis - r * n;
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d I_inv = R * rod.inverseInertia() * R.transpose();
  const Eigen::Vector3d v_minus(0.0, 0.0, -kG * impact);
  const double j = -(1.0 + e) * v_minus.dot(n) / (1.0 / m + n.dot((I_inv * lever.cross(n)).cross(lever)));
  const Eigen::Vector3d P = m * v_minus + j * n + m * kDown * (t_end - impact);
  const Eigen::Vector3d L = lever.cross(j * n);
  return (scene.state().P_W - P).norm() / (j * n).norm() + (scene.state().L_W - L).norm() / L.norm();
}

const std::vector<ClosedFormCase>& closedFormCases() {
  static const std::vector<ClosedFormCase> cases = {
      {"bounce", "largest relative apex error, bounces 1-3", bounce},
      {"slide", "relative stop-distance error", slide},
      {"incline_slide", "relative distance error after 1 s",
       [](IntegratorType t, double dt, const ContactSettings& s) { return incline(t, dt, s, false); }},
      {"rolling", "relative distance error after 1 s",
       [](IntegratorType t, double dt, const ContactSettings& s) { return incline(t, dt, s, true); }},
      {"head_on", "position error after 1 s [m]", headOn},
      {"rod_impact", "relative momentum error 50 ms after impact", rodImpact},
  };
  return cases;
}

ContactSettings settingsFor(const Setting& setting) {
  ContactSettings settings;
  settings.event_location = setting.event_location;
  settings.iterations = setting.iterations;
  return settings;
}

std::string fmt(double value, int precision = 3) { return rigid_body::formatNumber(value, precision); }

}  // namespace

std::vector<ContactRow> runContactWorkPrecision(const Options& options) {
  const std::vector<double> steps = options.quick ? std::vector<double>{2e-3, 1e-3, 5e-4}
                                                  : std::vector<double>{4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4};
  const std::map<std::string, double> durations = {{"bounce", 1.2}, {"slide", 0.8},   {"incline_slide", 1.0},
                                                   {"rolling", 1.0}, {"head_on", 1.0}, {"rod_impact", 0.25}};
  std::vector<ContactRow> rows;
  for (const ClosedFormCase& c : closedFormCases()) {
    for (IntegratorType type : kMethods) {
      for (const Setting& setting : kSettings) {
        const ContactSettings settings = settingsFor(setting);
        for (double dt : steps) {
          double error = c.run(type, dt, settings);  // also the warm-up
          int repeats = 0;
          const double start = cpuSeconds();
          double elapsed = 0.0;
          while (elapsed < kMinMeasuredCpu) {
            error = c.run(type, dt, settings);
            ++repeats;
            elapsed = cpuSeconds() - start;
          }
          rows.push_back({c.name, c.metric, rigid_body::integratorName(type), setting.name, dt, error,
                          elapsed / repeats / durations.at(c.name)});
        }
      }
    }
  }
  std::ofstream csv(options.out + "/contact.csv");
  csv << "scene,metric,integrator,setting,dt,error,cpu_per_simulated_second\n";
  csv.precision(17);
  for (const ContactRow& row : rows) {
    csv << row.scene << ",\"" << row.metric << "\"," << row.integrator << ",\"" << row.setting << "\"," << row.dt
        << "," << row.error << "," << row.cpu_per_second << "\n";
  }
  return rows;
}

// ---------------------------------------------------------------------------------------------------------
// The stiff and extreme contact cases. Each threshold is what the contact step is built to do (docs/contact.md),
// written down before the case was first run; a case without a claim is reported.

namespace {

class CaseRows {
 public:
  void claim(const std::string& c, IntegratorType type, const std::string& metric, double value, const std::string& op,
             double bound) {
    const bool pass = op == "<=" ? value <= bound : value >= bound;
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, op + " " + rigid_body::formatNumber(bound, 6),
                     true, pass});
  }
  // Kept by construction: checked and shown apart, never counted as a claim.
  void invariant(const std::string& c, IntegratorType type, const std::string& metric, double value, double bound) {
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, "<= " + rigid_body::formatNumber(bound, 6),
                     true, value <= bound, true});
  }
  void report(const std::string& c, IntegratorType type, const std::string& metric, double value) {
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, "", false, false});
  }
  std::vector<StabilityRow> take() { return std::move(rows_); }

 private:
  std::vector<StabilityRow> rows_;
};

const Eigen::Vector3d kBoxSize(0.3, 0.3, 0.2);
constexpr double kStackDrift = 0.01;  // [m] the top box's claimed largest displacement (10 and 20 boxes)
constexpr int kPerturbedStarts = 8;   // the stack of 20 also from this many starts moved by k·1e-12 m

struct StackResult {
  double drift = 0.0;        // [m] the top box's largest displacement from its start
  double penetration = 0.0;  // [m] the deepest penetration
  double slip = 0.0;         // [m] the largest slip at an interface
};

// Boxes of `masses` stacked on the ground from below, over `duration`: the top box's largest displacement, the
// deepest penetration, and the largest slip at an interface (the horizontal offset of a box's bottom-face
// centre from the top-face centre of the box below, or from the ground point under the first box's start;
// the boxes' tilts move it only to second order). `offset` moves box i by offset·(i mod 3) along x at the
// start (a start that differs from the aligned one by rounding-sized amounts).
StackResult stack(const std::vector<double>& masses, IntegratorType type, double duration, double offset = 0.0) {
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
  std::vector<BodyDefinition> bodies;
  for (std::size_t i = 0; i < masses.size(); ++i) {
    bodies.push_back(body(MassProperties::box(masses[i], kBoxSize), Eigen::Vector3d(offset * double(i % 3), 0, 0.1 + 0.2 * i),
                          Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
    setup.bodies.push_back(shape(ShapeType::kBox, kBoxSize, 0.5, 0.0));
  }
  rigid_body::Scene scene = makeScene(bodies, setup, type, 1e-3, ContactSettings());
  StackResult result;
  const Eigen::Vector3d half_height(0.0, 0.0, 0.5 * kBoxSize.z());
  for (std::int64_t i = 0, n = stepsFor(duration, 1e-3); i < n; i += 100) {
    scene.step(100);
    const State& top = scene.state(masses.size() - 1);
    result.drift = std::max(result.drift, (top.p_WB - scene.initialState(masses.size() - 1).p_WB).norm());
    if (!(result.drift < 1.0)) break;  // fallen
    Eigen::Vector3d below = scene.initialState(0).p_WB - half_height;
    for (std::size_t b = 0; b < masses.size(); ++b) {
      const State& box = scene.state(b);
      result.slip = std::max(result.slip, (box.p_WB - box.q_WB * half_height - below).head<2>().norm());
      below = box.p_WB + box.q_WB * half_height;
    }
  }
  result.penetration = scene.contactStatistics().max_penetration;
  return result;
}

void stacks(CaseRows& rows, bool quick) {
  const double duration = quick ? 2.0 : 10.0;
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    for (std::size_t height : {10u, 20u, 50u}) {
      const std::string name = "contact_stack_" + std::to_string(height);
      const StackResult result = stack(std::vector<double>(height, 1.0), type, duration);
      if (height <= 20) {
        rows.claim(name, type, "largest top-box displacement [m]", result.drift, "<=", kStackDrift);
      } else {
        rows.report(name, type, "largest top-box displacement [m]", result.drift);
      }
      rows.report(name, type, "deepest penetration [m]", result.penetration);
      rows.report(name, type, "largest slip at an interface [m]", result.slip);
    }
    if (quick) continue;
    // How much of the stack of 20's drift is the draw of rounding: the same stack from starts moved by
    // k·1e-12 m (k = 1 … kPerturbedStarts; box i by k·1e-12·(i mod 3)), reported.
    double largest = 0.0;
    int over = 0;
    for (int k = 1; k <= kPerturbedStarts; ++k) {
      const double drift = stack(std::vector<double>(20, 1.0), type, duration, 1e-12 * k).drift;
      largest = std::max(largest, drift);
      over += drift > kStackDrift ? 1 : 0;
    }
    const std::string starts = std::to_string(kPerturbedStarts);
    rows.report("contact_stack_20", type, "largest top-box displacement over " + starts + " starts moved by <= 2e-11 m [m]",
                largest);
    rows.report("contact_stack_20", type, "of those " + starts + " starts, top box beyond 1 cm", over);
  }
}

void massRatios(CaseRows& rows, bool quick) {
  const double duration = quick ? 1.0 : 5.0;
  const IntegratorType type = IntegratorType::kRk4;
  for (double ratio : {100.0, 1000.0}) {
    for (bool heavy_on_top : {true, false}) {
      const std::string name = std::string("contact_mass_ratio_") + (ratio == 100.0 ? "100" : "1000") +
                               (heavy_on_top ? "_heavy_on_light" : "_light_on_heavy");
      const StackResult result = stack(heavy_on_top ? std::vector<double>{1.0, ratio} : std::vector<double>{ratio, 1.0},
                                       type, duration);
      if (ratio == 100.0) {
        rows.claim(name, type, "deepest penetration [m]", result.penetration, "<=", 1e-3);
        rows.claim(name, type, "largest top-box displacement [m]", result.drift, "<=", 1e-3);
      } else {
        rows.report(name, type, "deepest penetration [m]", result.penetration);
        rows.report(name, type, "largest top-box displacement [m]", result.drift);
      }
    }
  }
}

// A sphere (r = 5 cm) shot down at a 1 cm plate at `speed`, h = 1 ms: where its centre ends, above the plate's top.
void tunneling(CaseRows& rows) {
  const double radius = 0.05;
  for (double speed : {10.0, 100.0, 1000.0}) {
    for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
      CollisionShape plate = shape(ShapeType::kBox, Eigen::Vector3d(1.0, 1.0, 0.01), 0.5, 0.0);
      plate.name = "plate";
      ContactSetup setup;
      setup.environment = {plate};
      setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, 0.0)};
      rigid_body::Scene scene = makeScene({body(MassProperties::sphere(0.5, radius), Eigen::Vector3d(0, 0, 2.0),
                                                Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -speed),
                                                Eigen::Vector3d::Zero(), kDown)},
                                          setup, type, 1e-3, ContactSettings());
      scene.step(stepsFor(0.5, 1e-3));
      const std::string name = "contact_tunneling_" + rigid_body::formatNumber(speed, 4) + "_m_s";
      rows.claim(name, type, "centre height above the plate's top [m]", scene.state().p_WB.z() - 0.005, ">=",
                 radius - 1e-3);
    }
  }
}

// A box on an incline at exactly its friction angle (tan θ = μ): the rigid model with Coulomb friction is
// at the limit; what the solver does is reported.
void frictionAngle(CaseRows& rows, bool quick) {
  const double mu = 0.5, theta = std::atan(mu), duration = quick ? 1.0 : 5.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  const IntegratorType type = IntegratorType::kRk4;
  ContactSetup setup;
  setup.environment = {plane(q * Eigen::Vector3d::UnitZ(), mu)};
  const Eigen::Vector3d size(0.2, 0.2, 0.1);
  setup.bodies = {shape(ShapeType::kBox, size, mu, 0.0)};
  const Eigen::Vector3d start = 0.05 * (q * Eigen::Vector3d::UnitZ());
  rigid_body::Scene scene = makeScene({body(MassProperties::box(1.0, size), start, q, Eigen::Vector3d::Zero(),
                                            Eigen::Vector3d::Zero(), kDown)},
                                      setup, type, 1e-3, ContactSettings());
  scene.step(stepsFor(duration, 1e-3));
  rows.report("contact_friction_angle", type, "distance slid [m]", (scene.state().p_WB - start).norm());
}

// A sphere spun at 100 rad/s about a horizontal axis and set on the ground: it skids, friction μ M g
// speeding it up (a = μ g) and slowing its spin (α = μ M g r / I), until v = ω r at t = 2 ω₀ r/(7 μ g); it then
// rolls at v = (2/7) ω₀ r. The rolling speed follows from the angular momentum about the contact point, which
// impulses at that point keep by construction: an invariant. When the skid ends is the accuracy claim.
void spinningBall(CaseRows& rows) {
  const double radius = 0.1, w0 = 100.0, mu = 0.5, dt = 1e-3;
  for (IntegratorType type : kMethods) {
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), mu)};
    setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), mu, 0.0)};
    const MassProperties ball = MassProperties::sphere(1.0, radius);
    rigid_body::Scene scene = makeScene({body(ball, Eigen::Vector3d(0, 0, radius), Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d(0, w0, 0), kDown)},
                                        setup, type, dt, ContactSettings());
    double rolling_from = -1.0;
    for (std::int64_t i = 1, n = stepsFor(1.0, dt); i <= n; ++i) {
      scene.step(1);
      const Eigen::Vector3d v = rigid_body::linearVelocity(ball, scene.state());
      const Eigen::Vector3d w = rigid_body::angularVelocity(ball, scene.state());
      const double slip = (v + w.cross(Eigen::Vector3d(0, 0, -radius))).norm();
      if (rolling_from < 0.0 && slip <= 1e-9 * w0 * radius) rolling_from = static_cast<double>(i) * dt;
    }
    const double skid_end = 2.0 * w0 * radius / (7.0 * mu * kG);
    rows.claim("contact_spin_100_rad_s", type, "relative error of the time rolling begins",
               std::abs(rolling_from - skid_end) / skid_end, "<=", 1e-2);
    const double expected = 2.0 / 7.0 * w0 * radius;
    rows.invariant("contact_spin_100_rad_s", type, "relative error of the rolling speed (L about the contact point)",
                   std::abs(scene.state().P_W.norm() - expected) / expected, 1e-9);
  }
}

// Painlevé's case: a rod sliding on its lower end with friction μ = 2, more than the rigid model can take
// consistently (no solution, or two). The velocity-level solver always returns one: the end sticks by a
// tangential impulse (Stewart's "impact without collision"). Claimed: no energy is gained.
void painleve(CaseRows& rows) {
  const double r = 0.02, l = 1.0, m = 1.0, mu = 2.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-60.0 * kPi / 180.0, Eigen::Vector3d::UnitY()));  // 60° from vertical
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), mu)};
    setup.bodies = {shape(ShapeType::kCapsule, Eigen::Vector3d(r, l, 0), mu, 0.0)};
    const MassProperties rod = MassProperties::cylinder(m, r, l + 2.0 * r);
    rigid_body::Scene scene = makeScene({body(rod, Eigen::Vector3d(0, 0, 0.5 * l * std::abs(axis.z()) + r), q,
                                              Eigen::Vector3d(-3.0, 0, 0), Eigen::Vector3d::Zero(), kDown)},
                                        setup, type, 1e-3, ContactSettings());
    const auto energy = [&] {
      return rigid_body::kineticEnergy(rod, scene.state()) +
             rigid_body::potentialEnergy(rod, scene.model().forces, scene.state());
    };
    const double initial = energy();
    double gained = 0.0;
    for (int i = 0; i < 1000; ++i) {
      scene.step(1);
      gained = std::max(gained, energy() - initial);
    }
    rows.claim("contact_painleve", type, "largest energy gained [J]", gained, "<=", 1e-6 * initial);
    rows.report("contact_painleve", type, "speed after 1 s [m/s]", scene.state().P_W.norm() / m);
  }
}

// N bodies of mixed shapes dropped in a 2 m bin; semi-implicit Euler at 2 ms, as a game engine would run it.
void pile(CaseRows& rows, bool quick) {
  const std::size_t count = quick ? 100 : 1000;
  const double duration = quick ? 2.0 : 5.0, dt = 2e-3;
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
  for (int side = 0; side < 4; ++side) {
    CollisionShape wall = shape(ShapeType::kBox, side < 2 ? Eigen::Vector3d(0.1, 2.2, 3.0) : Eigen::Vector3d(2.0, 0.1, 3.0), 0.5, 0.0);
    wall.pose.translation() = side < 2 ? Eigen::Vector3d(side == 0 ? 1.05 : -1.05, 0, 1.5)
                                       : Eigen::Vector3d(0, side == 2 ? 1.05 : -1.05, 1.5);
    setup.environment.push_back(wall);
  }
  std::vector<BodyDefinition> bodies;
  double potential = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d p(-0.75 + 0.25 * static_cast<double>(i % 7), -0.75 + 0.25 * static_cast<double>((i / 7) % 7),
                            0.3 + 0.25 * static_cast<double>(i / 49));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3 * static_cast<double>(i % 5), Eigen::Vector3d(1, 1, 0).normalized()));
    switch (i % 3) {
      case 0:
        bodies.push_back(body(MassProperties::box(0.5, Eigen::Vector3d(0.15, 0.1, 0.08)), p, q, Eigen::Vector3d::Zero(),
                              Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kBox, Eigen::Vector3d(0.15, 0.1, 0.08), 0.5, 0.0));
        break;
      case 1:
        bodies.push_back(body(MassProperties::sphere(0.5, 0.06), p, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(0.06, 0, 0), 0.5, 0.0));
        break;
      default:
        bodies.push_back(body(MassProperties::cylinder(0.5, 0.05, 0.12), p, q, Eigen::Vector3d::Zero(),
                              Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kCylinder, Eigen::Vector3d(0.05, 0.12, 0), 0.5, 0.0));
    }
    potential += 0.5 * kG * p.z();
  }
  const IntegratorType type = IntegratorType::kSemiImplicitEuler;
  rigid_body::Scene scene = makeScene(bodies, setup, type, dt, ContactSettings());
  const double start = cpuSeconds();
  const std::int64_t steps = stepsFor(duration, dt);
  scene.step(steps);
  const double cpu = cpuSeconds() - start;
  double kinetic = 0.0;
  for (std::size_t i = 0; i < count; ++i) kinetic += rigid_body::kineticEnergy(scene.model(i).mass, scene.state(i));
  // The deepest penetration now: a fresh step at rest measures it (statistics since the start include the drop).
  const std::string name = "contact_pile_" + std::to_string(count);
  rows.claim(name, type, "kinetic energy at the end / potential energy at the start", kinetic / potential, "<=", 1e-2);
  rows.report(name, type, "deepest penetration during the drop [m]", scene.contactStatistics().max_penetration);
  rows.report(name, type, "CPU per body and step [us]", 1e6 * cpu / (static_cast<double>(steps) * count));
}

// A box resting on the ground for 10⁶ steps of 1 ms (10⁵ quick): no creep, no energy gained.
void longRest(CaseRows& rows, bool quick) {
  const std::int64_t steps = quick ? 100000 : 1000000;
  for (IntegratorType type : kMethods) {
    const Eigen::Vector3d size(0.4, 0.2, 0.1);
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
    setup.bodies = {shape(ShapeType::kBox, size, 0.5, 0.0)};
    const MassProperties box = MassProperties::box(1.0, size);
    rigid_body::Scene scene = makeScene({body(box, Eigen::Vector3d(0, 0, 0.05), Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
                                        setup, type, 1e-3, ContactSettings());
    const auto energy = [&] {
      return rigid_body::kineticEnergy(box, scene.state()) + rigid_body::potentialEnergy(box, scene.model().forces, scene.state());
    };
    const double initial = energy();
    scene.step(steps);
    rows.claim("contact_long_rest", type, "displacement [m]", (scene.state().p_WB - Eigen::Vector3d(0, 0, 0.05)).norm(),
               "<=", 1e-6);
    rows.claim("contact_long_rest", type, "energy gained [J]", energy() - initial, "<=", 1e-9);
  }
}

}  // namespace

std::vector<StabilityRow> runContactStability(bool quick) {
  CaseRows rows;
  stacks(rows, quick);
  massRatios(rows, quick);
  tunneling(rows);
  frictionAngle(rows, quick);
  spinningBall(rows);
  painleve(rows);
  pile(rows, quick);
  longRest(rows, quick);
  return rows.take();
}

std::vector<std::pair<std::string, std::string>> contactCaseDescriptions(bool quick) {
  const std::string stack_time = quick ? "2 s" : "10 s";
  std::vector<std::pair<std::string, std::string>> cases;
  for (const char* height : {"10", "20", "50"}) {
    cases.push_back({std::string("contact_stack_") + height,
                     std::string("a stack of ") + height + " boxes (0.3 x 0.3 x 0.2 m, 1 kg, friction 0.5) on the ground, h = 1 ms, " +
                         stack_time + "; displacement of the top box claimed <= 1 cm for 10 and 20, reported for 50" +
                         "; reported: the largest slip at an interface (a box's bottom-face centre against the top-face "
                         "centre of the box below, horizontally)" +
                         (std::string(height) == "20" && !quick
                              ? "; also reported: the same stack from " + std::to_string(kPerturbedStarts) +
                                    " starts moved by k 1e-12 m (box i by k 1e-12 (i mod 3) along x, k = 1 ... " +
                                    std::to_string(kPerturbedStarts) + "), how far its top box goes then"
                              : "")});
  }
  const std::string ratio_time = quick ? "1 s" : "5 s";
  for (const char* name : {"contact_mass_ratio_100_heavy_on_light", "contact_mass_ratio_100_light_on_heavy",
                           "contact_mass_ratio_1000_heavy_on_light", "contact_mass_ratio_1000_light_on_heavy"}) {
    cases.push_back({name, "two boxes stacked on the ground with masses 1 and 100 (or 1000) kg, rk4, h = 1 ms, " + ratio_time +
                               "; 1:100 claims penetration and displacement <= 1 mm, 1:1000 is reported"});
  }
  for (const char* speed : {"10", "100", "1000"}) {
    cases.push_back({std::string("contact_tunneling_") + speed + "_m_s",
                     std::string("a sphere (r = 5 cm) shot at ") + speed +
                         " m/s down onto a 1 cm plate, h = 1 ms: it must end on the plate (centre >= r - 1 mm above it)"});
  }
  cases.push_back({"contact_friction_angle", std::string("a box on an incline at exactly its friction angle (tan theta = mu = 0.5), ") +
                                                 (quick ? "1 s" : "5 s") + "; reported: the rigid Coulomb model is at its limit"});
  cases.push_back({"contact_spin_100_rad_s", "a sphere (r = 0.1 m) spun at 100 rad/s about a horizontal axis, set on the ground (mu = 0.5): it skids until 2 w0 r/(7 mu g) = 0.58 s (claimed to 1 %), then rolls at (2/7) w0 r (an invariant: L about the contact point); 1 s, every method"});
  cases.push_back({"contact_painleve", "Painleve's case: a capsule rod at 60 deg from the vertical, sliding at 3 m/s on its lower end with mu = 2 (the rigid model has no consistent solution); the solver sticks the end by a tangential impulse; claimed: no energy gained in 1 s"});
  cases.push_back({std::string("contact_pile_") + (quick ? "100" : "1000"),
                   std::string(quick ? "100" : "1000") + " boxes, spheres and cylinders dropped into a 2 m bin, semi-implicit Euler at 2 ms, " +
                       (quick ? "2 s" : "5 s") + "; claimed: settled (kinetic energy <= 1 % of the potential energy at the start); penetration and cost reported"});
  cases.push_back({"contact_long_rest", std::string("a box resting on the ground for ") + (quick ? "1e5" : "1e6") +
                                            " steps of 1 ms: displacement <= 1 um and no energy gained (<= 1e-9 J)"});
  return cases;
}

bool drawContactFigures(const Options& options, const std::vector<ContactRow>& rows) {
  bool all = true;
  std::set<std::string> scenes;
  for (const ContactRow& row : rows) scenes.insert(row.scene);
  for (const std::string& scene : scenes) {
    // One data block per method and setting, for gnuplot's `index`.
    const std::string data = options.out + "/contact_" + scene + ".dat";
    std::ofstream out(data);
    std::vector<std::string> titles;
    for (IntegratorType type : kMethods) {
      for (const Setting& setting : kSettings) {
        bool any = false;
        for (const ContactRow& row : rows) {
          if (row.scene != scene || row.integrator != rigid_body::integratorName(type) || row.setting != setting.name) continue;
          out << row.cpu_per_second << " " << std::max(row.error, 1e-17) << "\n";
          any = true;
        }
        if (!any) continue;
        out << "\n\n";
        titles.push_back(rigid_body::integratorName(type) + ", " + setting.name);
      }
    }
    out.close();
    const std::string script = options.out + "/contact_" + scene + ".gp";
    std::ofstream gp(script);
    gp << "set terminal pngcairo size 900,560 enhanced font 'DejaVu Sans,10'\n"
       << "set output '" << options.out << "/contact_" << scene << ".png'\n"
       << "set logscale xy\nset grid\nset key outside right top\nset format y '10^{%L}'\nset format x '10^{%L}'\n"
       << "set xlabel 'CPU time per simulated second [s]'\nset ylabel 'error'\nset title 'contact: " << scene << "'\n"
       << "plot ";
    for (std::size_t i = 0; i < titles.size(); ++i) {
      gp << (i ? ", " : "") << "'" << data << "' index " << i << " with linespoints title '" << titles[i] << "'";
    }
    gp << "\n";
    gp.close();
    const bool drawn = std::system(("gnuplot '" + script + "' 2>/dev/null").c_str()) == 0;
    if (drawn) {
      std::remove(script.c_str());
      std::remove(data.c_str());
    }
    all = all && drawn;
  }
  return all;
}

void writeContactSection(std::ostream& md, const std::vector<ContactRow>& rows, bool figures) {
  md << "\n## Contact\n\nThe closed-form contact scenes of docs/references.md §4, each run with explicit Euler, "
        "semi-implicit Euler, symplectic splitting and rk4 under three contact settings (impacts located in time "
        "or resolved at the step's end; 20 or 5 solver iterations) and swept over h; error against CPU time per "
        "simulated second (the CPU time over repeats of at least 10 ms). File: `contact.csv`.\n\n";
  std::set<std::string> scenes;
  std::map<std::string, std::string> metrics;
  for (const ContactRow& row : rows) scenes.insert(row.scene), metrics[row.scene] = row.metric;
  if (figures) {
    for (const std::string& scene : scenes) md << "![" << scene << "](contact_" << scene << ".png)\n";
    md << "\n";
  }
  md << "### At h = 1 ms\n\nError (and CPU time per simulated second) per scene, method and setting.\n\n"
        "| scene | metric | method | ";
  for (const Setting& setting : kSettings) md << setting.name << " | ";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < kSettings.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& scene : scenes) {
    for (IntegratorType type : kMethods) {
      md << "| " << scene << " | " << metrics[scene] << " | " << rigid_body::integratorName(type) << " | ";
      for (const Setting& setting : kSettings) {
        for (const ContactRow& row : rows) {
          if (row.scene == scene && row.integrator == rigid_body::integratorName(type) && row.setting == setting.name &&
              row.dt == 1e-3) {
            md << fmt(row.error, 2) << " (" << fmt(row.cpu_per_second * 1e3, 2) << " ms) ";
          }
        }
        md << "| ";
      }
      md << "\n";
    }
  }
  // Which settings when: the cheapest run (per simulated second) that reaches each error, per scene.
  md << "\n### Which contact settings when\n\nFor each scene and target error, the cheapest method, setting and step "
        "that reach it, computed from the runs above (\"-\": none of them does).\n\n| scene | ";
  const std::vector<double> targets = {1e-2, 1e-4, 1e-6};
  for (double target : targets) md << "error <= " << fmt(target) << " | ";
  md << "\n|---|";
  for (std::size_t i = 0; i < targets.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& scene : scenes) {
    md << "| " << scene << " | ";
    for (double target : targets) {
      const ContactRow* best = nullptr;
      for (const ContactRow& row : rows) {
        if (row.scene != scene || !(row.error <= target)) continue;
        if (best == nullptr || row.cpu_per_second < best->cpu_per_second) best = &row;
      }
      if (best == nullptr) {
        md << "- | ";
      } else {
        md << best->integrator << ", " << best->setting << ", h = " << fmt(best->dt * 1e3, 2) << " ms ("
           << fmt(best->cpu_per_second * 1e3, 2) << " ms/s) | ";
      }
    }
    md << "\n";
  }
  md << "\n";
}

}  // namespace accuracy_report
