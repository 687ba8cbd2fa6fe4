// The shape table (shape_registry.hpp): every row agrees with its enumeration value, its name and what the
// rest of the core assumes of it. Parameterised over the table: a new row is tested by being added.
#include <gtest/gtest.h>

#include <set>
#include <ostream>
#include <string>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/shape_registry.hpp"

namespace rigid_body {
// gtest prints a parameter by this (a row's bytes otherwise).
inline void PrintTo(const ShapeInfo& row, std::ostream* os) { *os << row.name; }
}  // namespace rigid_body

using namespace rigid_body;

namespace {
class EveryShape : public ::testing::TestWithParam<ShapeInfo> {};
class SolidShape : public ::testing::TestWithParam<ShapeInfo> {};  // the rows with a solid formula

std::vector<ShapeInfo> solidShapes() {
  std::vector<ShapeInfo> rows;
  for (const ShapeInfo& row : shapeRegistry()) {
    if (row.solid) rows.push_back(row);
  }
  return rows;
}

std::string nameOf(const ::testing::TestParamInfo<ShapeInfo>& info) { return info.param.name; }
}  // namespace

TEST_P(EveryShape, RowIsFoundByItsValueAndItsName) {
  const ShapeInfo& row = GetParam();
  EXPECT_EQ(shapeInfo(row.type).name, std::string(row.name));
  EXPECT_EQ(shapeTypeName(row.type), std::string(row.name));
  ASSERT_TRUE(shapeFromName(row.name).has_value());
  EXPECT_EQ(*shapeFromName(row.name), row.type);
  EXPECT_FALSE(shapeFromName(std::string(row.name) + "s").has_value());
}

TEST_P(EveryShape, DefaultSizeHasExactlyTheEntriesTheShapeReads) {
  const ShapeInfo& row = GetParam();
  ASSERT_GE(row.size_count, 0);
  ASSERT_LE(row.size_count, 3);
  for (int i = 0; i < 3; ++i) {
    if (i < row.size_count) {
      EXPECT_GT(row.default_size[i], 0.0) << row.name << " entry " << i;
    } else {
      EXPECT_EQ(row.default_size[i], 0.0) << row.name << " entry " << i << " is not read";
    }
  }
  // A shape that reads sizes is valid at its default size, and refused with any one of them zero.
  if (row.size_count == 0 || row.environment_only) return;
  CollisionShape shape;
  shape.type = row.type;
  shape.size = row.default_size;
  EXPECT_NO_THROW(validateShape(shape, false)) << row.name;
  for (int i = 0; i < row.size_count; ++i) {
    CollisionShape bad = shape;
    bad.size[i] = 0.0;
    EXPECT_THROW(validateShape(bad, false), std::invalid_argument) << row.name << " entry " << i;
  }
}

// A uniform solid inside the ball of radius R about its centre (its outer radius, which the continuous
// collision test relies on) has every moment about an axis through the centre at most M R²: each of its
// points is within R of the axis. A formula that misreads its size entries (a sphere's radius taken as a
// diameter, a cylinder's length as a half-length, at the default sizes) breaks it.
TEST_P(SolidShape, SolidFormulaFitsInsideTheShapesOuterBall) {
  const ShapeInfo& row = GetParam();
  EXPECT_FALSE(row.environment_only) << "a shape with mass can be a body";
  CollisionShape shape;
  shape.type = row.type;
  shape.size = row.default_size;
  const double mass = 2.5;
  const double R = outerRadius(shape);
  const MassProperties solid = row.solid(mass, row.default_size);
  EXPECT_DOUBLE_EQ(solid.mass(), mass);
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(solid.principalMoments()[i], 0.0) << row.name;
    EXPECT_LE(solid.principalMoments()[i], mass * R * R * (1 + 1e-12)) << row.name;
  }
}

INSTANTIATE_TEST_SUITE_P(ShapeTable, EveryShape, ::testing::ValuesIn(shapeRegistry()), nameOf);
INSTANTIATE_TEST_SUITE_P(ShapeTable, SolidShape, ::testing::ValuesIn(solidShapes()), nameOf);

TEST(ShapeTable, NamesAreUniqueAndEveryValueHasARow) {
  std::set<std::string> names;
  for (const ShapeInfo& row : shapeRegistry()) EXPECT_TRUE(names.insert(row.name).second) << row.name;
  // The rows are the enumeration's values in order: shapeInfo finds a row by its index.
  for (std::size_t i = 0; i < shapeRegistry().size(); ++i) EXPECT_EQ(static_cast<std::size_t>(shapeRegistry()[i].type), i);
  EXPECT_EQ(shapeNames([](const ShapeInfo& s) { return s.environment_only; }), "plane");
}
