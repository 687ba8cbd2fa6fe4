#include "rigid_body_sim/ros/body_properties.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <Eigen/Geometry>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/number_format.hpp"
#include "rigid_body_sim/shape_registry.hpp"

namespace rigid_body_ros {

void fillProperties(const BodyConfig& body, const std::string& integrator, const rigid_body::StepTerms& terms,
                    rigid_body_sim::GetProperties::Response& response) {
  const rigid_body::MassProperties& mass = body.model.mass;
  // X_BP is the published frame P in the body frame B (B's origin the centre of mass): a vector in B is
  // R_BP v_P, so I_P = R_BPᵀ I_B R_BP, and the centre of mass sits in P at X_BP⁻¹'s translation.
  const Eigen::Matrix3d R_BP = body.X_BP.linear();
  const Eigen::Matrix3d I_P = R_BP.transpose() * mass.inertia() * R_BP;
  response.mass = mass.mass();
  // + 0: the identity's inverse has −0 entries (−Rᵀ 0), which would print as "-0.0".
  response.center_of_mass = tf2::toMsg(Eigen::Vector3d(body.X_BP.inverse().translation() + Eigen::Vector3d::Zero()));
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) response.inertia[3 * r + c] = I_P(r, c);
    response.principal_moments[r] = mass.principalMoments()[r];
  }
  response.principal_axes = tf2::toMsg(Eigen::Quaterniond(R_BP.transpose() * mass.principalAxes()).normalized());
  response.shape = body.shapeLabel();
  const bool sized = body.mass_source == MassSource::kShape && rigid_body::shapeInfo(body.shape).size_count > 0;
  response.size = sized ? body.size : std::vector<double>();  // a mesh's size is its file's
  response.collides = body.collision.has_value();
  response.collision_shape = body.collision ? rigid_body::shapeTypeName(body.collision->type) : "";
  response.restitution = body.collision ? body.collision->material.restitution : 0.0;
  response.friction = body.collision ? body.collision->material.friction : 0.0;
  response.wrench_input = body.wrench_input;
  response.integrator = integrator;
  response.step_terms = rigid_body::describeTerms(terms);
}

std::string describeProperties(const rigid_body_sim::GetProperties::Response& properties) {
  auto number = [](double value) { return rigid_body::formatNumber(value, 6); };
  const auto& moments = properties.principal_moments;
  const auto& c = properties.center_of_mass;
  return "mass " + number(properties.mass) + " kg, principal moments [" + number(moments[0]) + ", " +
         number(moments[1]) + ", " + number(moments[2]) + "] kg m^2, centre of mass (" + number(c.x) + ", " +
         number(c.y) + ", " + number(c.z) + ") m in the published frame, shape " + properties.shape;
}

}  // namespace rigid_body_ros
