// The contact section of the accuracy report: error against CPU time on the closed-form contact scenes
// (docs/references.md §4), swept over the step and the contact solver's settings, and the stiff and extreme
// contact cases of the stability suite.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "measurements.hpp"
#include "stability.hpp"

namespace accuracy_report {

/// Runs every closed-form contact scene over the methods, settings and steps; writes contact.csv.
std::vector<ContactRow> runContactWorkPrecision(const Options& options);

/// The stiff and extreme contact cases, as rows of the stability suite.
std::vector<StabilityRow> runContactStability(bool quick);

/// One line per contact case of the stability suite, for the report.
std::vector<std::pair<std::string, std::string>> contactCaseDescriptions(bool quick);

/// contact_<scene>.png: error against CPU time, one polyline per method and setting (gnuplot).
bool drawContactFigures(const Options& options, const std::vector<ContactRow>& rows);

/// The report's contact section: the figures, a table at h = 1 ms and "which contact settings when".
void writeContactSection(std::ostream& md, const std::vector<ContactRow>& rows, bool figures);

}  // namespace accuracy_report
