// The one-step maps of the methods that are not a plain Runge–Kutta tableau, one family per source file:
// lie_euler.cpp (Buss) and splitting.cpp (symplectic splitting, implicit midpoint); semi-implicit Euler is
// a lane kernel with explicit Euler and rk4 (lane_dispatch.hpp: one body or four at once).
// dopri5 lives in dopri5.cpp, as Integrator's member (it keeps memory between calls).
// Internal to the integrators (not installed).
#pragma once

#include <cstdint>

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/integrators.hpp"

namespace rigid_body {
namespace integrators {

State bussStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h, const State& y);
/// Two of the principal moments equal (to a relative 1e-12): a symmetric top, or a sphere.
bool isSymmetricTop(const MassProperties& mass);
/// What a symmetric top's flow needs: its odd principal axis (the one not in the equal pair; either end) as
/// an index into the principal moments and as a unit vector in body axes, 1/I_r for the pair's moment I_r
/// and 1/I_s − 1/I_r for the odd one's I_s (0 for a sphere). For a symmetric top only (isSymmetricTop).
struct SymmetricTopAxes {
  int odd = 2;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double inverse_pair = 0.0;
  double spin_coefficient = 0.0;
};
SymmetricTopAxes symmetricTopAxes(const MassProperties& mass);
/// A symmetric top (two equal principal moments) turns exactly over h at fixed world L: its two flows commute.
/// Returns false, leaving s alone, for an asymmetric body (splitting.cpp).
bool symmetricTopFlow(const MassProperties& mass, double h, State& s);
/// The same on q alone (world L is fixed over the flow).
bool symmetricTopFlow(const MassProperties& mass, double h, const Eigen::Vector3d& L_W, Eigen::Quaterniond& q_WB);
StepStatus symplecticSplittingStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                   State& s);
StepStatus implicitMidpointStep(const Model& model, const StepTerms& terms, const AppliedWrench& input, double h,
                                const IntegratorSettings& settings, std::uint64_t& newton_iterations, State& s);

}  // namespace integrators
}  // namespace rigid_body
