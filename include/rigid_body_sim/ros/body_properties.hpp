// A body's constant properties as the get_properties service reports them (pure: tested without a master).
#pragma once

#include <string>

#include "rigid_body_sim/GetProperties.h"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body_ros {

/// The response for `body`, stepped by `integrator` with `terms`: mass, centre of mass and inertia in the
/// published frame P (I_P = R_BPᵀ I_B R_BP, the centre of mass at X_BP⁻¹'s origin), its principal moments
/// and axes, its shape and size, its collision material, and how it steps.
void fillProperties(const BodyConfig& body, const std::string& integrator, const rigid_body::StepTerms& terms,
                    rigid_body_sim::GetProperties::Response& response);

/// One line for the start-up log (a user loading a URDF link sees what it read): "mass M kg, principal
/// moments [I1, I2, I3] kg m^2, centre of mass (x, y, z) m in the published frame, shape S" (6 digits).
std::string describeProperties(const rigid_body_sim::GetProperties::Response& properties);

}  // namespace rigid_body_ros
