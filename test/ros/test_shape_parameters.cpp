// The parameters of shapes follow the shape table (shape_registry.hpp): a body's `shape`, `collision/shape`
// and an environment item's `type` accept exactly the table's names where they apply, read as many `size`
// entries as its row says, and a body's mass properties are its row's solid formula. Parameterised over the
// table: a new row is tested by being added.
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

#include "parameter_test_support.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/shape_registry.hpp"

namespace rigid_body {
// gtest prints a parameter by this (a row's bytes otherwise).
inline void PrintTo(const ShapeInfo& row, std::ostream* os) { *os << row.name; }
}  // namespace rigid_body

using rigid_body_ros::NodeConfig;
using rigid_body_ros::parseConfig;
using XmlRpc::XmlRpcValue;

namespace {

// A mesh body is read from its file (test_parameters); the shapes that take a size, on a body.
class ShapeOtherThanMesh : public ::testing::TestWithParam<rigid_body::ShapeInfo> {};
class ShapeWithSize : public ::testing::TestWithParam<rigid_body::ShapeInfo> {};
class EnvironmentOnlyShape : public ::testing::TestWithParam<rigid_body::ShapeInfo> {};

std::vector<rigid_body::ShapeInfo> shapes(bool (*keep)(const rigid_body::ShapeInfo&)) {
  std::vector<rigid_body::ShapeInfo> rows;
  for (const rigid_body::ShapeInfo& row : rigid_body::shapeRegistry()) {
    if (keep(row)) rows.push_back(row);
  }
  return rows;
}

XmlRpcValue sizeList(const rigid_body::ShapeInfo& row, double scale) {
  XmlRpcValue array;
  array.setSize(row.size_count);
  for (int i = 0; i < row.size_count; ++i) array[i] = scale * row.default_size[i];
  return array;
}

using parameter_test::errorOf;

std::string nameOf(const ::testing::TestParamInfo<rigid_body::ShapeInfo>& info) { return info.param.name; }

}  // namespace

TEST_P(ShapeOtherThanMesh, ABodyTakesTheShapeExactlyWhenItHasASolidFormula) {
  const rigid_body::ShapeInfo& row = GetParam();
  XmlRpcValue params;
  params["shape"] = std::string(row.name);
  params["mass"] = 3.0;
  if (row.size_count > 0) params["size"] = sizeList(row, 1.5);
  if (!row.solid) {
    EXPECT_NE(errorOf(params).find("parameter ~shape = '" + std::string(row.name) + "': must be one of:"),
              std::string::npos)
        << row.name;
    return;
  }
  const NodeConfig config = parseConfig(params);
  ASSERT_TRUE(config.bodies[0].hasShape(row.type));
  EXPECT_EQ(config.bodies[0].shapeLabel(), row.name);
  const rigid_body::MassProperties expected = row.solid(3.0, 1.5 * row.default_size);
  EXPECT_TRUE(config.bodies[0].model.mass.inertia().isApprox(expected.inertia(), 1e-14)) << row.name;
  // With no size, the row's default; with one entry too many, refused naming the rule.
  params = XmlRpcValue();
  params["shape"] = std::string(row.name);
  const NodeConfig defaults = parseConfig(params);
  EXPECT_TRUE(defaults.bodies[0].model.mass.inertia().isApprox(row.solid(1.0, row.default_size).inertia(), 1e-14));
  XmlRpcValue long_size = sizeList(row, 1.0);
  long_size[row.size_count] = 0.1;
  params["size"] = long_size;
  EXPECT_NE(errorOf(params).find(rigid_body::sizeRule(row.type)), std::string::npos) << errorOf(params);
}

TEST_P(ShapeWithSize, ACollisionShapeReadsTheEntriesItsRowSays) {
  const rigid_body::ShapeInfo& row = GetParam();
  XmlRpcValue params;
  params["collision"]["shape"] = std::string(row.name);
  params["collision"]["size"] = sizeList(row, 0.5);
  const NodeConfig config = parseConfig(params);
  ASSERT_TRUE(config.bodies[0].collision.has_value());
  EXPECT_EQ(config.bodies[0].collision->type, row.type);
  EXPECT_EQ(config.bodies[0].collision->size, 0.5 * row.default_size);
  XmlRpcValue short_size;
  short_size.setSize(row.size_count + 1);
  for (int i = 0; i <= row.size_count; ++i) short_size[i] = 0.1;
  params["collision"]["size"] = short_size;
  EXPECT_NE(errorOf(params).find(rigid_body::sizeRule(row.type)), std::string::npos) << errorOf(params);
}

TEST_P(EnvironmentOnlyShape, IsRefusedOnABody) {
  const rigid_body::ShapeInfo& row = GetParam();
  XmlRpcValue params;
  params["collision"]["shape"] = std::string(row.name);
  EXPECT_NE(errorOf(params).find("parameter ~collision/shape = '" + std::string(row.name) + "': must be one of:"),
            std::string::npos)
      << errorOf(params);
}

INSTANTIATE_TEST_SUITE_P(ShapeTable, ShapeOtherThanMesh, ::testing::ValuesIn(shapes([](const rigid_body::ShapeInfo& s) {
                           return s.type != rigid_body::ShapeType::kMesh;
                         })),
                         nameOf);
INSTANTIATE_TEST_SUITE_P(ShapeTable, ShapeWithSize, ::testing::ValuesIn(shapes([](const rigid_body::ShapeInfo& s) {
                           return s.size_count > 0 && !s.environment_only;
                         })),
                         nameOf);
INSTANTIATE_TEST_SUITE_P(ShapeTable, EnvironmentOnlyShape, ::testing::ValuesIn(shapes([](const rigid_body::ShapeInfo& s) {
                           return s.environment_only;
                         })),
                         nameOf);
