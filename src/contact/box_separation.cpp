#include "box_separation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigid_body {
namespace contact {

namespace {

// Edges closer to parallel than this (the sine of their angle) give no axis of their own: their cross
// product's direction is rounding, and the face axes already hold what such a pair of edges separates.
constexpr double kParallelSine = 1e-6;

// How much farther apart an edge axis must put the boxes than the best face axis to be taken: a share of the
// boxes' largest half extent (two boxes face to face have cross products equal to the face's normal, to
// rounding), and where they overlap a share of the face axis's depth too (a face gives the pair its four
// points, an edge one; Bullet's and ODE's box–box tests prefer faces by the same 5 %).
constexpr double kEdgePreference = 1e-9;
constexpr double kEdgeDepthPreference = 0.05;

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

// The gap between the boxes' shadows on the unit axis L: |L·d| − Σ hₐ,ᵢ |L·Aᵢ| − Σ h_b,ⱼ |L·Bⱼ|, d from a's
// centre to b's.
double gapAlong(const Eigen::Vector3d& L, const Eigen::Vector3d& d, const Eigen::Matrix3d& A, const Eigen::Vector3d& half_a,
                const Eigen::Matrix3d& B, const Eigen::Vector3d& half_b) {
  return std::abs(L.dot(d)) - half_a.dot((A.transpose() * L).cwiseAbs()) - half_b.dot((B.transpose() * L).cwiseAbs());
}

// A box's point farthest along `direction` (a corner).
Eigen::Vector3d support(const Eigen::Vector3d& centre, const Eigen::Matrix3d& R, const Eigen::Vector3d& half,
                        const Eigen::Vector3d& direction) {
  Eigen::Vector3d p = centre;
  for (int k = 0; k < 3; ++k) p += sign(R.col(k).dot(direction)) * half[k] * R.col(k);
  return p;
}

// The centre of a box's edge along axis i that lies farthest along `direction`.
Eigen::Vector3d edgeCentre(const Eigen::Vector3d& centre, const Eigen::Matrix3d& R, const Eigen::Vector3d& half, int i,
                           const Eigen::Vector3d& direction) {
  Eigen::Vector3d p = centre;
  for (int k = 0; k < 3; ++k) {
    if (k != i) p += sign(R.col(k).dot(direction)) * half[k] * R.col(k);
  }
  return p;
}

}  // namespace

BoxSeparation separateBoxes(const Eigen::Isometry3d& X_WA, const Eigen::Vector3d& half_a, const Eigen::Isometry3d& X_WB,
                            const Eigen::Vector3d& half_b) {
  const Eigen::Matrix3d A = X_WA.linear(), B = X_WB.linear();
  const Eigen::Vector3d p_a = X_WA.translation(), p_b = X_WB.translation();
  const Eigen::Vector3d d = p_b - p_a;
  // The three face normals of each box, then the nine cross products of their edges.
  int best = -1;
  double gap = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  for (int f = 0; f < 6; ++f) {
    const Eigen::Vector3d L = f < 3 ? Eigen::Vector3d(A.col(f)) : Eigen::Vector3d(B.col(f - 3));
    const double g = gapAlong(L, d, A, half_a, B, half_b);
    if (g > gap) best = f, gap = g, axis = L;
  }
  const double face_gap = gap;
  const double preference = std::max(kEdgePreference * std::max(half_a.maxCoeff(), half_b.maxCoeff()),
                                     kEdgeDepthPreference * std::max(0.0, -face_gap));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d cross = A.col(i).cross(B.col(j));
      const double length = cross.norm();
      if (!(length > kParallelSine)) continue;
      const Eigen::Vector3d L = cross / length;
      const double g = gapAlong(L, d, A, half_a, B, half_b);
      if (g > gap && g > face_gap + preference) best = 6 + 3 * i + j, gap = g, axis = L;
    }
  }
  BoxSeparation out;
  if (best < 0) {  // no gap compared: a pose or size not finite
    out.distance = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  out.distance = gap;
  out.normal = axis.dot(d) > 0.0 ? Eigen::Vector3d(-axis) : axis;  // from b towards a
  const Eigen::Vector3d& n = out.normal;
  if (best < 3) {  // a's face: over b's corner nearest a
    out.on_b = support(p_b, B, half_b, n);
    out.on_a = out.on_b + gap * n;
  } else if (best < 6) {  // b's face: under a's corner nearest b
    out.on_a = support(p_a, A, half_a, -n);
    out.on_b = out.on_a - gap * n;
  } else {  // the nearest points of a's edge along Aᵢ and b's along Bⱼ, the edges that face each other
    const int i = (best - 6) / 3, j = (best - 6) % 3;
    const Eigen::Vector3d c_a = edgeCentre(p_a, A, half_a, i, -n), c_b = edgeCentre(p_b, B, half_b, j, n);
    const Eigen::Vector3d u = A.col(i), v = B.col(j), r = c_a - c_b;
    // min |r + s u − t v|²: s − (u·v) t = −u·r and (u·v) s − t = −v·r.
    const double uv = u.dot(v), denominator = 1.0 - uv * uv;
    const double s = (uv * v.dot(r) - u.dot(r)) / denominator;
    const double t = v.dot(r) + s * uv;
    out.edges = true;
    out.edges_cross = std::abs(s) <= half_a[i] && std::abs(t) <= half_b[j];
    out.on_a = c_a + s * u;
    out.on_b = c_b + t * v;
  }
  return out;
}

}  // namespace contact
}  // namespace rigid_body
