#include "rigid_body_sim/shape_registry.hpp"

#include "registry_row.hpp"

namespace rigid_body {

namespace {
MassProperties solidBox(double mass, const Eigen::Vector3d& size) { return MassProperties::box(mass, size); }
MassProperties solidSphere(double mass, const Eigen::Vector3d& size) { return MassProperties::sphere(mass, size.x()); }
MassProperties solidCylinder(double mass, const Eigen::Vector3d& size) {
  return MassProperties::cylinder(mass, size.x(), size.y());
}
}  // namespace

const std::vector<ShapeInfo>& shapeRegistry() {
  // In the enumeration's order. type, name, size entries, their meaning, a body's default size, curved,
  // environment only, solid
  static const std::vector<ShapeInfo> registry = {
      {ShapeType::kPlane, "plane", 0, "none", Eigen::Vector3d::Zero(), false, true, nullptr},
      {ShapeType::kBox, "box", 3, "[x, y, z]", Eigen::Vector3d(0.4, 0.2, 0.1), false, false, solidBox},
      {ShapeType::kSphere, "sphere", 1, "[radius]", Eigen::Vector3d(0.1, 0, 0), true, false, solidSphere},
      {ShapeType::kCylinder, "cylinder", 2, "[radius, length]", Eigen::Vector3d(0.1, 0.4, 0), true, false,
       solidCylinder},
      {ShapeType::kCapsule, "capsule", 2, "[radius, length]", Eigen::Vector3d(0.1, 0.4, 0), true, false, nullptr},
      {ShapeType::kMesh, "mesh", 0, "none", Eigen::Vector3d::Zero(), false, false, nullptr},
  };
  return registry;
}

const ShapeInfo& shapeInfo(ShapeType type) { return registryRow(shapeRegistry(), type, "shape"); }

std::optional<ShapeType> shapeFromName(const std::string& name) {
  for (const ShapeInfo& info : shapeRegistry()) {
    if (name == info.name) return info.type;
  }
  return std::nullopt;
}

std::string sizeRule(ShapeType type) {
  const ShapeInfo& info = shapeInfo(type);
  const std::string count = info.size_count == 1 ? "a finite number" : std::to_string(info.size_count) + " finite numbers";
  return std::string("for a ") + info.name + ", must be " + info.size_meaning + " with " + count + " > 0 [m]";
}

std::string shapeNames(bool (*keep)(const ShapeInfo&)) {
  std::string names;
  for (const ShapeInfo& info : shapeRegistry()) {
    if (keep(info)) names += (names.empty() ? "" : ", ") + std::string(info.name);
  }
  return names;
}

}  // namespace rigid_body
