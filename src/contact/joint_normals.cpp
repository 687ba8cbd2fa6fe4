#include "joint_normals.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace rigid_body {
namespace contact {

namespace {

// A face's points must spread in both of its directions for its three coordinates to be told apart: the
// centred second moments' determinant against their trace squared (1 for a square, 0 for a line).
constexpr double kLeastSpread = 1e-6;
// Two points are inverted together only while K is this far from singular (Box2D's two-point block
// solver's guard: k₁₁² < 1000 det K).
constexpr double kTwoPointConditioning = 1000.0;

// K_ij = J_i M⁻¹ J_jᵀ for the normal rows: (1/m_a + 1/m_b) n_i·n_j + (r_a,i × n_i)·I_a⁻¹(r_a,j × n_j) + (same for b).
Eigen::Matrix4d normalCoupling(const SolverContact* points, std::size_t count, double inverse_mass_a,
                               double inverse_mass_b) {
  Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t j = i; j < count; ++j) {  // symmetric: I⁻¹ is
      const SolverContact& p = points[i];
      const SolverContact& q = points[j];
      K(i, j) = (inverse_mass_a + inverse_mass_b) * p.n.dot(q.n) + p.cross_a.col(0).dot(q.response_a.col(0)) +
                p.cross_b.col(0).dot(q.response_b.col(0));
      K(j, i) = K(i, j);
    }
  }
  return K;
}

}  // namespace

// Three or four points of a face: a rigid pair's normal velocity at point i is v_i = α + β₁ u_i + β₂ w_i, with
// (u_i, w_i) the point's place on the face about the points' centre (α the face's normal speed, β its tilt
// rates), so J = P J_r with P = [1 u_i w_i] and K = P K_r Pᵀ has rank three. For a residual r in the range of P
// (every residual a rigid motion leaves), the least-norm Δλ with K Δλ = r is Δλ = Gᵀ K_r⁻¹ G r with
// G = (PᵀP)⁻¹ Pᵀ (G P = I, so K_r = G K Gᵀ): docs/references.md, "A face's normal impulses together".
bool jointNormalInverse(const SolverContact* points, std::size_t count, double inverse_mass_a,
                        double inverse_mass_b, JointInverse& inverse) {
  if (count < 2 || count > kMaxManifoldPoints) return false;
  const Eigen::Matrix4d K = normalCoupling(points, count, inverse_mass_a, inverse_mass_b);
  Eigen::Matrix4d B = Eigen::Matrix4d::Zero();
  if (count == 2) {
    const double det = K(0, 0) * K(1, 1) - K(0, 1) * K(1, 0);
    if (!(K(0, 0) * K(0, 0) < kTwoPointConditioning * det)) return false;
    B(0, 0) = K(1, 1) / det, B(0, 1) = -K(0, 1) / det;
    B(1, 0) = -K(1, 0) / det, B(1, 1) = K(0, 0) / det;
  } else {
    const bool on_a = points[0].a != kEnvironment;
    const auto arm = [&](std::size_t i) -> const Eigen::Vector3d& { return on_a ? points[i].r_a : points[i].r_b; };
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < count; ++i) centre += arm(i);
    centre /= static_cast<double>(count);
    Eigen::Matrix<double, 4, 3> P = Eigen::Matrix<double, 4, 3>::Zero();
    for (std::size_t i = 0; i < count; ++i) {
      const Eigen::Vector3d d = arm(i) - centre;
      P(i, 0) = 1.0, P(i, 1) = d.dot(points[0].t1), P(i, 2) = d.dot(points[0].t2);
    }
    const Eigen::Matrix3d moments = P.transpose() * P;
    const double trace = moments(1, 1) + moments(2, 2);
    const double spread = moments(1, 1) * moments(2, 2) - moments(1, 2) * moments(2, 1);
    if (!(spread > kLeastSpread * trace * trace)) return false;
    const Eigen::Matrix<double, 3, 4> G = moments.inverse() * P.transpose();
    const Eigen::LLT<Eigen::Matrix3d> reduced(G * K * G.transpose());
    if (reduced.info() != Eigen::Success) return false;
    B = G.transpose() * reduced.solve(G);
  }
  if (!B.allFinite()) return false;
  for (std::size_t i = 0; i < kMaxManifoldPoints; ++i) {
    for (std::size_t j = i; j < kMaxManifoldPoints; ++j) inverse[jointEntry(i, j)] = B(i, j);
  }
  return true;
}

void jointManifolds(const std::vector<SolverContact>& contacts, std::size_t begin, std::size_t end,
                    std::vector<JointManifold>& manifolds) {
  manifolds.clear();
  for (std::size_t k = begin; k < end;) {
    JointManifold& m = manifolds.emplace_back();
    m.first = k;
    m.count = manifoldLength(contacts, k, end);
    k += m.count;
  }
}

bool solveJointNormals(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                       JointManifold& manifold, double& largest_change) {
  if (manifold.inverted && !manifold.joint) return false;
  double residual[kMaxManifoldPoints] = {}, next[kMaxManifoldPoints] = {};
  bool moving = false;  // some point's residual beyond kFaceAtRest
  for (std::size_t p = 0; p < manifold.count; ++p) {
    const SolverContact& c = contacts[manifold.first + p];
    residual[p] = c.target_speed - normalSpeed(c, bodies[c.a], bodies[c.b]);
    moving = moving || std::abs(c.normal_mass * residual[p]) > kFaceAtRest * c.normal_impulse;
  }
  if (!moving) return false;
  if (!manifold.inverted) {
    const SolverContact& c = contacts[manifold.first];  // the environment's entry has zero inverse mass
    manifold.joint = jointNormalInverse(&c, manifold.count, bodies[c.a].inverse_mass, bodies[c.b].inverse_mass,
                                        manifold.inverse);
    manifold.inverted = true;
    if (!manifold.joint) return false;
  }
  for (std::size_t p = 0; p < manifold.count; ++p) {
    const SolverContact& c = contacts[manifold.first + p];
    double increment = 0.0;
    for (std::size_t q = 0; q < manifold.count; ++q) {
      increment += manifold.inverse[jointEntry(p, q)] * residual[q];
    }
    next[p] = c.normal_impulse + increment;
    if (!(next[p] >= c.normal_floor)) return false;  // it would pull somewhere: point by point instead
  }
  for (std::size_t p = 0; p < manifold.count; ++p) {
    SolverContact& c = contacts[manifold.first + p];
    const double dn = next[p] - c.normal_impulse;
    c.normal_impulse = next[p];
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    if (c.a != kEnvironment) a.v += a.inverse_mass * dn * c.n, a.w += dn * c.response_a.col(0);
    if (c.b != kEnvironment) b.v -= b.inverse_mass * dn * c.n, b.w -= dn * c.response_b.col(0);
    largest_change = std::max(largest_change, std::abs(dn));
  }
  return true;
}

}  // namespace contact
}  // namespace rigid_body
