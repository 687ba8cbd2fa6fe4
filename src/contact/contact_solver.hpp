// The velocity-level contact solver: sequential impulses (projected Gauss–Seidel on the contact impulses,
// Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005) with warm starting, Newton's restitution
// law on the normal and Coulomb's friction disc, then a position projection for what penetration remains
// (nonlinear Gauss–Seidel on positions, which moves bodies without touching their momenta, so it adds no
// kinetic energy). A contact with one point and no friction gives the impulse formula of Baraff & Witkin's
// notes ("Rigid Body Simulation", part II, colliding contact):
//   j = −(1+e) v⁻·n / (1/M_a + 1/M_b + n·(I_a⁻¹(r_a×n))×r_a + n·(I_b⁻¹(r_b×n))×r_b).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace rigid_body {
namespace contact {

/// Solver body 0 is the environment: zero inverse mass and inertia, at rest. Every contact refers to two
/// solver bodies, so the inner loop has no branch for "static or not".
constexpr std::size_t kEnvironment = 0;

/// A body as the solver sees it: inverse mass and world inverse inertia, working velocities, and the
/// position changes it accumulates.
struct SolverBody {
  double inverse_mass = 0.0;
  Eigen::Matrix3d inverse_inertia_W = Eigen::Matrix3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();       ///< [m/s]
  Eigen::Vector3d w = Eigen::Vector3d::Zero();       ///< [rad/s]
  Eigen::Vector3d dP = Eigen::Vector3d::Zero();      ///< Σ impulses [N s] (summed after the solve)
  Eigen::Vector3d dL = Eigen::Vector3d::Zero();      ///< Σ r × impulse about the centre of mass [N m s]
  Eigen::Vector3d dx = Eigen::Vector3d::Zero();      ///< position change [m]
  Eigen::Vector3d dtheta = Eigen::Vector3d::Zero();  ///< orientation change, a rotation vector [rad]
};

/// One contact point between solver bodies a and b (b may be kEnvironment), normal from b towards a. The
/// products the inner loop needs (r × n, I⁻¹(r × n) and the same for both tangents) are made once in
/// prepareContacts.
struct SolverContact {
  std::size_t a = kEnvironment, b = kEnvironment;
  Eigen::Vector3d r_a = Eigen::Vector3d::Zero(), r_b = Eigen::Vector3d::Zero();  ///< from each centre of mass
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ(), t1 = Eigen::Vector3d::UnitX(), t2 = Eigen::Vector3d::UnitY();
  double separation = 0.0;     ///< signed distance when detected [m]
  double friction = 0.0;       ///< μ
  double restitution = 0.0;    ///< e
  double target_speed = 0.0;   ///< the normal relative speed the solve aims at (≥ it)
  /// The pair touched at the start of the step: its impulse stands for a force over the whole step (and
  /// moves the bodies as that force would have). A new contact's impulse is an impact at the step's end.
  bool sustained = false;
  /// A sticking contact's anchors: the two points where it began to stick, one on each body, apart by
  /// anchor_gap in the tangent plane (t1, t2) when detected; the position projection closes that gap.
  bool anchored = false;
  Eigen::Vector2d anchor_gap = Eigen::Vector2d::Zero();  ///< [m]
  double slip_squared = 0.0;  ///< |tangential relative velocity|² before the last sweep's friction update [m²/s²]
  double normal_floor = 0.0;   ///< the least normal impulse the solve may end with (an impact's restitution) [N s]
  double normal_impulse = 0.0;                                 ///< accumulated [N s], ≥ normal_floor
  Eigen::Vector2d friction_impulse = Eigen::Vector2d::Zero();  ///< accumulated [N s], |·| ≤ μ normal_impulse
  // Made by prepareContacts: r × d and I⁻¹(r × d) for d = n, t1, t2 (columns), and the effective masses.
  Eigen::Matrix3d cross_a, cross_b, response_a, response_b;
  double normal_mass = 0.0;                                ///< 1 / (n·K n)
  Eigen::Matrix2d tangent_mass = Eigen::Matrix2d::Zero();  ///< (T K Tᵀ)⁻¹ for the two tangents
  Eigen::Matrix2d tangent_response = Eigen::Matrix2d::Zero();  ///< T K Tᵀ: slip change per friction impulse
};

/// How a solve treats the approach velocity.
struct SolveOptions {
  int iterations = 20;
  /// A solve not converged after `iterations` sweeps goes on (to a change of 1e-9 of the impulses) while its
  /// sweeps have updated fewer contacts than `iterations` sweeps over this many would: a small scene
  /// converges (a heavy box on a light one needs hundreds of sweeps, the impulse crossing a mass ratio of
  /// 1 000 a little at each), a large one costs what `iterations` sweeps cost.
  std::size_t sweep_budget_contacts = 100;
  /// The contacts the sweep budget is shared over (0: this solve's own). An island of a larger solve sweeps
  /// as often as the whole solve would (SolverIslands): its cost and bits then do not depend on how the
  /// scene falls into islands or threads.
  std::size_t budget_contacts = 0;
  double restitution_threshold = 0.05;  ///< [m/s]
  bool bounce = true;                   ///< apply restitution to approaches faster than the threshold
  double dt = 0.0;                      ///< > 0: a separated contact (separation > 0) may close at separation/dt
};

/// How many sweeps a solve of `contacts` contacts may take (the iterations, and beyond them the small
/// scene's budget: SolveOptions::sweep_budget_contacts and budget_contacts); 0 for no contacts.
std::size_t allowedSweeps(const SolveOptions& options, std::size_t contacts);

/// A solver body for the environment, to put first in the bodies' list.
SolverBody environmentBody();

/// The part of a solve's lists one call works on: contacts [contact_begin, contact_end) acting on bodies
/// [body_begin, body_end) and the environment, and on no other body (an island; or everything, with
/// body_begin = 0). Nothing is written to the environment's entry, so calls on disjoint ranges of the same
/// lists may run on different threads.
struct SolveRange {
  std::size_t contact_begin = 0, contact_end = 0;
  std::size_t body_begin = 0, body_end = 0;
  /// The whole of both lists.
  static SolveRange all(std::size_t contacts, std::size_t bodies) { return {0, contacts, 0, bodies}; }
};

/// A contact's direction d: 0 its normal, 1 and 2 its tangents t1 and t2 (the columns of cross_a and the rest).
inline const Eigen::Vector3d& contactDirection(const SolverContact& c, Eigen::Index d) {
  return d == 0 ? c.n : d == 1 ? c.t1 : c.t2;
}

/// The contact's relative speed along its direction d, J_d V = d·(v_a − v_b) + (r_a × d)·ω_a − (r_b × d)·ω_b
/// (needs the products prepareContacts makes).
inline double rowSpeed(const SolverContact& c, Eigen::Index d, const SolverBody& a, const SolverBody& b) {
  return contactDirection(c, d).dot(a.v - b.v) + c.cross_a.col(d).dot(a.w) - c.cross_b.col(d).dot(b.w);
}

/// The contact's normal relative speed, J_n V.
inline double normalSpeed(const SolverContact& c, const SolverBody& a, const SolverBody& b) {
  return rowSpeed(c, 0, a, b);
}

/// The relative velocity of the contact point of a with respect to b's.
Eigen::Vector3d relativeVelocity(const SolverContact& contact, const std::vector<SolverBody>& bodies);

/// Jacobian products, effective masses and target speeds from the bodies' current velocities; applies the
/// warm-start impulses the contacts carry: prepareContactRows on the range's contacts, then applyWarmStarts.
void prepareContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options,
                     const SolveRange& range);
/// The first part alone, for contacts [begin, end): each contact's own rows from the bodies as they are
/// (before any warm start), writing that contact only; disjoint runs may be prepared on different threads.
void prepareContactRows(std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                        const SolveOptions& options, std::size_t begin, std::size_t end);
/// The second: the impulses the range's contacts carry from the last step, applied to their bodies in order.
void applyWarmStarts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range);
void prepareContacts(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options);

/// Sequential impulses until every contact meets its target within rounding or the iterations run out;
/// then each body's dP and dL are summed from the contacts' impulses. Returns whether it converged (a
/// sweep changed no impulse by more than rounding) before the iterations ran out.
bool solveVelocities(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options,
                     const SolveRange& range);
bool solveVelocities(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options);

/// Each body's dP and dL in `range` from its contacts' impulses (what solveVelocities ends with).
void sumImpulses(const std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range);

/// Scales back the impulses of the contacts in `range` (and the bodies' velocities, dP and dL, as sumImpulses
/// left them) to the largest share, at most all, that does not raise the bodies' kinetic energy above what
/// they had before the impulses: a solve that has converged never raises it (its impulses stop approaches and
/// oppose slips), but one whose sweeps could not take back a first guess that was too large (a heavy body on
/// a light one, each sweep moving the impulse by the light body's share) can. Returns the share kept.
double limitEnergyGain(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range);

/// An impact at one instant: Poisson's restitution with Coulomb friction, bounded in energy (docs/references.md,
/// "An impact that never creates energy"). A compression solve (every point stopped, e = 0) gives each point its
/// compression impulse p_c; a restitution solve then holds each point's normal impulse at (1 + e) p_c or more
/// (e only where the approach beat the restitution threshold) with friction on the larger disc. Where the two
/// together would raise the bodies' kinetic energy, the restitution phase is scaled back to the largest share
/// that does not (a root of a quadratic: the energy is quadratic in a scaled impulse). Frictionless single
/// points keep Newton's v⁺ₙ = −e v⁻ₙ exactly. A point whose target is below zero is still apart (a speculative
/// point: it may close at that speed, no faster) and keeps its target in both phases, without restitution.
/// Each body's dP and dL are the impact's total.
void solveImpact(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveOptions& options);

/// Position projection: moves bodies apart along the normals until no penetration beyond `slop` remains
/// (a fraction `correction` of it per sweep), and brings an anchored contact's anchors together in the
/// tangent plane by the same fraction (the slip that unconverged friction impulses leave would otherwise
/// add up over the steps). A new contact that bounces is left as it is (lifting it out would add the
/// potential energy of its depth to a rebound that already has its kinetic energy). The separations count the bodies' dx and dtheta as they stand (what the step
/// has already moved them since detection) to first order.
void projectPositions(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, int iterations,
                      double slop, double correction, const SolveRange& range);

}  // namespace contact
}  // namespace rigid_body
