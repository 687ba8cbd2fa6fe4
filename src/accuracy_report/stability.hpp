// The stiff and extreme suite of the accuracy report: each case run with every integrator, measured, and
// judged against its threshold for the methods that claim it (the others are reported).
#pragma once

#include <string>
#include <vector>

namespace accuracy_report {

struct StabilityRow {
  std::string case_name;   ///< e.g. "thin_rod"
  std::string integrator;  ///< integrator name
  std::string metric;      ///< what `value` is, with its unit
  double value;            ///< the measured value
  std::string threshold;   ///< the rule, e.g. "<= 1e-4"; empty when only reported
  bool claimed;            ///< whether this method claims the threshold
  bool pass;               ///< value meets the threshold (meaningful when threshold is set)
  /// An invariant: a property every method keeps by construction (|q| = 1 after its own normalisation, world
  /// L with no torque, a finite result, the energy bounds of a unit q). Reported in its own table, checked,
  /// and never counted as an accuracy or stability claim.
  bool invariant = false;
};

/// Runs the suite. `quick` shortens the long run (10⁵ instead of 10⁶ steps) and the bisections.
std::vector<StabilityRow> runStabilitySuite(bool quick);

/// One line per case: what was run, for the report.
std::vector<std::pair<std::string, std::string>> stabilityCaseDescriptions(bool quick);

}  // namespace accuracy_report
