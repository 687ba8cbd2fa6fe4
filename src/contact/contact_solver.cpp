#include "contact_solver.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "friction_disc.hpp"
#include "joint_normals.hpp"
#include "sticking_solve.hpp"

namespace rigid_body {
namespace contact {

namespace {

// The share of the energy change's terms within which limitEnergyGain takes a gain for rounding: the sums'
// rounding is of order 1e-16 of them.
constexpr double kEnergyGainTolerance = 1e-9;

// The velocity change of body `s` along its three Jacobian columns (linear part d, angular part r × d) per
// unit impulse along d: J_d = (d, r × d), and the contact's velocity along d is d·v + (r × d)·ω.
// The environment (either side may be it) does not move and is not written: islands on other threads share
// its entry.
inline void applyImpulse(SolverBody& a, SolverBody& b, const SolverContact& c, const Eigen::Vector3d& linear,
                         const Eigen::Vector3d& coefficients) {
  if (c.a != kEnvironment) {
    a.v += a.inverse_mass * linear;
    a.w += c.response_a * coefficients;
  }
  if (c.b != kEnvironment) {
    b.v -= b.inverse_mass * linear;
    b.w -= c.response_b * coefficients;
  }
}

}  // namespace

SolverBody environmentBody() { return SolverBody(); }

std::size_t allowedSweeps(const SolveOptions& options, std::size_t contacts) {
  const std::size_t shared = std::max(options.budget_contacts, contacts);
  const std::size_t budget =
      static_cast<std::size_t>(std::max(options.iterations, 0)) * std::max(options.sweep_budget_contacts, shared);
  return contacts == 0 ? 0 : budget / shared;
}

Eigen::Vector3d relativeVelocity(const SolverContact& c, const std::vector<SolverBody>& bodies) {
  const SolverBody& a = bodies[c.a];
  const SolverBody& b = bodies[c.b];
  return a.v + a.w.cross(c.r_a) - b.v - b.w.cross(c.r_b);
}

void prepareContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options) {
  prepareContacts(contacts, bodies, options, SolveRange::all(contacts.size(), bodies.size()));
}

void prepareContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options,
                     const SolveRange& range) {
  prepareContactRows(contacts, bodies, options, range.contact_begin, range.contact_end);
  applyWarmStarts(contacts, bodies, range);
}

void prepareContactRows(std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                        const SolveOptions& options, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin; k < end; ++k) {
    SolverContact& c = contacts[k];
    const SolverBody& a = bodies[c.a];
    const SolverBody& b = bodies[c.b];
    const Eigen::Vector3d* directions[3] = {&c.n, &c.t1, &c.t2};
    for (int j = 0; j < 3; ++j) {
      c.cross_a.col(j) = c.r_a.cross(*directions[j]);
      c.cross_b.col(j) = c.r_b.cross(*directions[j]);
    }
    c.response_a.noalias() = a.inverse_inertia_W * c.cross_a;
    c.response_b.noalias() = b.inverse_inertia_W * c.cross_b;
    // K in the contact's directions, (1/M_a + 1/M_b) 1 + (r_a×D)ᵀ I_a⁻¹ (r_a×D) + the same for b: only the
    // entries the solve reads, the normal's and the tangents' block, whose two off-diagonal entries are one
    // (K is symmetric: I⁻¹ is).
    const double mass = a.inverse_mass + b.inverse_mass;
    const auto entry = [&c](int i, int j) {
      return c.cross_a.col(i).dot(c.response_a.col(j)) + c.cross_b.col(i).dot(c.response_b.col(j));
    };
    const double k00 = mass + entry(0, 0), k11 = mass + entry(1, 1), k22 = mass + entry(2, 2), k12 = entry(1, 2);
    c.normal_mass = k00 > 0.0 ? 1.0 / k00 : 0.0;
    c.tangent_response << k11, k12, k12, k22;
    const double determinant = k11 * k22 - k12 * k12;
    if (determinant > 0.0) {
      c.tangent_mass << k22, -k12, -k12, k11;
      c.tangent_mass /= determinant;
    } else {
      c.tangent_mass.setZero();
    }
    // Newton's law: the normal speed after is −e times the speed before, for approaches fast enough to bounce.
    const double approach = c.n.dot(relativeVelocity(c, bodies));
    c.target_speed = 0.0;
    if (options.bounce && approach < -options.restitution_threshold) c.target_speed = -c.restitution * approach;
    // Speculative: a contact still apart may close its gap, but no more, within the next step.
    if (c.separation > 0.0 && options.dt > 0.0) c.target_speed = std::min(c.target_speed, -c.separation / options.dt);
  }
}

void applyWarmStarts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range) {
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {  // last step's impulses
    const SolverContact& c = contacts[k];
    const Eigen::Vector3d coefficients(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
    if (coefficients.isZero(0.0)) continue;
    applyImpulse(bodies[c.a], bodies[c.b], c, c.n * coefficients.x() + c.t1 * coefficients.y() + c.t2 * coefficients.z(),
                 coefficients);
  }
}

bool solveVelocities(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options) {
  return solveVelocities(contacts, bodies, options, SolveRange::all(contacts.size(), bodies.size()));
}

namespace {

// Normal: v_n ≥ target, impulse ≥ its floor (a contact pushes, never pulls). Returns the impulse's change.
double solvePointNormal(SolverContact& c, SolverBody& a, SolverBody& b) {
  const double normal =
      std::max(c.normal_floor, c.normal_impulse - c.normal_mass * (normalSpeed(c, a, b) - c.target_speed));
  const double dn = normal - c.normal_impulse;
  c.normal_impulse = normal;
  if (dn != 0.0) applyImpulse(a, b, c, dn * c.n, Eigen::Vector3d(dn, 0.0, 0.0));
  return dn;
}

// Friction: stop the slip if the disc |f| ≤ μ f_n allows; else slide with μ f_n against the slip. (Scaling
// the sticking impulse back onto the disc instead turns part of it sideways wherever the tangent mass is
// not isotropic, as at a box's corner, and brakes a sliding box too little.) Returns the impulse's change.
Eigen::Vector2d solvePointFriction(SolverContact& c, SolverBody& a, SolverBody& b) {
  const Eigen::Vector2d slip(rowSpeed(c, 1, a, b), rowSpeed(c, 2, a, b));
  c.slip_squared = slip.squaredNorm();
  Eigen::Vector2d friction = c.friction_impulse - c.tangent_mass * slip;
  const double limit = c.friction * c.normal_impulse;
  if (friction.squaredNorm() > limit * limit) friction = ontoFrictionDisc(friction, c.tangent_response, limit);
  const Eigen::Vector2d df = friction - c.friction_impulse;
  c.friction_impulse = friction;
  if (!df.isZero(0.0)) applyImpulse(a, b, c, df.x() * c.t1 + df.y() * c.t2, Eigen::Vector3d(0.0, df.x(), df.y()));
  return df;
}

}  // namespace

bool solveVelocities(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options,
                     const SolveRange& range) {
  bool converged = false;
  const std::size_t sweeps = allowedSweeps(options, range.contact_end - range.contact_begin);
  std::vector<JointManifold> manifolds;
  jointManifolds(contacts, range.contact_begin, range.contact_end, manifolds);
  for (std::size_t iteration = 0; iteration < sweeps && !converged; ++iteration) {
    double largest_change = 0.0, largest_impulse = 0.0;
    for (JointManifold& manifold : manifolds) {
      // A face's normals together first (joint_normals.hpp), then each point's normal and friction: the
      // points' own normal updates take up what the friction updates of the face's earlier points changed.
      solveJointNormals(contacts, bodies, manifold, largest_change);
      for (std::size_t k = manifold.first; k < manifold.first + manifold.count; ++k) {
        SolverContact& c = contacts[k];
        SolverBody& a = bodies[c.a];
        SolverBody& b = bodies[c.b];
        const double dn = solvePointNormal(c, a, b);
        const Eigen::Vector2d df = solvePointFriction(c, a, b);
        largest_change = std::max({largest_change, std::abs(dn), df.lpNorm<Eigen::Infinity>()});
        largest_impulse = std::max({largest_impulse, c.normal_impulse, c.friction_impulse.lpNorm<Eigen::Infinity>()});
      }
    }
    // To rounding within the sweeps asked for; beyond them (a small scene's budget), to a change of 1e-9 of
    // the impulses, far below anything a trajectory shows.
    const double tolerance = iteration < static_cast<std::size_t>(options.iterations) ? 1e-14 : 1e-9;
    converged = largest_change <= tolerance * largest_impulse;
  }
  sumImpulses(contacts, bodies, range);
  return converged;
}

void sumImpulses(const std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range) {
  // Summed once from the final impulses (not per update in the sweeps).
  for (std::size_t s = range.body_begin; s < range.body_end; ++s) bodies[s].dP.setZero(), bodies[s].dL.setZero();
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    const Eigen::Vector3d coefficients(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
    const Eigen::Vector3d impulse = c.n * coefficients.x() + c.t1 * coefficients.y() + c.t2 * coefficients.z();
    if (c.a != kEnvironment) bodies[c.a].dP += impulse, bodies[c.a].dL += c.cross_a * coefficients;
    if (c.b != kEnvironment) bodies[c.b].dP -= impulse, bodies[c.b].dL -= c.cross_b * coefficients;
  }
}

namespace {

// The bodies' velocities and summed impulses at one moment of an impact.
struct ImpactPhase {
  std::vector<Eigen::Vector3d> v, w, dP, dL;
  void take(const std::vector<SolverBody>& bodies) {
    v.resize(bodies.size()), w.resize(bodies.size()), dP.resize(bodies.size()), dL.resize(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      v[i] = bodies[i].v, w[i] = bodies[i].w, dP[i] = bodies[i].dP, dL[i] = bodies[i].dL;
    }
  }
};

// The change of kinetic energy between two moments, ΔT = ½ Σ (v₀ + v₁)·ΔP + (ω₀ + ω₁)·ΔL (M Δv = ΔP and
// I Δω = ΔL, I constant over the instant), split as ΔT(α) = α a + α² b for the change scaled by α.
void energyTerms(const ImpactPhase& from, const ImpactPhase& to, double& a, double& b) {
  a = 0.0, b = 0.0;
  for (std::size_t i = 0; i < from.v.size(); ++i) {
    const Eigen::Vector3d dP = to.dP[i] - from.dP[i], dL = to.dL[i] - from.dL[i];
    a += from.v[i].dot(dP) + from.w[i].dot(dL);
    b += 0.5 * ((to.v[i] - from.v[i]).dot(dP) + (to.w[i] - from.w[i]).dot(dL));
  }
}

// The largest α in [0, 1] with `base` + α a + α² b ≤ 0 (b ≥ 0, base ≤ 0): 1 if it holds there.
double largestShare(double base, double a, double b) {
  if (base + a + b <= 0.0) return 1.0;
  if (!(b > 0.0)) return a < 0.0 ? std::min(1.0, -base / a) : 0.0;
  const double root = (-a + std::sqrt(std::max(0.0, a * a - 4.0 * b * base))) / (2.0 * b);
  return std::clamp(root, 0.0, 1.0);
}

// Sets the bodies and contacts to the moment `from` plus α of the way to `to`.
void scaleBack(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const ImpactPhase& from,
               const ImpactPhase& to, const std::vector<Eigen::Vector3d>& impulses_from, double alpha) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].v = from.v[i] + alpha * (to.v[i] - from.v[i]);
    bodies[i].w = from.w[i] + alpha * (to.w[i] - from.w[i]);
    bodies[i].dP = from.dP[i] + alpha * (to.dP[i] - from.dP[i]);
    bodies[i].dL = from.dL[i] + alpha * (to.dL[i] - from.dL[i]);
  }
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    SolverContact& c = contacts[k];
    const Eigen::Vector3d& p0 = impulses_from[k];
    c.normal_impulse = p0.x() + alpha * (c.normal_impulse - p0.x());
    c.friction_impulse = p0.tail<2>() + alpha * (c.friction_impulse - p0.tail<2>());
  }
}

}  // namespace

void solveImpact(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options) {
  ImpactPhase before, compressed, restored;
  for (SolverBody& body : bodies) body.dP.setZero(), body.dL.setZero();
  before.take(bodies);
  // Compression: every point stopped (e = 0); what restitution each point has left waits for the next phase.
  std::vector<double> restitution(contacts.size());
  std::vector<Eigen::Vector3d> zero(contacts.size(), Eigen::Vector3d::Zero()), compression(contacts.size());
  // A point still apart keeps its speculative target (< 0: it may close its gap): it has not arrived, so it
  // neither bounces nor is stopped, only kept from passing the surface (located_impacts.cpp's arrivals).
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    restitution[k] = contacts[k].target_speed > 0.0 ? contacts[k].restitution : 0.0;
    contacts[k].target_speed = std::min(0.0, contacts[k].target_speed);
  }
  if (!solveVelocities(contacts, bodies, options)) {
    // Sweeps that run out before every point stops (a heavy body striking a light one that lies on the
    // ground: each sweep carries the light body's share of the momentum) left the light one going on into
    // what it lies on for the rest of the step. Stopping every point is the compression's aim, so the rows
    // solved at once as equalities give it wherever every point then pushes and holds within its disc
    // (sticking_solve.hpp; a point still apart keeps its target); else the sweeps' result stands.
    StickingScratch scratch;
    const SolveRange all = SolveRange::all(contacts.size(), bodies.size());
    const double no_sliding_limit = std::numeric_limits<double>::infinity();
    if (solveStickingIsland(contacts, bodies, all, 0.0, no_sliding_limit, scratch) == StickingOutcome::kSolved) {
      sumImpulses(contacts, bodies, all);
    }
  }
  compressed.take(bodies);
  double a = 0.0, b = 0.0;
  energyTerms(before, compressed, a, b);
  if (a + b > 0.0) {  // an unconverged compression that would gain: scaled back, and no restitution
    scaleBack(contacts, bodies, before, compressed, zero, largestShare(0.0, a, b));
    return;
  }
  const double compression_change = a + b;  // ≤ 0
  // Restitution: each point's normal impulse at least (1 + e) p_c, non-penetration kept, friction on the
  // disc of the whole normal impulse.
  bool any = false;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    SolverContact& c = contacts[k];
    compression[k] = Eigen::Vector3d(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
    const double extra = restitution[k] * c.normal_impulse;
    c.normal_floor = c.normal_impulse + extra;
    if (!(extra > 0.0)) continue;
    any = true;
    c.normal_impulse += extra;
    bodies[c.a].v += bodies[c.a].inverse_mass * extra * c.n, bodies[c.a].w += extra * c.response_a.col(0);
    bodies[c.b].v -= bodies[c.b].inverse_mass * extra * c.n, bodies[c.b].w -= extra * c.response_b.col(0);
  }
  if (any) {
    solveVelocities(contacts, bodies, options);
    restored.take(bodies);
    energyTerms(compressed, restored, a, b);
    const double alpha = largestShare(compression_change, a, b);
    if (alpha < 1.0) scaleBack(contacts, bodies, compressed, restored, compression, alpha);
  }
  for (SolverContact& c : contacts) c.normal_floor = 0.0;
}

double limitEnergyGain(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range) {
  // With Δv = dP / M and Δω = I⁻¹ dL, the impulses scaled by α change the kinetic energy by α a + α² b,
  // a = Σ v₀·dP + ω₀·dL (v₀ = v − Δv, the velocities before them) and b = ½ Σ Δv·dP + Δω·dL ≥ 0.
  double a = 0.0, b = 0.0, size = 0.0;
  for (std::size_t s = std::max<std::size_t>(range.body_begin, 1); s < range.body_end; ++s) {  // 0: environment
    const SolverBody& body = bodies[s];
    const Eigen::Vector3d dv = body.inverse_mass * body.dP, dw = body.inverse_inertia_W * body.dL;
    const double first = (body.v - dv).dot(body.dP) + (body.w - dw).dot(body.dL);
    const double second = 0.5 * (dv.dot(body.dP) + dw.dot(body.dL));
    a += first, b += second, size += std::abs(first) + second;
  }
  // Within rounding of the sums a converged solve's change may come out either side of zero.
  if (!(a + b > kEnergyGainTolerance * size)) return 1.0;
  const double alpha = largestShare(0.0, a, b);
  for (std::size_t s = std::max<std::size_t>(range.body_begin, 1); s < range.body_end; ++s) {
    SolverBody& body = bodies[s];
    const Eigen::Vector3d dv = body.inverse_mass * body.dP, dw = body.inverse_inertia_W * body.dL;
    body.v += (alpha - 1.0) * dv, body.w += (alpha - 1.0) * dw;
    body.dP *= alpha, body.dL *= alpha;
  }
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    contacts[k].normal_impulse *= alpha;
    contacts[k].friction_impulse *= alpha;
  }
  return alpha;
}

void projectPositions(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, int iterations,
                      double slop, double correction, const SolveRange& range) {
  for (int iteration = 0; iteration < iterations; ++iteration) {
    double deepest = 0.0;
    for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
      SolverContact& c = contacts[k];
      SolverBody& a = bodies[c.a];
      SolverBody& b = bodies[c.b];
      // The separation now, to first order in what the bodies have moved since detection.
      const double separation = c.separation + c.n.dot(a.dx - b.dx) + c.cross_a.col(0).dot(a.dtheta) -
                                c.cross_b.col(0).dot(b.dtheta);
      const double error = separation + slop;
      const bool bouncing = !c.sustained && c.target_speed > 0.0;
      if (error < 0.0 && !bouncing) {
        deepest = std::min(deepest, error);
        const double push = -correction * error * c.normal_mass;
        if (c.a != kEnvironment) a.dx += a.inverse_mass * push * c.n, a.dtheta += push * c.response_a.col(0);
        if (c.b != kEnvironment) b.dx -= b.inverse_mass * push * c.n, b.dtheta -= push * c.response_b.col(0);
      }
      if (!c.anchored) continue;
      // The anchors' tangential gap now, to first order as the separation; a push p along (t1, t2) changes
      // it by K_t p, so p = −correction K_t⁻¹ gap removes that fraction of it.
      const Eigen::Vector2d gap(
          c.anchor_gap.x() + c.t1.dot(a.dx - b.dx) + c.cross_a.col(1).dot(a.dtheta) - c.cross_b.col(1).dot(b.dtheta),
          c.anchor_gap.y() + c.t2.dot(a.dx - b.dx) + c.cross_a.col(2).dot(a.dtheta) - c.cross_b.col(2).dot(b.dtheta));
      const Eigen::Vector2d push = -correction * (c.tangent_mass * gap);
      const Eigen::Vector3d linear = push.x() * c.t1 + push.y() * c.t2;
      if (c.a != kEnvironment) {
        a.dx += a.inverse_mass * linear, a.dtheta += c.response_a.col(1) * push.x() + c.response_a.col(2) * push.y();
      }
      if (c.b == kEnvironment) continue;
      b.dx -= b.inverse_mass * linear, b.dtheta -= c.response_b.col(1) * push.x() + c.response_b.col(2) * push.y();
    }
    if (deepest == 0.0) break;
  }
}

}  // namespace contact
}  // namespace rigid_body
