// SimBenchmark's contact scenes (Kang, Hwangbo et al., leggedrobotics/SimBenchmark, 2018) run in the package
// with the same set-up and the same error metrics, so that the report's numbers sit beside the table that
// compares RaiSim, Bullet, ODE, MuJoCo and DART (docs/report.md, "SimBenchmark").
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "measurements.hpp"

namespace accuracy_report {

/// Runs the three scenes over their sweeps; writes simbenchmark.csv.
std::vector<SimBenchmarkRow> runSimBenchmark(const Options& options);

/// The report's SimBenchmark section: the package's rows beside the published ones at h = 1 ms.
void writeSimBenchmarkSection(std::ostream& md, const std::vector<SimBenchmarkRow>& rows, bool quick);

}  // namespace accuracy_report
