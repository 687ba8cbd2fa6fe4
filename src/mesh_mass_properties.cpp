#include "rigid_body_sim/mesh_mass_properties.hpp"

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace rigid_body {

namespace {

const std::array<std::string, 4> kMethodNames = {"exact", "sampling", "bounding_box", "oriented_bounding_box"};

// The ray of the inside test: a direction with no simple relation to the axes, so that rays through
// points of axis-aligned meshes do not graze edges or vertices.
const Eigen::Vector3d kRayDirection = Eigen::Vector3d(1.0, 0.3711, 0.2163).normalized();

Eigen::Matrix3d boxInertia(double mass, const Eigen::Vector3d& size) {
  return boxPrincipalMoments(mass, size).asDiagonal();
}

// Eberly's subexpressions for one coordinate of a triangle's corners.
struct Sub {
  double f1, f2, f3, g0, g1, g2;
};

Sub subexpressions(double w0, double w1, double w2) {
  Sub s;
  const double temp0 = w0 + w1;
  s.f1 = temp0 + w2;
  const double temp1 = w0 * w0;
  const double temp2 = temp1 + w1 * temp0;
  s.f2 = temp2 + w2 * s.f1;
  s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
  s.g0 = s.f2 + w0 * (s.f1 + w0);
  s.g1 = s.f2 + w1 * (s.f1 + w1);
  s.g2 = s.f2 + w2 * (s.f1 + w2);
  return s;
}

// The exact volume integrals of 1, x, y, z, x², y², z², xy, yz, zx over the solid (density 1), by the
// divergence theorem applied triangle by triangle (Eberly 2002, §4).
std::array<double, 10> volumeIntegrals(const TriangleMesh& mesh) {
  std::array<double, 10> integral{};
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& p0 = mesh.vertices[t[0]];
    const Eigen::Vector3d& p1 = mesh.vertices[t[1]];
    const Eigen::Vector3d& p2 = mesh.vertices[t[2]];
    const Eigen::Vector3d d = (p1 - p0).cross(p2 - p0);
    const Sub x = subexpressions(p0.x(), p1.x(), p2.x());
    const Sub y = subexpressions(p0.y(), p1.y(), p2.y());
    const Sub z = subexpressions(p0.z(), p1.z(), p2.z());
    integral[0] += d.x() * x.f1;
    integral[1] += d.x() * x.f2;
    integral[2] += d.y() * y.f2;
    integral[3] += d.z() * z.f2;
    integral[4] += d.x() * x.f3;
    integral[5] += d.y() * y.f3;
    integral[6] += d.z() * z.f3;
    integral[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    integral[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    integral[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  const std::array<double, 10> scale = {1.0 / 6,   1.0 / 24,  1.0 / 24,  1.0 / 24,  1.0 / 60,
                                        1.0 / 60,  1.0 / 60,  1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (size_t i = 0; i < integral.size(); ++i) integral[i] *= scale[i];
  return integral;
}

void exact(const TriangleMesh& input, MeshMassProperties& out) {
  // Integrate about a point near the body (the vertex mean), not the mesh origin: for a part modelled far
  // from its origin the parallel-axis shift below would otherwise cancel m|c|² against the tensor and lose
  // digits (a 10 cm bracket 2.3 m away lost 3e-11 relative).
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  for (const auto& p : input.vertices) reference += p;
  reference /= static_cast<double>(input.vertices.size());
  TriangleMesh mesh = input;
  for (auto& p : mesh.vertices) p -= reference;
  const std::array<double, 10> v = volumeIntegrals(mesh);
  const double density = out.mass / v[0];
  const Eigen::Vector3d c(v[1] / v[0], v[2] / v[0], v[3] / v[0]);
  out.p_MBcm = c + reference;
  // ∫ (|r|²𝟙 − r rᵀ) about the origin, then moved to the centre of mass (parallel-axis theorem).
  Eigen::Matrix3d I;
  I(0, 0) = v[5] + v[6];
  I(1, 1) = v[4] + v[6];
  I(2, 2) = v[4] + v[5];
  I(0, 1) = I(1, 0) = -v[7];
  I(1, 2) = I(2, 1) = -v[8];
  I(0, 2) = I(2, 0) = -v[9];
  out.I_Bcm_M = density * I - out.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

// The points sampling draws: `samples`, or for a stratified grid the n³ cells nearest to it.
std::uint64_t samplingDraws(const MeshMassOptions& options, int& cells) {
  cells = std::max(1, static_cast<int>(std::round(std::cbrt(static_cast<double>(options.samples)))));
  return options.stratified ? static_cast<std::uint64_t>(cells) * cells * cells : options.samples;
}

void sampling(const TriangleMesh& mesh, const MeshMassOptions& options, MeshMassProperties& out) {
  const std::uint64_t tests = samplingTests(mesh.triangles.size(), options);
  if (tests > kMaxSamplingTests) {
    throw MeshError("sampling: " + std::to_string(options.samples) + " samples on " +
                    std::to_string(mesh.triangles.size()) + " triangles are " + std::to_string(tests) +
                    " ray-triangle tests, more than the limit of " + std::to_string(kMaxSamplingTests) +
                    " (~10 s): use fewer samples or the exact method");
  }
  Eigen::AlignedBox3d bounds;
  for (const auto& p : mesh.vertices) bounds.extend(p);
  const Eigen::Vector3d size = bounds.sizes();
  std::mt19937_64 generator(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Stratified: a grid of n³ ≈ samples cells with one jittered point each.
  int cells = 1;
  const std::uint64_t draws = samplingDraws(options, cells);
  std::vector<Eigen::Vector3d> inside;
  inside.reserve(draws);
  for (std::uint64_t k = 0; k < draws; ++k) {
    Eigen::Vector3d u(unit(generator), unit(generator), unit(generator));
    if (options.stratified) {
      const Eigen::Vector3d cell(static_cast<double>(k % cells), static_cast<double>((k / cells) % cells),
                                 static_cast<double>(k / (static_cast<std::uint64_t>(cells) * cells)));
      u = (cell + u) / cells;
    }
    const Eigen::Vector3d p = bounds.min() + u.cwiseProduct(size);
    if (isInside(mesh, p)) inside.push_back(p);
  }
  out.inside_samples = inside.size();
  if (inside.empty()) throw MeshError("sampling found no point inside the mesh: raise ~samples");
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : inside) c += p;
  c /= static_cast<double>(inside.size());
  out.p_MBcm = c;
  // Each inside point carries mass/N_in; I = Σ m (|r|²𝟙 − r rᵀ) about the sampled centre of mass. The
  // standard error is that of a mean of N_in i.i.d. contributions (an upper estimate when stratified).
  const double n = static_cast<double>(inside.size());
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero(), sum_squares = Eigen::Matrix3d::Zero();
  for (const auto& p : inside) {
    const Eigen::Vector3d r = p - c;
    const Eigen::Matrix3d f = r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose();
    sum += f;
    sum_squares += f.cwiseProduct(f);
  }
  const Eigen::Matrix3d mean = sum / n;
  out.I_Bcm_M = out.mass * mean;
  const Eigen::Matrix3d variance = (sum_squares / n - mean.cwiseProduct(mean)).cwiseMax(0.0);
  out.inertia_standard_error = out.mass * std::sqrt(variance.sum() / n);
}

void boundingBox(const TriangleMesh& mesh, bool oriented, MeshMassProperties& out) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // box axes in M
  if (oriented) {
    // The box's axes: principal axes of the vertices' covariance (cheap, no volume integrals).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : mesh.vertices) mean += p;
    mean /= static_cast<double>(mesh.vertices.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto& p : mesh.vertices) covariance += (p - mean) * (p - mean).transpose();
    R = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors();
  }
  Eigen::AlignedBox3d bounds;
  for (const auto& p : mesh.vertices) bounds.extend(R.transpose() * p);
  out.p_MBcm = R * bounds.center();
  out.I_Bcm_M = R * boxInertia(out.mass, bounds.sizes()) * R.transpose();
}

}  // namespace

const std::string& inertiaMethodName(InertiaMethod method) { return kMethodNames.at(static_cast<size_t>(method)); }

InertiaMethod inertiaMethodFromName(const std::string& name) {
  for (size_t i = 0; i < kMethodNames.size(); ++i) {
    if (kMethodNames[i] == name) return static_cast<InertiaMethod>(i);
  }
  throw std::invalid_argument("unknown inertia method '" + name +
                              "', valid: exact, sampling, bounding_box, oriented_bounding_box");
}

std::uint64_t samplingTests(std::size_t triangles, const MeshMassOptions& options) {
  int cells = 1;
  std::uint64_t tests = 0;
  if (__builtin_mul_overflow(samplingDraws(options, cells), static_cast<std::uint64_t>(triangles), &tests)) {
    return std::numeric_limits<std::uint64_t>::max();
  }
  return tests;
}

bool isInside(const TriangleMesh& mesh, const Eigen::Vector3d& point) {
  int crossings = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d e1 = mesh.vertices[t[1]] - a, e2 = mesh.vertices[t[2]] - a;
    const Eigen::Vector3d h = kRayDirection.cross(e2);
    const double det = e1.dot(h);
    if (det == 0.0) continue;  // the ray is parallel to the triangle
    const double inverse = 1.0 / det;
    const Eigen::Vector3d s = point - a;
    const double u = inverse * s.dot(h);
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = inverse * kRayDirection.dot(q);
    if (v < 0.0 || u + v > 1.0) continue;
    if (inverse * e2.dot(q) > 0.0) ++crossings;
  }
  return crossings % 2 == 1;
}

MeshBody meshBody(const MeshMassProperties& properties, bool principal_axes) {
  MeshBody body;
  body.mass = MassProperties::fromInertia(properties.mass, properties.I_Bcm_M);
  body.X_MB.translation() = properties.p_MBcm;
  if (principal_axes) {
    const Eigen::Matrix3d R_MB = body.mass.principalAxes();  // a proper rotation
    body.X_MB.linear() = R_MB;
    body.mass = MassProperties::fromInertia(properties.mass, R_MB.transpose() * properties.I_Bcm_M * R_MB);
  }
  return body;
}

MeshMassProperties meshMassProperties(const TriangleMesh& input, const MeshMassOptions& options) {
  MeshMassProperties out;
  const TriangleMesh mesh = validatedClosedMesh(input, out.warnings);
  out.volume = signedVolume(mesh);
  if (options.mass > 0.0 && std::isfinite(options.mass)) {
    out.mass = options.mass;
  } else if (options.density > 0.0 && std::isfinite(options.density)) {
    out.mass = options.density * out.volume;
  } else {
    throw std::invalid_argument("give a mass > 0 [kg] or a density > 0 [kg/m^3]");
  }
  switch (options.method) {
    case InertiaMethod::kExact:
      exact(mesh, out);
      break;
    case InertiaMethod::kSampling:
      sampling(mesh, options, out);
      break;
    case InertiaMethod::kBoundingBox:
      boundingBox(mesh, false, out);
      break;
    case InertiaMethod::kOrientedBoundingBox:
      boundingBox(mesh, true, out);
      break;
  }
  return out;
}

}  // namespace rigid_body
