#include "rigid_body_sim/number_format.hpp"

#include <cstdlib>
#include <sstream>

namespace rigid_body {

namespace {
std::string withPrecision(double value, int significant) {
  std::ostringstream out;
  out.precision(significant);
  out << value;
  return out.str();
}
}  // namespace

std::string formatNumber(double value, int significant) {
  if (significant < 17) return withPrecision(value, significant);
  // The shortest text that reads back as the same double: "0.1", "1e+300", not 0.10000000000000001.
  for (int digits = 1; digits < 17; ++digits) {
    const std::string text = withPrecision(value, digits);
    if (std::strtod(text.c_str(), nullptr) == value) return text;
  }
  return withPrecision(value, 17);
}

}  // namespace rigid_body
