// The measurements of the accuracy report, one function per section, each writing its CSV, and the
// report written from their results (figures by gnuplot, REPORT.md).
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "scenes.hpp"
#include "stability.hpp"

namespace accuracy_report {

struct Options {
  std::string out = "report";
  bool quick = false;
  bool only_stability = false;  ///< the stiff and extreme suite alone
  bool only_simbenchmark = false;  ///< SimBenchmark's scenes alone
  bool substituted = false;     ///< --substitute was given
};

// The sweeps. --quick thins them so the whole report takes seconds (for the test).
struct Sweep {
  std::vector<double> steps;       // h [s]
  std::vector<double> tolerances;  // dopri5
  int repeats;                     // timed repeats after one warm-up
  long long_run_steps;             // error growth and the long-run stability case
};

/// The sweeps of a full or a --quick run.
Sweep sweepFor(bool quick);



/// The control steps of the control-rate table [s].
extern const std::vector<double> kControlSteps;

// Error at h = 5 ms (dopri5: tolerance 1e-8) and CPU time per simulated second, per scene and method.
using SceneTable = std::map<std::string, std::map<std::string, std::pair<double, double>>>;
// Error after 1 s and CPU time per tick, per method and control step h.
using ControlTable = std::map<std::string, std::map<double, std::pair<double, double>>>;

struct LongRunSummary {
  double max_energy_error;  // max |dE/E|
  double max_L_error;       // max |dL|/|L|
  double max_norm_error;    // max ||q| - 1|
  double drift;             // slope of dE/E against t over the second half [1/s]
};

/// One run of a closed-form contact scene (contact_report.hpp).
struct ContactRow {
  std::string scene;        ///< e.g. "bounce"
  std::string metric;       ///< what `error` is, with its unit
  std::string integrator;   ///< integrator name
  std::string setting;      ///< the contact settings, e.g. "located, 20 iterations"
  double dt;                ///< [s]
  double error;             ///< against the closed form
  double cpu_per_second;    ///< CPU time per simulated second [s]
};

// One run of a SimBenchmark scene (simbenchmark.hpp).
struct SimBenchmarkRow {
  std::string scene;       ///< "bouncing", "rolling" or "666"
  std::string integrator;  ///< integrator name
  double dt;               ///< [s]
  int iterations;          ///< the contact solver's sweeps per step
  double error;            ///< the scene's own metric (mean over the steps of a squared error)
  double cpu_seconds;      ///< CPU time of the whole simulated run [s], as SimBenchmark publishes it
  double cpu_per_body_step;  ///< [s]
};

struct Results {
  std::vector<Scene> scenes;
  SceneTable at_control_step;
  std::map<std::string, double> fitted_orders;
  ControlTable control;
  std::map<std::string, LongRunSummary> long_run;
  std::vector<StabilityRow> stability;
  std::vector<ContactRow> contact;
  std::vector<SimBenchmarkRow> simbenchmark;
  bool figures = false;
  bool contact_figures = false;
};


SceneTable runWorkPrecision(const Options& options, const Sweep& sweep, const std::vector<Scene>& scenes);
std::map<std::string, double> runOrder(const Options& options);
ControlTable runControlRate(const Options& options, const Sweep& sweep);
/// Error growth over the long run; adds the long-run rows of the stability suite to `rows`.
std::map<std::string, LongRunSummary> runLongRun(const Options& options, const Sweep& sweep,
                                                 std::vector<StabilityRow>& rows);
void writeStabilityCsv(const Options& options, const std::vector<StabilityRow>& rows);

/// "CPU, cores, compiler, flags" of this machine, for the report.
std::string machineDescription();
/// CPU time of this process [s] (CLOCK_PROCESS_CPUTIME_ID): what every timing of the report reads.
double cpuSeconds();
/// The CPU-time clock the timings use: its resolution and the cost of one read, measured now.
std::string clockDescription();
/// The figures; false if gnuplot failed on any.
bool drawFigures(const Options& options, const std::vector<Scene>& scenes);
/// Claimed thresholds among the rows, and how many were met.
std::pair<int, int> countClaims(const std::vector<StabilityRow>& rows);
/// REPORT.md: every section from the results.
void writeMarkdown(std::ostream& md, const Options& options, const Sweep& sweep, const std::string& machine,
                   const Results& results);

}  // namespace accuracy_report
