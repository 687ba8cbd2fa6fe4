#include "parameter_values.hpp"

#include <cstdlib>
#include <sstream>

namespace rigid_body_ros {
namespace parameter_values {

namespace {

// A hand-typed quaternion such as [0, 0, 0.7071, 0.7071] is accepted and normalised if |q| is this close to 1.
constexpr double kQuaternionNormTolerance = 1e-3;
// roscpp turns a rosrun argument _size:=[0.4,0.2,0.1] into the string "[0.4,0.2,0.1]" (it parses only
// scalars), so a list may come as text: "[a, b, ...]" of numbers becomes an XmlRpc array.
bool parseListText(const std::string& text, XmlRpcValue& array) {
  const size_t open = text.find_first_not_of(" \t");
  const size_t close = text.find_last_not_of(" \t");
  if (open == std::string::npos || text[open] != '[' || text[close] != ']') return false;
  std::istringstream items(text.substr(open + 1, close - open - 1));
  std::string item;
  array.setSize(0);
  int index = 0;
  while (std::getline(items, item, ',')) {
    char* end = nullptr;
    const double number = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || item.find_first_not_of(" \t", end - item.c_str()) != std::string::npos) return false;
    array[index++] = number;
  }
  return true;
}

}  // namespace

std::string render(const XmlRpcValue& value) {
  XmlRpcValue copy = value;  // the XmlRpc accessors are not const
  std::ostringstream out;
  out.precision(17);
  switch (copy.getType()) {
    case XmlRpcValue::TypeInt:
      out << static_cast<int>(copy);
      break;
    case XmlRpcValue::TypeDouble:
      out << static_cast<double>(copy);
      break;
    case XmlRpcValue::TypeBoolean:
      out << (static_cast<bool>(copy) ? "true" : "false");
      break;
    case XmlRpcValue::TypeString:
      out << "'" << static_cast<std::string>(copy) << "'";
      break;
    case XmlRpcValue::TypeArray:
      out << "[";
      for (int i = 0; i < copy.size(); ++i) out << (i ? ", " : "") << render(copy[i]);
      out << "]";
      break;
    case XmlRpcValue::TypeStruct:
      out << "{...}";
      break;
    default:
      out << "(unset)";
  }
  return out.str();
}

void fail(const std::string& name, const XmlRpcValue& value, const std::string& allowed) {
  throw ParameterError("parameter ~" + name + " = " + render(value) + ": " + allowed);
}

void failAt(const XmlRpcValue& params, const std::string& name, const XmlRpcValue& effective,
            const std::string& allowed) {
  if (const XmlRpcValue* value = find(params, name)) fail(name, *value, allowed);
  throw ParameterError("parameter ~" + name + " (not set, so " + render(effective) + "): " + allowed);
}

bool isNumber(const XmlRpcValue& value) {
  return value.getType() == XmlRpcValue::TypeInt || value.getType() == XmlRpcValue::TypeDouble;
}

double asNumber(const XmlRpcValue& value) {
  XmlRpcValue copy = value;
  return copy.getType() == XmlRpcValue::TypeInt ? static_cast<double>(static_cast<int>(copy))
                                                : static_cast<double>(copy);
}

// Looks up a/b/c in nested structs; returns nullptr when it is not set.
const XmlRpcValue* find(const XmlRpcValue& params, const std::string& name) {
  const XmlRpcValue* node = &params;
  std::istringstream path(name);
  std::string key;
  while (std::getline(path, key, '/')) {
    if (node->getType() != XmlRpcValue::TypeStruct || !node->hasMember(key)) return nullptr;
    node = &(*node)[key];
  }
  return node;
}

// An integer >= minimum (a double is refused: a count or a seed is not a measurement).
int readInteger(const XmlRpcValue& params, const std::string& name, int fallback, int minimum,
                const std::string& allowed) {
  const XmlRpcValue* value = find(params, name);
  if (!value) return fallback;
  if (value->getType() != XmlRpcValue::TypeInt || static_cast<const int&>(*value) < minimum) {
    fail(name, *value, allowed);
  }
  return static_cast<const int&>(*value);
}

std::vector<double> readNumbers(const XmlRpcValue& params, const std::string& name, std::vector<double> fallback,
                                size_t length, const std::string& allowed) {
  const XmlRpcValue* value = find(params, name);
  if (!value) return fallback;
  XmlRpcValue copy = *value;
  if (copy.getType() == XmlRpcValue::TypeString) {
    XmlRpcValue parsed;
    if (parseListText(static_cast<std::string>(copy), parsed)) copy = parsed;
  }
  if (copy.getType() != XmlRpcValue::TypeArray || static_cast<size_t>(copy.size()) != length) {
    fail(name, *value, allowed);
  }
  std::vector<double> numbers;
  for (int i = 0; i < copy.size(); ++i) {
    if (!isNumber(copy[i]) || !std::isfinite(asNumber(copy[i]))) fail(name, *value, allowed);
    numbers.push_back(asNumber(copy[i]));
  }
  return numbers;
}

Eigen::Vector3d readVector3(const XmlRpcValue& params, const std::string& name, const std::string& unit) {
  const std::vector<double> v =
      readNumbers(params, name, {0.0, 0.0, 0.0}, 3, "must be a list of 3 finite numbers [x, y, z] " + unit);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Quaterniond readQuaternion(const XmlRpcValue& params, const std::string& name) {
  const std::vector<double> q = readNumbers(params, name, {0.0, 0.0, 0.0, 1.0}, 4,
                                            "must be a unit quaternion [x, y, z, w] of 4 finite numbers");
  const Eigen::Quaterniond orientation(q[3], q[0], q[1], q[2]);
  if (std::abs(orientation.norm() - 1.0) > kQuaternionNormTolerance) {
    failAt(params, name, XmlRpcValue(),
           "must be a unit quaternion [x, y, z, w]: |q| must be within 1e-3 of 1 (it is then normalised)");
  }
  return orientation;
}

std::string readString(const XmlRpcValue& params, const std::string& name, const std::string& fallback,
                       const std::string& allowed) {
  const XmlRpcValue* value = find(params, name);
  if (!value) return fallback;
  if (value->getType() != XmlRpcValue::TypeString) fail(name, *value, allowed);
  return static_cast<const std::string&>(*value);
}

std::string readFrame(const XmlRpcValue& params, const std::string& name, const std::string& fallback) {
  const std::string allowed = "must be a non-empty tf2 frame id without a leading '/'";
  const std::string frame = readString(params, name, fallback, allowed);
  if (frame.empty() || frame.front() == '/' || frame.find(' ') != std::string::npos) {
    failAt(params, name, XmlRpcValue(frame), allowed);
  }
  return frame;
}

bool readBool(const XmlRpcValue& params, const std::string& name, bool fallback) {
  const XmlRpcValue* value = find(params, name);
  if (!value) return fallback;
  if (value->getType() != XmlRpcValue::TypeBoolean) fail(name, *value, "must be true or false");
  return static_cast<const bool&>(*value);
}

// A key that groups others must be a struct: `_publish:=5` or `noise: loud` is an error, not "unset".
void requireStruct(const XmlRpcValue& params, const std::string& name, const std::string& keys) {
  const XmlRpcValue* value = find(params, name);
  if (value && value->getType() != XmlRpcValue::TypeStruct) fail(name, *value, "must be a struct of " + keys);
}

void collectUnknown(const XmlRpcValue& params, const std::string& prefix, const std::set<std::string>& known,
                    std::vector<std::string>& unknown) {
  XmlRpcValue copy = params;
  if (copy.getType() != XmlRpcValue::TypeStruct) return;
  for (const auto& member : copy) {
    if (!known.count(member.first)) unknown.push_back(prefix + member.first);
  }
}

}  // namespace parameter_values
}  // namespace rigid_body_ros
