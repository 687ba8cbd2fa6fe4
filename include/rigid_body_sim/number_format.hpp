// One way to print a number in messages, logs and reports.
#pragma once

#include <string>

namespace rigid_body {

/// `value` with `significant` digits; with 17 (the default) the shortest text that reads back as the same
/// double, e.g. "0.1" or "1e+300".
std::string formatNumber(double value, int significant = 17);

}  // namespace rigid_body
