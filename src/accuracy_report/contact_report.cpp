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
#include "contact_scene.hpp"
#include "scenes.hpp"

namespace accuracy_report {


namespace {

// The CPU time of one measurement is taken over repeats until at least this much has passed [s].
constexpr double kMinMeasuredCpu = 0.01;

struct Setting {
  std::string name;
  bool event_location;
  int iterations;
};
const std::vector<Setting> kSettings = {{"located, 20 iterations", true, 20},
                                        {"at step end, 20 iterations", false, 20},
                                        {"located, 5 iterations", true, 5}};

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
