// accuracy_report: error against run time for every integrator, order, control-rate cost, long-run error
// growth and the stiff and extreme suite, as CSV files, PNG figures (gnuplot) and REPORT.md.
//
//   rosrun rigid_body_sim accuracy_report [--out DIR] [--quick]
//
// Conventions (docs/references.md §3): error at the final time against the closed form; CPU time the
// median of repeats after a warm-up, each repeat long enough to be measured, per simulated second;
// log–log work-precision polylines per method.
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "contact_report.hpp"
#include "simbenchmark.hpp"
#include "measurements.hpp"
#include "rigid_body_sim/integrators.hpp"

using namespace accuracy_report;

namespace {

// "rk4:explicit_euler" → substitute(kRk4, kExplicitEuler); false if either name is unknown.
bool parseSubstitution(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return false;
  try {
    substitute(rigid_body::integratorFromName(text.substr(0, colon)),
               rigid_body::integratorFromName(text.substr(colon + 1)));
  } catch (const std::invalid_argument&) {
    return false;
  }
  return true;
}

bool parseOptions(int argc, char** argv, Options& options, int& exit_code) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") {
      options.quick = true;
    } else if (arg == "--out" && i + 1 < argc) {
      options.out = argv[++i];
    } else if (arg == "--only-stability") {
      options.only_stability = true;
    } else if (arg == "--only-simbenchmark") {
      options.only_simbenchmark = true;
    } else if (arg == "--substitute" && i + 1 < argc && parseSubstitution(argv[++i])) {
      options.substituted = true;
    } else {
      std::cerr << "usage: accuracy_report [--out DIR] [--quick] [--only-stability | --only-simbenchmark]\n"
                   "                       [--substitute CLAIMED:RUN]\n"
                   "  writes work_precision.csv, order.csv, control_rate.csv, error_growth.csv, stability.csv,\n"
                   "  their PNG figures (with gnuplot) and REPORT.md into DIR (default ./report).\n"
                   "  --only-stability: the stiff and extreme suite only (stability.csv).\n"
                   "  --only-simbenchmark: SimBenchmark's scenes only (simbenchmark.csv, the table on stdout).\n"
                   "  --substitute CLAIMED:RUN: runs method RUN wherever CLAIMED is named (a mutation check:\n"
                   "  CLAIMED's claims should then fail if RUN is of lower order). Methods: " +
                       rigid_body::integratorNameList() + "\n";
      exit_code = arg == "--help" || arg == "-h" ? 0 : 2;
      return false;
    }
  }
  mkdir(options.out.c_str(), 0755);
  std::ofstream probe(options.out + "/.write_test");
  if (!probe) {
    std::cerr << "accuracy_report: cannot write into " << options.out << "\n";
    exit_code = 1;
    return false;
  }
  std::remove((options.out + "/.write_test").c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  int exit_code = 0;
  if (!parseOptions(argc, argv, options, exit_code)) return exit_code;
  const Sweep sweep = sweepFor(options.quick);
  const std::string machine = machineDescription();
  std::cerr << "accuracy_report: " << (options.quick ? "quick" : "full") << " run on " << machine << "\n";

  if (options.substituted) std::cerr << "accuracy_report: methods substituted: the numbers are a mutation check\n";
  if (options.only_stability) {
    std::vector<StabilityRow> rows = runStabilitySuite(options.quick);
    const std::vector<StabilityRow> contact_rows = runContactStability(options.quick);
    rows.insert(rows.end(), contact_rows.begin(), contact_rows.end());
    writeStabilityCsv(options, rows);
    const std::pair<int, int> claims = countClaims(rows);
    std::cerr << "accuracy_report: wrote " << options.out << "/stability.csv; " << claims.second << " of "
              << claims.first << " claimed thresholds met\n";
    return 0;
  }
  if (options.only_simbenchmark) {
    writeSimBenchmarkSection(std::cout, runSimBenchmark(options), options.quick);
    return 0;
  }
  Results results;
  results.scenes = workPrecisionScenes();
  results.at_control_step = runWorkPrecision(options, sweep, results.scenes);
  results.fitted_orders = runOrder(options);
  results.control = runControlRate(options, sweep);
  std::vector<StabilityRow> long_rows;
  results.long_run = runLongRun(options, sweep, long_rows);
  std::cerr << "  stiff and extreme suite\n";
  results.stability = runStabilitySuite(options.quick);
  results.stability.insert(results.stability.end(), long_rows.begin(), long_rows.end());
  std::cerr << "  contact: closed forms, then the stiff and extreme contact cases\n";
  results.contact = runContactWorkPrecision(options);
  const std::vector<StabilityRow> contact_rows = runContactStability(options.quick);
  results.stability.insert(results.stability.end(), contact_rows.begin(), contact_rows.end());
  std::cerr << "  SimBenchmark's scenes\n";
  results.simbenchmark = runSimBenchmark(options);
  writeStabilityCsv(options, results.stability);
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    results.figures = drawFigures(options, results.scenes);
    results.contact_figures = drawContactFigures(options, results.contact);
  } else {
    std::cerr << "accuracy_report: gnuplot not found: CSV and REPORT.md only, no figures\n";
  }

  std::ofstream md(options.out + "/REPORT.md");
  writeMarkdown(md, options, sweep, machine, results);
  md.close();
  const std::pair<int, int> claims = countClaims(results.stability);
  std::cerr << "accuracy_report: wrote " << options.out << "/REPORT.md; " << claims.second << " of " << claims.first
            << " claimed thresholds met\n";
  return 0;
}
