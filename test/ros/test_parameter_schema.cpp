// The scene-wide parameter schema (parameter_schema.hpp) against what it drives: NodeConfig's defaults, the
// reading and its messages, the known keys, and the README's parameter table. Parameterised over the rows:
// a new row is tested by being added.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/number_format.hpp"
#include "rigid_body_sim/ros/parameter_schema.hpp"

using rigid_body_ros::NodeConfig;
using rigid_body_ros::ParameterSpec;
using rigid_body_ros::ParameterType;
using XmlRpc::XmlRpcValue;

namespace rigid_body_ros {
inline void PrintTo(const ParameterSpec& spec, std::ostream* os) { *os << spec.key; }
}  // namespace rigid_body_ros

namespace {

// Every row; the scalar ones (numbers, integers, booleans); those a config holds as a plain field (load);
// those the schema reads itself (store); those of them with a range (not booleans).
class EveryParameter : public ::testing::TestWithParam<ParameterSpec> {};
class ScalarParameter : public ::testing::TestWithParam<ParameterSpec> {};
class ShownParameter : public ::testing::TestWithParam<ParameterSpec> {};
class StoredParameter : public ::testing::TestWithParam<ParameterSpec> {};
class RangedParameter : public ::testing::TestWithParam<ParameterSpec> {};

std::vector<ParameterSpec> rows(bool (*keep)(const ParameterSpec&)) {
  std::vector<ParameterSpec> kept;
  for (const ParameterSpec& spec : rigid_body_ros::sceneParameterSchema()) {
    if (keep(spec)) kept.push_back(spec);
  }
  return kept;
}
bool isScalar(const ParameterSpec& s) { return s.type != ParameterType::kList && s.type != ParameterType::kString; }

std::string nameOf(const ::testing::TestParamInfo<ParameterSpec>& info) {
  std::string name;  // publish/tf → publish__tf, apart from publish_tf
  for (const char* c = info.param.key; *c != '\0'; ++c) name += *c == '/' ? std::string("__") : std::string(1, *c);
  return name;
}

// params with `key` (a/b/c nests) set to `value`.
XmlRpcValue withKey(const std::string& key, const XmlRpcValue& value) {
  XmlRpcValue params;
  const std::size_t slash = key.find('/');
  if (slash == std::string::npos) {
    params[key] = value;
  } else {
    params[key.substr(0, slash)][key.substr(slash + 1)] = value;
  }
  return params;
}

XmlRpcValue typed(const ParameterSpec& spec, double value) {
  return spec.type == ParameterType::kInteger ? XmlRpcValue(static_cast<int>(value)) : XmlRpcValue(value);
}

// The cells of the row of the table in `path` whose first cell names `key` (in backticks) and whose type
// cell is filled, or none.
std::vector<std::string> documentedRow(const char* path, const std::string& key) {
  std::ifstream readme(path);
  std::string line;
  while (std::getline(readme, line)) {
    if (line.rfind("| ", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    std::string cell;
    while (std::getline(row, cell, '|')) {
      const std::size_t first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
      cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
    }
    if (cells.size() >= 5 && cells[0].find("`" + key + "`") != std::string::npos && !cells[1].empty()) return cells;
  }
  return {};
}

// The cells of the first row whose first cell names `key` (in backticks) and gives its type, in the README's
// parameter table or, for the keys it sums up in one row and sends there, docs/contact.md's; or none.
std::vector<std::string> readmeRow(const std::string& key) {
  for (const char* path : {README_PATH, CONTACT_DOC_PATH}) {
    const std::vector<std::string> row = documentedRow(path, key);
    if (!row.empty()) return row;
  }
  return {};
}

}  // namespace

TEST_P(ShownParameter, TheConfigsDefaultIsTheSchemas) {
  const ParameterSpec& spec = GetParam();
  EXPECT_EQ(spec.load(NodeConfig()), spec.default_value) << "NodeConfig's own default";
  EXPECT_EQ(spec.load(rigid_body_ros::parseConfig(XmlRpcValue())), spec.default_value) << "read with nothing set";
}

TEST_P(StoredParameter, TheStartUpLogShowsItsValue) {
  const ParameterSpec& spec = GetParam();
  // A value other than the default, so that the log shows what was read, not what it assumes.
  NodeConfig config;
  const double value = spec.type == ParameterType::kBool ? (spec.default_value != 0.0 ? 0.0 : 1.0)
                       : std::isfinite(spec.default_value) ? spec.default_value + 7.0
                                                           : 7.0;
  spec.store(config, value);
  const std::string text = spec.type == ParameterType::kBool ? (value != 0.0 ? "true" : "false")
                                                             : rigid_body::formatNumber(value, 6);
  EXPECT_NE(config.describe().find(std::string(spec.key) + " " + text), std::string::npos) << config.describe();
}

TEST_P(RangedParameter, AValueInRangeIsReadAndOneBeyondEitherBoundRefusedNamingTheRule) {
  const ParameterSpec& spec = GetParam();
  const rigid_body_ros::ParameterRange& r = spec.range;
  // Inside: the default where finite, else just inside the low bound.
  const double inside = std::isfinite(spec.default_value) ? spec.default_value : r.low + 1.0;
  const NodeConfig read = rigid_body_ros::parseConfig(withKey(spec.key, typed(spec, inside)));
  EXPECT_EQ(spec.load(read), inside);
  const std::string rule = rigid_body_ros::allowedText(spec);
  for (const bool low : {true, false}) {
    const double bound = low ? r.low : r.high;
    if (!std::isfinite(bound) || std::abs(bound) >= 2147483647.0) continue;  // no bound (or the int's own)
    const bool open = low ? r.low_open : r.high_open;
    const double step = spec.type == ParameterType::kInteger ? 1.0 : std::max(1e-9, std::abs(bound) * 1e-9);
    const double beyond = open ? bound : (low ? bound - step : bound + step);
    const std::string message = parameter_test::errorOf(withKey(spec.key, typed(spec, beyond)));
    EXPECT_NE(message.find("parameter ~" + std::string(spec.key) + " = "), std::string::npos) << message;
    EXPECT_NE(message.find(rule), std::string::npos) << message << " lacks " << rule;
  }
}

TEST_P(ScalarParameter, IsAKnownKeyAndItsMisspellingIsNot) {
  const ParameterSpec& spec = GetParam();
  // A value the key accepts: the default, or just inside the bound of a limit that is unset by default.
  const XmlRpcValue value = spec.type == ParameterType::kBool ? XmlRpcValue(spec.default_value != 0.0)
                            : std::isfinite(spec.default_value) ? typed(spec, spec.default_value)
                                                                : typed(spec, spec.range.low + 1.0);
  EXPECT_TRUE(rigid_body_ros::parseConfig(withKey(spec.key, value)).unknown_parameters.empty()) << spec.key;
  const std::vector<std::string> unknown =
      rigid_body_ros::parseConfig(withKey(std::string(spec.key) + "x", value)).unknown_parameters;
  ASSERT_EQ(unknown.size(), 1u) << spec.key;
  EXPECT_EQ(unknown[0], std::string(spec.key) + "x");
}

// The README (or docs/contact.md) row of a schema row has its type, default, unit and, where the schema
// reads the value itself, its range.
void expectDocumented(const ParameterSpec& spec) {
  const std::vector<std::string> row = readmeRow(spec.key);
  ASSERT_FALSE(row.empty()) << "README.md (or docs/contact.md) has no row for `" << spec.key << "`";
  const std::string& type = row[1];
  const std::string& fallback = row[2];
  const std::string& unit = row[3];
  const std::string& allowed = row[4];
  switch (spec.type) {
    case ParameterType::kNumber:
      EXPECT_EQ(type, "double");
      break;
    case ParameterType::kInteger:
      EXPECT_EQ(type, "int");
      break;
    case ParameterType::kBool:
      EXPECT_EQ(type, "bool");
      EXPECT_EQ(fallback, spec.default_value != 0.0 ? "true" : "false");
      break;
    case ParameterType::kString:
      EXPECT_EQ(type, "string");
      break;
    case ParameterType::kList:
      EXPECT_EQ(type.rfind("double[", 0), 0u) << type;
      break;
  }
  if (spec.type == ParameterType::kNumber || spec.type == ParameterType::kInteger) {
    if (std::isinf(spec.default_value)) {
      EXPECT_EQ(fallback.rfind("unset", 0), 0u) << fallback;
    } else {
      EXPECT_EQ(std::stod(fallback), spec.default_value) << fallback;
    }
  }
  if (spec.type == ParameterType::kList) {
    EXPECT_NE(unit.find(spec.unit), std::string::npos) << unit;  // a grouped row lists each one's unit
  } else {
    EXPECT_EQ(unit, spec.unit);
  }
  const std::string range = rigid_body_ros::rangeText(spec);
  if (spec.store && !range.empty()) {
    EXPECT_EQ(allowed.rfind(range, 0), 0u) << allowed << " should begin " << range;
  }
}

TEST_P(EveryParameter, TheReadmeTableSaysWhatTheSchemaSays) { expectDocumented(GetParam()); }

class BodyParameter : public ::testing::TestWithParam<ParameterSpec> {};

TEST_P(BodyParameter, TheReadmeTableSaysWhatTheSchemaSays) {
  expectDocumented(GetParam());
  // A body key is known in the flat form and in an item of ~bodies.
  EXPECT_TRUE(rigid_body_ros::isKnownParameter(GetParam().key)) << GetParam().key;
}

INSTANTIATE_TEST_SUITE_P(Schema, EveryParameter, ::testing::ValuesIn(rigid_body_ros::sceneParameterSchema()), nameOf);
INSTANTIATE_TEST_SUITE_P(Schema, BodyParameter, ::testing::ValuesIn(rigid_body_ros::bodyParameterSchema()), nameOf);
INSTANTIATE_TEST_SUITE_P(Schema, ScalarParameter, ::testing::ValuesIn(rows(isScalar)), nameOf);
INSTANTIATE_TEST_SUITE_P(Schema, ShownParameter, ::testing::ValuesIn(rows([](const ParameterSpec& s) {
                           return s.load != nullptr;
                         })),
                         nameOf);
INSTANTIATE_TEST_SUITE_P(Schema, StoredParameter, ::testing::ValuesIn(rows([](const ParameterSpec& s) {
                           return s.store != nullptr;
                         })),
                         nameOf);
INSTANTIATE_TEST_SUITE_P(Schema, RangedParameter, ::testing::ValuesIn(rows([](const ParameterSpec& s) {
                           return s.store != nullptr && s.type != ParameterType::kBool;
                         })),
                         nameOf);

// The other way round: every key the README's parameter table names is one the node reads, so a schema row
// dropped (its key then unread and reported unknown) or a README row for a key that does not exist fails.
TEST(ParameterSchema, EveryKeyTheReadmeTableNamesIsRead) {
  std::ifstream readme(README_PATH);
  std::string line;
  bool in_table = false;
  std::size_t keys = 0;
  while (std::getline(readme, line)) {
    if (line.rfind("| parameter | type | default | unit | allowed |", 0) == 0) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (line.rfind("|", 0) != 0) break;
    const std::string first = line.substr(1, line.find('|', 1) - 1);
    for (std::size_t open = first.find('`'); open != std::string::npos; open = first.find('`', open + 1)) {
      const std::size_t close = first.find('`', open + 1);
      if (close == std::string::npos) break;
      const std::string key = first.substr(open + 1, close - open - 1);
      EXPECT_TRUE(rigid_body_ros::isKnownParameter(key)) << "README.md names `" << key << "`, which the node does not read";
      ++keys;
      open = close;
    }
  }
  EXPECT_GT(keys, 50u) << "the README's parameter table was not found";
}
