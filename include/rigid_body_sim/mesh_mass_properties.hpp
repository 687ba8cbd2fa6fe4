// Mass, centre of mass and inertia of a solid bounded by a closed triangle mesh, three ways:
//   exact        — volume integrals by the divergence theorem (Eberly, "Polyhedral Mass Properties
//                  (Revisited)", 2002, after Mirtich, J. Graphics Tools 1(2), 1996): exact for the polyhedron;
//   sampling     — points in the bounding box, kept if inside (ray parity), with a standard error;
//   bounding box — the inertia of the axis-aligned (or oriented) box around the mesh: cheap, coarse.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/mesh.hpp"

namespace rigid_body {

enum class InertiaMethod { kExact, kSampling, kBoundingBox, kOrientedBoundingBox };

/// "exact", "sampling", "bounding_box", "oriented_bounding_box".
const std::string& inertiaMethodName(InertiaMethod method);
/// The method called `name`; throws std::invalid_argument listing the valid names.
InertiaMethod inertiaMethodFromName(const std::string& name);

struct MeshMassOptions {
  InertiaMethod method = InertiaMethod::kExact;
  double mass = 0.0;     ///< total mass [kg]; if 0, density × the mesh's volume
  double density = 0.0;  ///< [kg/m³], used when mass is 0
  std::uint64_t samples = 100000;  ///< sampling: points drawn in the bounding box
  std::uint64_t seed = 1;          ///< sampling: the generator's seed (results are reproducible)
  bool stratified = false;         ///< sampling: one jittered point per cell of a grid instead of i.i.d.
};

/// Mass properties in the mesh frame M.
struct MeshMassProperties {
  double volume = 0.0;                                    ///< exact volume of the mesh [m³]
  double mass = 0.0;                                      ///< [kg]
  Eigen::Vector3d p_MBcm = Eigen::Vector3d::Zero();       ///< centre of mass in M [m]
  Eigen::Matrix3d I_Bcm_M = Eigen::Matrix3d::Zero();      ///< inertia about the centre of mass, M's axes [kg m²]
  double inertia_standard_error = 0.0;  ///< sampling: standard error of I (Frobenius norm) [kg m²]; else 0
  std::uint64_t inside_samples = 0;     ///< sampling: points found inside
  std::vector<std::string> warnings;    ///< repairs made to the mesh (e.g. flipped inside-out)
};

/// The most ray–triangle tests `sampling` may make (points × triangles): seconds of start-up, not more
/// (docs/performance_log.md#sampling-budget).
/// The largest mesh file (kDefaultMaxMeshBytes, ~5 million triangles) at the most samples the node takes (1e7)
/// would be 5e13 tests, days of start-up.
constexpr std::uint64_t kMaxSamplingTests = 2000000000;

/// The ray–triangle tests `sampling` makes on a mesh of `triangles` with these options (saturating).
std::uint64_t samplingTests(std::size_t triangles, const MeshMassOptions& options);

/// Validates the mesh (validatedClosedMesh) and computes its mass properties by `options.method`.
/// Throws MeshError for an unusable mesh, or for sampling beyond kMaxSamplingTests, and std::invalid_argument
/// for a mass/density that is not > 0.
MeshMassProperties meshMassProperties(const TriangleMesh& mesh, const MeshMassOptions& options);

/// The body frame B of a mesh body: origin at the centre of mass, axes those of the mesh or, with
/// `principal_axes`, the principal axes (then the inertia is diagonal, ascending).
struct MeshBody {
  MassProperties mass;  ///< mass and I_Bcm_B, validated (positive definite, triangle inequality)
  Eigen::Isometry3d X_MB = Eigen::Isometry3d::Identity();  ///< pose of B in the mesh frame M
};

/// Builds the validated body from mesh mass properties. Throws InvalidMassProperties if the tensor is not
/// physical (it always is for the exact method on a valid mesh).
MeshBody meshBody(const MeshMassProperties& properties, bool principal_axes);

/// True if `point` is inside the closed mesh, by the parity of crossings of a ray (Möller–Trumbore).
bool isInside(const TriangleMesh& mesh, const Eigen::Vector3d& point);

}  // namespace rigid_body
