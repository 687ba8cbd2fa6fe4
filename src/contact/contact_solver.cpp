#include "contact_solver.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace rigid_body {
namespace contact {

namespace {

SolverBody& bodyOf(std::vector<SolverBody>& bodies, std::size_t index, SolverBody& fixed) {
  return index == kStatic ? fixed : bodies[index];
}

// The velocity change of a point r of a body per unit impulse j applied there: K = M⁻¹ 1 − [r]× I⁻¹ [r]×,
// so that Δv_point = K j. For two bodies the contact's K is the sum.
Eigen::Matrix3d pointInverseMass(const SolverBody& body, const Eigen::Vector3d& r) {
  Eigen::Matrix3d r_cross;
  r_cross << 0.0, -r.z(), r.y(), r.z(), 0.0, -r.x(), -r.y(), r.x(), 0.0;
  return body.inverse_mass * Eigen::Matrix3d::Identity() - r_cross * body.inverse_inertia_W * r_cross;
}

void applyImpulse(std::vector<SolverBody>& bodies, const SolverContact& c, const Eigen::Vector3d& impulse) {
  if (c.a != kStatic) {
    SolverBody& a = bodies[c.a];
    const Eigen::Vector3d angular = c.r_a.cross(impulse);
    a.v += a.inverse_mass * impulse, a.w += a.inverse_inertia_W * angular;
    a.dP += impulse, a.dL += angular, a.touched = true;
  }
  if (c.b != kStatic) {
    SolverBody& b = bodies[c.b];
    const Eigen::Vector3d angular = c.r_b.cross(impulse);
    b.v -= b.inverse_mass * impulse, b.w -= b.inverse_inertia_W * angular;
    b.dP -= impulse, b.dL -= angular, b.touched = true;
  }
}

}  // namespace

Eigen::Vector3d relativeVelocity(const SolverContact& c, const std::vector<SolverBody>& bodies) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  if (c.a != kStatic) v += bodies[c.a].v + bodies[c.a].w.cross(c.r_a);
  if (c.b != kStatic) v -= bodies[c.b].v + bodies[c.b].w.cross(c.r_b);
  return v;
}

void prepareContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options) {
  SolverBody fixed;
  for (SolverContact& c : contacts) {
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
    if (c.a != kStatic) K += pointInverseMass(bodyOf(bodies, c.a, fixed), c.r_a);
    if (c.b != kStatic) K += pointInverseMass(bodyOf(bodies, c.b, fixed), c.r_b);
    const double k_n = c.n.dot(K * c.n);
    c.normal_mass = k_n > 0.0 ? 1.0 / k_n : 0.0;
    Eigen::Matrix<double, 3, 2> T;
    T << c.t1, c.t2;
    const Eigen::Matrix2d k_t = T.transpose() * K * T;
    c.tangent_mass = k_t.determinant() > 0.0 ? Eigen::Matrix2d(k_t.inverse()) : Eigen::Matrix2d::Zero();
    // Newton's law: the normal speed after is −e times the speed before, for approaches fast enough to bounce.
    const double approach = c.n.dot(relativeVelocity(c, bodies));
    c.target_speed = 0.0;
    if (options.bounce && approach < -options.restitution_threshold) c.target_speed = -c.restitution * approach;
    // Speculative: a contact still apart may close its gap, but no more, within the next step.
    if (c.separation > 0.0 && options.dt > 0.0) c.target_speed = std::min(c.target_speed, -c.separation / options.dt);
  }
  for (SolverContact& c : contacts) {  // warm start: last step's impulses as the first guess
    if (c.normal_impulse > 0.0 || !c.friction_impulse.isZero(0.0)) {
      applyImpulse(bodies, c, c.normal_impulse * c.n + c.friction_impulse.x() * c.t1 + c.friction_impulse.y() * c.t2);
    }
  }
}

void solveVelocities(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options) {
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    double largest_change = 0.0, largest_impulse = 0.0;
    for (SolverContact& c : contacts) {
      // Normal: v_n ≥ target, impulse ≥ 0 (a contact pushes, never pulls).
      const double v_n = c.n.dot(relativeVelocity(c, bodies));
      const double normal = std::max(0.0, c.normal_impulse - c.normal_mass * (v_n - c.target_speed));
      const double dn = normal - c.normal_impulse;
      c.normal_impulse = normal;
      if (dn != 0.0) applyImpulse(bodies, c, dn * c.n);
      // Friction: stop the sliding, within the disc |f| ≤ μ n (Coulomb's cone, not a pyramid).
      const Eigen::Vector3d v = relativeVelocity(c, bodies);
      const Eigen::Vector2d slip(c.t1.dot(v), c.t2.dot(v));
      Eigen::Vector2d friction = c.friction_impulse - c.tangent_mass * slip;
      const double limit = c.friction * c.normal_impulse;
      if (friction.norm() > limit) {
        // Sliding: dynamic friction opposes the slip at full strength (maximal dissipation). Scaling the
        // sticking impulse back onto the disc instead would turn part of it sideways wherever the contact's
        // tangent mass is not isotropic (a box's corner), and brake a sliding box too little.
        const double slip_speed = slip.norm();
        friction = slip_speed > 0.0 ? Eigen::Vector2d(-limit * slip / slip_speed) : Eigen::Vector2d(friction * (limit / friction.norm()));
      }
      const Eigen::Vector2d df = friction - c.friction_impulse;
      c.friction_impulse = friction;
      if (!df.isZero(0.0)) applyImpulse(bodies, c, df.x() * c.t1 + df.y() * c.t2);
      largest_change = std::max({largest_change, std::abs(dn), df.lpNorm<Eigen::Infinity>()});
      largest_impulse = std::max({largest_impulse, c.normal_impulse, c.friction_impulse.lpNorm<Eigen::Infinity>()});
    }
    if (largest_change <= 1e-14 * largest_impulse) break;  // converged to rounding
  }
}

void projectPositions(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, int iterations,
                      double slop, double correction) {
  SolverBody fixed;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    double deepest = 0.0;
    for (SolverContact& c : contacts) {
      // The separation now, to first order in what the bodies have moved since detection.
      double separation = c.separation;
      if (c.a != kStatic) separation += c.n.dot(bodies[c.a].dx + bodies[c.a].dtheta.cross(c.r_a));
      if (c.b != kStatic) separation -= c.n.dot(bodies[c.b].dx + bodies[c.b].dtheta.cross(c.r_b));
      const double error = separation + slop;
      if (error >= 0.0) continue;
      deepest = std::min(deepest, error);
      const double push = -correction * error * c.normal_mass;
      const Eigen::Vector3d impulse = push * c.n;
      if (c.a != kStatic) {
        SolverBody& a = bodyOf(bodies, c.a, fixed);
        a.dx += a.inverse_mass * impulse, a.dtheta += a.inverse_inertia_W * c.r_a.cross(impulse), a.touched = true;
      }
      if (c.b != kStatic) {
        SolverBody& b = bodyOf(bodies, c.b, fixed);
        b.dx -= b.inverse_mass * impulse, b.dtheta -= b.inverse_inertia_W * c.r_b.cross(impulse), b.touched = true;
      }
    }
    if (deepest == 0.0) break;
  }
}

}  // namespace contact
}  // namespace rigid_body
