#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "contact_report.hpp"
#include "simbenchmark.hpp"
#include "measurements.hpp"
#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/number_format.hpp"

namespace accuracy_report {

using namespace rigid_body;

namespace {

std::string fmt(double value, int precision = 3) { return formatNumber(value, precision); }

std::string integratorList() {
  std::string list;
  for (IntegratorType type : allIntegrators()) list += (list.empty() ? "" : " ") + integratorName(type);
  return list;
}

// Runs a gnuplot script written to DIR/NAME.gp; the figure is DIR/NAME.png.
bool plot(const std::string& dir, const std::string& name, const std::string& body) {
  const std::string script = dir + "/" + name + ".gp";
  std::ofstream gp(script);
  gp << "set terminal pngcairo size 900,620 enhanced font 'DejaVu Sans,10'\n"
     << "set output '" << dir << "/" << name << ".png'\n"
     << "set datafile separator ','\nset key outside right top\nset grid\n"
     << "methods = '" << integratorList() << "'\n"
     << body;
  gp.close();
  const bool drawn = std::system(("gnuplot '" + script + "'").c_str()) == 0;
  if (drawn) std::remove(script.c_str());  // keep the script only when it failed, to debug it
  return drawn;
}

// A floor for log axes: errors of exactly 0 (exact methods) are drawn at 1e-17.
const char* kFloor = "(column(c) > 1e-17 ? column(c) : 1e-17)";

void writeIntroduction(std::ostream& md, const Options& options, const Sweep& sweep, const std::string& machine) {
  md << "# rigid_body_sim accuracy report\n\n"
     << "Written by `rosrun rigid_body_sim accuracy_report" << (options.quick ? " --quick" : "") << "` ("
     << (options.quick ? "quick" : "full") << " run). Machine: " << machine << ".\n\n"
     << "Errors are at the final time against the closed forms of `references.hpp` (the off-centre push, which has "
        "none: Euler's equations in body axes integrated by a separate RK4 at h = 10 µs); CPU time is the median of "
     << sweep.repeats << " in-process repeats after a warm-up (Hairer–Wanner convention), each repeat running the "
        "scene until at least 10 ms of CPU time have passed (clock: " << clockDescription() << "). dopri5 is swept over its "
        "tolerance (1e-4 … 1e-12) at an output step of 10 ms. Files: `work_precision.csv`, `order.csv`, "
        "`control_rate.csv`, `error_growth.csv`, `stability.csv`.\n\n";
}

void writeWorkPrecision(std::ostream& md, const Results& results) {
  md << "## Work precision\n\nError at T with each method at h = 5 ms (dopri5: tolerance 1e-8) and its CPU time per "
        "simulated second.\n\n| scene | ";
  for (IntegratorType type : allIntegrators()) md << integratorName(type) << " | ";
  md << "\n|---|";
  for (size_t i = 0; i < allIntegrators().size(); ++i) md << "---|";
  md << "\n";
  for (const Scene& scene : results.scenes) {
    md << "| " << scene.name << " (" << (scene.metric == ErrorMetric::kPosition ? "m" : "rad") << ") | ";
    for (IntegratorType type : allIntegrators()) {
      const auto& cell = results.at_control_step.at(scene.name).at(integratorName(type));
      md << fmt(cell.first, 2) << " in " << fmt(cell.second * 1e3, 2) << " ms | ";
    }
    md << "\n";
  }
  if (results.figures) {
    md << "\n";
    for (const Scene& scene : results.scenes) md << "![" << scene.name << "](work_precision_" << scene.name << ".png)\n";
  }
}

void writeOrder(std::ostream& md, const Results& results) {
  md << "\n## Order\n\nLeast-squares slope of log error against log h, orientation error at T = 2 s on the asymmetric "
        "body (h from 20 ms, or 100 ms for the fourth-order methods, halved three times).\n\n"
        "| integrator | nominal | fitted |\n|---|---|---|\n";
  for (const auto& fitted : results.fitted_orders) {
    md << "| " << fitted.first << " | " << nominalOrder(integratorFromName(fitted.first)) << " | "
       << fmt(fitted.second) << " |\n";
  }
  if (results.figures) md << "\n![order](order.png)\n";
}

void writeControlRate(std::ostream& md, const Results& results) {
  md << "\n## At control rates\n\nOrientation error after 1 s on the asymmetric body, and CPU time per tick (one step).\n\n"
        "| integrator | 1 ms | 2 ms | 5 ms | 10 ms |\n|---|---|---|---|---|\n";
  for (IntegratorType type : allIntegrators()) {
    md << "| " << integratorName(type) << " | ";
    for (double h : kControlSteps) {
      const auto& cell = results.control.at(integratorName(type)).at(h);
      md << fmt(cell.first, 2) << " / " << fmt(cell.second * 1e9, 3) << " ns | ";
    }
    md << "\n";
  }
  if (results.figures) md << "\n![control rate](control_rate.png)\n";
}

void writeLongRun(std::ostream& md, const Results& results, const Sweep& sweep) {
  md << "\n## Long run\n\n" << fmt(static_cast<double>(sweep.long_run_steps), 2)
     << " steps of 50 ms on the asymmetric body (torque-free).\n\n"
        "| integrator | max \\|dE/E\\| | drift of dE/E [1/s] (2nd half) | max \\|dL\\|/\\|L\\| | max \\|\\|q\\| - 1\\| |\n|---|---|---|---|---|\n";
  for (IntegratorType type : allIntegrators()) {
    const LongRunSummary& s = results.long_run.at(integratorName(type));
    md << "| " << integratorName(type) << " | " << fmt(s.max_energy_error, 2) << " | " << fmt(s.drift, 2) << " | "
       << fmt(s.max_L_error, 2) << " | " << fmt(s.max_norm_error, 2) << " |\n";
  }
  if (results.figures) md << "\n![error growth](error_growth.png)\n";
}

}  // namespace

std::pair<int, int> countClaims(const std::vector<StabilityRow>& rows) {
  int claims = 0, met = 0;
  for (const StabilityRow& row : rows) {
    if (!row.claimed || row.threshold.empty() || row.invariant) continue;
    ++claims;
    met += row.pass ? 1 : 0;
  }
  return {claims, met};
}

namespace {

void writeStability(std::ostream& md, const Results& results, bool quick) {
  const std::pair<int, int> claims = countClaims(results.stability);
  int invariants = 0, invariants_held = 0;
  for (const StabilityRow& row : results.stability) {
    if (!row.invariant) continue;
    ++invariants;
    invariants_held += row.pass ? 1 : 0;
  }
  md << "\n## Stiff and extreme suite\n\n" << claims.second << " of " << claims.first
     << " claimed accuracy and stability thresholds met. A value in **bold** is a claimed threshold the method "
        "missed; `claimed` says whether the method claims the threshold (the others are reported). Invariants "
        "(properties every method keeps by construction: |q| = 1 after its normalisation, world L without torque, "
        "a finite result, the energy bounds of a unit q) are checked apart and not counted as claims: "
     << invariants_held << " of " << invariants << " held.\n\n";
  std::vector<std::pair<std::string, std::string>> descriptions = stabilityCaseDescriptions(quick);
  for (const auto& contact : contactCaseDescriptions(quick)) descriptions.push_back(contact);
  for (const auto& description : descriptions) {
    md << "### " << description.first << "\n\n" << description.second << ".\n\n| integrator | metric | value | threshold | claimed | pass |\n|---|---|---|---|---|---|\n";
    for (const StabilityRow& row : results.stability) {
      if (row.case_name != description.first || row.invariant) continue;
      const bool missed = row.claimed && !row.threshold.empty() && !row.pass;
      md << "| " << row.integrator << " | " << row.metric << " | " << (missed ? "**" : "") << fmt(row.value, 3)
         << (missed ? "**" : "") << " | " << (row.threshold.empty() ? "-" : row.threshold) << " | "
         << (row.claimed ? "yes" : "no") << " | " << (row.threshold.empty() ? "-" : row.pass ? "yes" : "no") << " |\n";
    }
    md << "\n";
  }
  md << "### Invariants\n\n| case | integrator | invariant | value | bound | held |\n|---|---|---|---|---|---|\n";
  for (const StabilityRow& row : results.stability) {
    if (!row.invariant) continue;
    md << "| " << row.case_name << " | " << row.integrator << " | " << row.metric << " | " << fmt(row.value, 3) << " | "
       << row.threshold << " | " << (row.pass ? "yes" : "**no**") << " |\n";
  }
  md << "\n";
}

// The methods whose row of `case_name` with a metric starting `metric` has value `wanted`, by name.
std::string methodsWith(const std::vector<StabilityRow>& rows, const std::string& case_name, const std::string& metric,
                        double wanted) {
  std::string names;
  for (const StabilityRow& row : rows) {
    if (row.case_name == case_name && row.metric.rfind(metric, 0) == 0 && row.value == wanted) {
      names += (names.empty() ? "" : ", ") + row.integrator;
    }
  }
  return names.empty() ? "none" : names;
}

// "Which integrator when": every sentence is computed from this run's tables; what they do not measure is
// not said.
void writeRecommendations(std::ostream& md, const Results& results) {
  md << "## Which integrator when\n\n";
  constexpr double kTarget = 1e-6;  // orientation error after 1 s [rad]
  std::string cheapest_tick, cheapest_second;
  double tick_cost = INFINITY, second_cost = INFINITY;
  for (const auto& method : results.control) {
    for (const auto& cell : method.second) {
      const double error = cell.second.first, per_tick = cell.second.second, per_second = per_tick / cell.first;
      if (!(error <= kTarget)) continue;
      const std::string what = method.first + " at h = " + fmt(cell.first * 1e3) + " ms";
      if (per_tick < tick_cost) tick_cost = per_tick, cheapest_tick = what;
      if (per_second < second_cost) second_cost = per_second, cheapest_second = what;
    }
  }
  if (!cheapest_tick.empty()) {
    md << "* Orientation error <= " << fmt(kTarget) << " rad after 1 s at a control step of 1-10 ms (asymmetric "
       << "body, input unchanged): cheapest per tick **" << cheapest_tick << "** (" << fmt(tick_cost * 1e9)
       << " ns), cheapest per simulated second **" << cheapest_second << "** (" << fmt(second_cost * 1e6)
       << " us).\n";
  }
  for (double h : kControlSteps) {
    std::string best;
    double best_error = INFINITY;
    for (const auto& method : results.control) {
      if (method.second.at(h).first < best_error) best_error = method.second.at(h).first, best = method.first;
    }
    md << "* Most accurate at h = " << fmt(h * 1e3) << " ms: **" << best << "** (" << fmt(best_error, 2) << " rad).\n";
  }
  std::string flattest, drifting;
  double flattest_energy = INFINITY;
  for (const auto& method : results.long_run) {
    if (method.second.max_energy_error < flattest_energy) flattest_energy = method.second.max_energy_error, flattest = method.first;
    if (!(method.second.max_energy_error <= 0.1)) drifting += (drifting.empty() ? "" : ", ") + method.first;
  }
  md << "* Smallest energy error over the long run: **" << flattest << "** (max |dE/E| = " << fmt(flattest_energy, 2)
     << "); energy error above 10 %: " << (drifting.empty() ? "none" : drifting) << ".\n";
  std::string stable_name;
  double stable_value = 0;
  for (const StabilityRow& row : results.stability) {
    // dopri5 chooses its own internal steps: the fixed-step methods compete here.
    if (row.case_name == "high_spin" && row.metric.rfind("largest stable", 0) == 0 && row.value > stable_value &&
        !integratorInfo(integratorFromName(row.integrator)).adaptive) {
      stable_value = row.value, stable_name = row.integrator;
    }
  }
  if (!stable_name.empty()) {
    md << "* Largest stable |w|h of a fixed-step method on the spinning body: **" << stable_name << "** ("
       << fmt(stable_value) << ").\n";
  }
  md << "* Stiff damping (c/m = 1000/s at h = 10 ms): monotone decay with "
     << methodsWith(results.stability, "stiff_damping", "monotone decay", 1.0) << "; not with "
     << methodsWith(results.stability, "stiff_damping", "monotone decay", 0.0) << ".\n";
}

}  // namespace

bool drawFigures(const Options& options, const std::vector<Scene>& scenes) {
  bool figures = true;
  for (const Scene& scene : scenes) {
    std::ostringstream body;
    body << "set title \"" << scene.description << "\"\nset logscale xy\nset format xy '10^{%L}'\n"
         << "set xlabel 'CPU time per simulated second [s]'\nset ylabel '" << metricLabel(scene.metric)
         << " at T (0 drawn at 1e-17)'\n"
         << "c = 8\nplot for [m in methods] '" << options.out << "/work_precision.csv' using "
         << "(strcol(1) eq '" << scene.name << "' && strcol(2) eq m ? column(7) : NaN):" << kFloor
         << " with linespoints title m noenhanced\n";
    figures = plot(options.out, "work_precision_" + scene.name, body.str()) && figures;
  }
  figures = plot(options.out, "order",
                 std::string("set title 'Order: error at T = 2 s on the asymmetric body against h'\n"
                             "set logscale xy\nset format xy '10^{%L}'\nset xlabel 'h [s]'\n"
                             "set ylabel 'orientation error [rad]'\nc = 4\n"
                             "plot for [m in methods] '") + options.out + "/order.csv' using (strcol(1) eq m ? column(3) : NaN):" +
                     kFloor + " with linespoints title m noenhanced, 1e-1*(x/0.02) title 'slope 1' dt 2 lc 'gray', " +
                     "1e-2*(x/0.02)**2 title 'slope 2' dt 3 lc 'gray', 1e-6*(x/0.1)**4 title 'slope 4' dt 4 lc 'gray'\n") &&
            figures;
  figures = plot(options.out, "control_rate",
                 std::string("set title 'Control rate: error after 1 s (asymmetric body) at h = 1, 2, 5, 10 ms'\n"
                             "set logscale xy\nset format xy '10^{%L}'\nset xlabel 'CPU time per tick [s]'\n"
                             "set ylabel 'orientation error after 1 s [rad]'\nc = 3\n"
                             "plot for [m in methods] '") + options.out + "/control_rate.csv' using (strcol(1) eq m ? column(4) : NaN):" +
                     kFloor + " with linespoints title m noenhanced\n") &&
            figures;
  figures = plot(options.out, "error_growth",
                 std::string("set terminal pngcairo size 900,1000 enhanced font 'DejaVu Sans,10'\nset output '") +
                     options.out + "/error_growth.png'\nset multiplot layout 3,1 title 'Long run: h = 50 ms on the asymmetric body'\n"
                     "set logscale y\nset format y '10^{%L}'\nset xlabel 't [s]'\n"
                     "set ylabel '|dE/E|'\nplot for [m in methods] '" + options.out +
                     "/error_growth.csv' using (strcol(1) eq m ? column(2) : NaN):(abs(column(3)) > 1e-17 ? abs(column(3)) : 1e-17) with lines title m noenhanced\n"
                     "set ylabel '|dL|/|L| (exactly 0: drawn at 1e-17)'\nset yrange [1e-18:1e-15]\nplot for [m in methods] '" + options.out +
                     "/error_growth.csv' using (strcol(1) eq m ? column(2) : NaN):(column(4) > 1e-17 ? column(4) : 1e-17) with lines title m noenhanced\n"
                     "set autoscale y\nset ylabel '||q| - 1|'\nplot for [m in methods] '" + options.out +
                     "/error_growth.csv' using (strcol(1) eq m ? column(2) : NaN):(column(5) > 1e-17 ? column(5) : 1e-17) with lines title m noenhanced\n"
                     "unset multiplot\n") &&
            figures;
  return figures;
}

void writeMarkdown(std::ostream& md, const Options& options, const Sweep& sweep, const std::string& machine,
                   const Results& results) {
  writeIntroduction(md, options, sweep, machine);
  writeWorkPrecision(md, results);
  writeOrder(md, results);
  writeControlRate(md, results);
  writeLongRun(md, results, sweep);
  writeStability(md, results, options.quick);
  writeContactSection(md, results.contact, results.contact_figures);
  writeSimBenchmarkSection(md, results.simbenchmark, options.quick);
  writeRecommendations(md, results);
}

}  // namespace accuracy_report
