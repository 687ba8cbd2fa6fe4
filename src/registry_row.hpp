// A registry's row by its enumeration value: the integrator and shape tables keep their rows in the
// enumeration's order, so a row is its value's index (every step asks for one; no search). Internal.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rigid_body {

/// rows[type], after checking once per table that row i holds value i (a row out of order or missing is a
/// programming error: std::logic_error naming the table).
template <class Row, class Enum>
const Row& registryRow(const std::vector<Row>& rows, Enum type, const char* table) {
  static const bool in_order = [&rows] {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (static_cast<std::size_t>(rows[i].type) != i) return false;
    }
    return true;
  }();
  const std::size_t index = static_cast<std::size_t>(type);
  if (!in_order || index >= rows.size()) throw std::logic_error(std::string(table) + " registry out of order");
  return rows[index];
}

}  // namespace rigid_body
