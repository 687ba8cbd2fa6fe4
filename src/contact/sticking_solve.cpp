#include "sticking_solve.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace rigid_body {
namespace contact {

namespace {

constexpr std::size_t kNoRow = std::numeric_limits<std::size_t>::max();
// K is factored as K + ε k̄ 1 (k̄ the mean of K's diagonal): positive definite, and its solution tends to the
// least-norm one as ε → 0. The refinements x ← x + (K + ε k̄ 1)⁻¹ (r − K x) take the error on the range of K down
// by ε k̄/(μ + ε k̄) each (μ its eigenvalues there), to rounding; along the null space they add nothing but
// rounding over ε k̄.
constexpr double kRegularisation = 1e-9;
constexpr int kRefinements = 3;
// A face the solve holds exactly stays at the depth it had, which may be zero; its points' separations then
// straddle zero by rounding, those apart ask to close by their gap (a target of order 1e-13 m/s that changes
// sign from step to step), and the sweeps never met their tolerance again: a settled stack of ten paid the
// island solve in every step and cost five times as much. So a point shallower than half this depth is sunk
// to it within the step, and rests pressed at a target of zero; a point apart by more than it counts as apart
// (leftOut). Far below anything a trajectory shows, far above the rounding of a position.
constexpr double kRestingDepth = 1e-9;
// Islands of more points are left to the sweeps: the factorisation's cost grows faster than the island
// (the pyramid of 20 rows, 1 600 points, would pay it in every step).
constexpr std::size_t kMostPoints = 256;
// An island whose rows already hold to this fraction of its impulses is left to the sweeps (nearlyHeld).
constexpr double kNearlyHeld = 1e-13;
// Islands of up to this many rows are solved in a dense matrix.
constexpr std::size_t kMostDenseRows = 48;
// Solves of an island, each after letting go of the points that pulled in the one before (letGoOfPulling).
constexpr int kMostRounds = 3;
// A friction impulse at least this fraction of the disc's radius μ fₙ is at its edge (sliding).
constexpr double kDiscEdge = 1.0 - 1e-3;
// A slip below this fraction of the largest normal speed a point's own impulse makes in the island
// (fₙ / m_n) may be what unconverged sweeps leave (sliding).
constexpr double kUnconvergedSlip = 0.1;

// A point still apart (by more than kRestingDepth) that the sweeps left unpressed: a speculative point, or a
// corner of a face that has not come down. It is no row: held to its closing speed as an equality it would
// contradict the pressed point beside it (a box's top corners, speculative on the ground 0.2 m below its
// bottom ones at h = 20 ms, asked to close at 10 m/s where the bottom ones stop: the least-norm impulses
// were 3e9 N s); the solve is kept only if such a point then closes no faster than its target allows.
bool leftOut(const SolverContact& c) { return c.separation > kRestingDepth && c.normal_impulse == 0.0; }

// The rows: each point's normal, and its tangents where it has friction (without, they keep their zero);
// none for a point left out or let go (s.let_go).
std::size_t numberRows(const std::vector<SolverContact>& contacts, const SolveRange& range, StickingScratch& s) {
  const std::size_t points = range.contact_end - range.contact_begin;
  s.row_of.assign(3 * points, kNoRow);
  s.contact.clear();
  for (std::size_t k = 0; k < points; ++k) {
    if (s.let_go[k] || leftOut(contacts[range.contact_begin + k])) continue;
    for (std::size_t d = 0; d < 3; ++d) {
      if (d > 0 && !(contacts[range.contact_begin + k].friction > 0.0)) continue;
      s.row_of[3 * k + d] = s.contact.size();
      s.contact.push_back(3 * k + d);
    }
  }
  return s.contact.size();
}

// K's lower triangle, body by body: rows i (point p, direction u) and j (point q, direction v) that move one
// body B couple by σ_p σ_q (d_u·d_v / M_B + (r_p × d_u)·I_B⁻¹(r_q × d_v)), σ = +1 on a contact's side a, −1 on b.
void assembleCoupling(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                      const SolveRange& range, StickingScratch& s, Eigen::VectorXd& diagonal) {
  const std::size_t points = range.contact_end - range.contact_begin;
  s.rows_on.resize(range.body_end - range.body_begin);
  for (auto& list : s.rows_on) list.clear();
  for (std::size_t k = 0; k < points; ++k) {
    const SolverContact& c = contacts[range.contact_begin + k];
    if (c.a != kEnvironment) s.rows_on[c.a - range.body_begin].push_back(2 * k);
    if (c.b != kEnvironment) s.rows_on[c.b - range.body_begin].push_back(2 * k + 1);
  }
  s.entries.clear();
  for (std::size_t body = 0; body < s.rows_on.size(); ++body) {
    const double inverse_mass = bodies[range.body_begin + body].inverse_mass;
    for (const std::size_t first : s.rows_on[body]) {
      const SolverContact& p = contacts[range.contact_begin + first / 2];
      const bool p_on_a = first % 2 == 0;
      for (const std::size_t second : s.rows_on[body]) {
        const SolverContact& q = contacts[range.contact_begin + second / 2];
        const bool q_on_a = second % 2 == 0;
        const double sign = p_on_a == q_on_a ? 1.0 : -1.0;
        const Eigen::Matrix3d& cross = p_on_a ? p.cross_a : p.cross_b;
        const Eigen::Matrix3d& response = q_on_a ? q.response_a : q.response_b;
        for (std::size_t u = 0; u < 3; ++u) {
          const std::size_t i = s.row_of[3 * (first / 2) + u];
          if (i == kNoRow) continue;
          for (std::size_t v = 0; v < 3; ++v) {
            const std::size_t j = s.row_of[3 * (second / 2) + v];
            if (j == kNoRow || j > i) continue;
            const auto cu = static_cast<Eigen::Index>(u), cv = static_cast<Eigen::Index>(v);
            const double value =
                sign * (inverse_mass * contactDirection(p, cu).dot(contactDirection(q, cv)) +
                        cross.col(cu).dot(response.col(cv)));
            s.entries.emplace_back(static_cast<int>(i), static_cast<int>(j), value);
            if (i == j) diagonal[static_cast<Eigen::Index>(i)] += value;
          }
        }
      }
    }
  }
}

// What each row aims at: the normal's target speed (a bounce, or a speculative point's closing), with a
// shallow point (less than half kRestingDepth deep) also sunk to kRestingDepth within the step; no slip.
void rowResiduals(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                  const SolveRange& range, double dt, const StickingScratch& s, Eigen::VectorXd& residual,
                  Eigen::VectorXd& now) {
  for (std::size_t i = 0; i < s.contact.size(); ++i) {
    const std::size_t k = s.contact[i] / 3, d = s.contact[i] % 3;
    const SolverContact& c = contacts[range.contact_begin + k];
    double target = d == 0 ? c.target_speed : 0.0;
    if (d == 0 && target <= 0.0 && dt > 0.0 && c.separation > -0.5 * kRestingDepth) {
      target = std::min(target, -(c.separation + kRestingDepth) / dt);
    }
    const auto row = static_cast<Eigen::Index>(i);
    residual[row] = target - rowSpeed(c, static_cast<Eigen::Index>(d), bodies[c.a], bodies[c.b]);
    now[row] = d == 0 ? c.normal_impulse : c.friction_impulse[static_cast<Eigen::Index>(d - 1)];
  }
}

// Whether the impulses `next` (rows as numbered) keep every point pushing (at or above its floor) and within
// its friction disc.
bool admissible(const std::vector<SolverContact>& contacts, const SolveRange& range, const StickingScratch& s,
                const Eigen::VectorXd& next) {
  const auto value = [&](std::size_t k, std::size_t d, double kept) {
    const std::size_t row = s.row_of[3 * k + d];
    return row == kNoRow ? kept : next[static_cast<Eigen::Index>(row)];
  };
  for (std::size_t k = 0; k < range.contact_end - range.contact_begin; ++k) {
    const SolverContact& c = contacts[range.contact_begin + k];
    const double normal = value(k, 0, c.normal_impulse);
    const Eigen::Vector2d friction(value(k, 1, c.friction_impulse.x()), value(k, 2, c.friction_impulse.y()));
    const double limit = c.friction * normal;
    if (!(normal >= c.normal_floor) || !(friction.squaredNorm() <= limit * limit)) return false;
  }
  return true;
}

// A point's impulses (normal, two tangents) become `after`, and its bodies' velocities change by what that adds.
void changeImpulses(SolverContact& c, std::vector<SolverBody>& bodies, const Eigen::Vector3d& after) {
  const Eigen::Vector3d change = after - Eigen::Vector3d(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
  c.normal_impulse = after.x();
  c.friction_impulse = after.tail<2>();
  const Eigen::Vector3d linear = change.x() * c.n + change.y() * c.t1 + change.z() * c.t2;
  if (c.a != kEnvironment) bodies[c.a].v += bodies[c.a].inverse_mass * linear, bodies[c.a].w += c.response_a * change;
  if (c.b != kEnvironment) bodies[c.b].v -= bodies[c.b].inverse_mass * linear, bodies[c.b].w -= c.response_b * change;
}

// The impulses of the points with rows become `next`.
void applyImpulses(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range,
                   const StickingScratch& s, const Eigen::VectorXd& next) {
  for (std::size_t k = 0; k < range.contact_end - range.contact_begin; ++k) {
    SolverContact& c = contacts[range.contact_begin + k];
    Eigen::Vector3d after(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
    for (std::size_t d = 0; d < 3; ++d) {
      const std::size_t row = s.row_of[3 * k + d];
      if (row != kNoRow) after[static_cast<Eigen::Index>(d)] = next[static_cast<Eigen::Index>(row)];
    }
    changeImpulses(c, bodies, after);
  }
}

// Whether every point without rows (left out, or let go) closes, after the solve, no faster than its target
// (to within the resting depth in the step).
bool pointsWithoutRowsHold(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                           const SolveRange& range, double dt, const StickingScratch& s) {
  const double allowance = dt > 0.0 ? kRestingDepth / dt : 0.0;
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    if (!s.let_go[k - range.contact_begin] && !leftOut(c)) continue;
    if (!(rowSpeed(c, 0, bodies[c.a], bodies[c.b]) >= c.target_speed - allowance)) return false;
  }
  return true;
}

// Points whose solved normal impulse fell below zero (they would pull) are let go: their impulses become
// zero and the rest is solved again without them, as a point lifting off would be (the active-set step
// for a linear complementarity problem; Murty, "Linear Complementarity, Linear and Nonlinear Programming",
// ch. 8). A heavy box set off diagonally on a light one at coarse steps had one corner of its face whose
// every sticking spread pulled. True if some were let go.
bool letGoOfPulling(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies, const SolveRange& range,
                    const Eigen::VectorXd& next, StickingScratch& s) {
  bool any = false;
  for (std::size_t k = 0; k < range.contact_end - range.contact_begin; ++k) {
    const std::size_t row = s.row_of[3 * k];
    SolverContact& c = contacts[range.contact_begin + k];
    if (row == kNoRow || c.normal_floor > 0.0 || next[static_cast<Eigen::Index>(row)] >= 0.0) continue;
    changeImpulses(c, bodies, Eigen::Vector3d::Zero());
    s.let_go[k] = 1;
    any = true;
  }
  return any;
}

// Whether some point of a pair that already touched slipped, in the sweeps' last friction update, faster
// than `sliding_speed` with its friction at the disc's edge: it slides, and the island would not stick (a
// pile while it falls: trying it there cost a third again of the pile's step, and was refused). A new
// contact's slip says nothing yet: its sweeps started cold, and a twisted tower placed at rest had its first
// step at h = 10 ms left unconverged by them and refused the solve for that slip; it rocked by 60 mm ever
// after. Nor does a slip with friction to spare, or one below a tenth of the largest normal speed a point's
// impulse makes in the island: unconverged sweeps leave such slips, of the order of g h (a tower of fifteen
// cubes set off by 5 mm, at h = 20 ms, slipped just beyond `sliding_speed` at one corner with friction to
// spare; a tower of standing cylinders had a rim point at its disc's edge slipping at 2–7 mm/s; both were
// refused, and fell).
bool sliding(const std::vector<SolverContact>& contacts, const SolveRange& range, double sliding_speed) {
  double pushed = 0.0;  // the largest normal speed a point's own impulse makes, fₙ / m_n
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    pushed = std::max(pushed, contacts[k].normal_impulse / contacts[k].normal_mass);
  }
  const double bound = std::max(sliding_speed, kUnconvergedSlip * pushed);
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    const double edge = kDiscEdge * c.friction * c.normal_impulse;
    if (c.sustained && c.friction_impulse.squaredNorm() >= edge * edge &&
        c.slip_squared > bound * bound) {
      return true;
    }
  }
  return false;
}

// K x = b in the least-squares sense, least-norm: x = K⁺ b. (K + shift 1) is factored once, and refined
// (above). b need not lie in K's range: targets no rigid motion meets (a face's points asking to close by
// different gaps, or rounding) have a part outside it, which (K + ε k̄ 1)⁻¹ multiplies by 1/(ε k̄) (a 1 kg box
// in a tower got −1 060 N s). So the first solution y is mapped back into the range, K y (the nearest b K can
// reach), and that is solved.
template <class Factor, class Coupling>
Eigen::VectorXd leastSquares(const Factor& factor, const Coupling& K, const Eigen::VectorXd& wanted) {
  const auto refined = [&](const Eigen::VectorXd& b) {
    Eigen::VectorXd x = factor.solve(b);
    for (int refinement = 0; refinement < kRefinements; ++refinement) x += factor.solve(b - K * x);
    return x;
  };
  return refined(K * refined(wanted));
}

// Impulses that give the island the velocities its rows ask for, K λ = K λ₀ + (target − v) =: b, and that
// `accept` takes. Every λ of λ* + null(K) gives the same velocities; the statics of a face on four points (or a
// box on two) is indeterminate, and only some of them push and hold within every friction disc. First the
// least-norm λ* = K⁺ b: it drops whatever the sweeps left in K's null space (a face's corners pushing against
// each other) and spreads a face's load as evenly as its balance allows. Then the least change from the
// sweeps' own impulses, λ₀ + K⁺ (target − v): they are within their discs, and where a box rests across two
// others λ* asked one corner for five times its friction (a pyramid of five rows at h = 10 ms crept 0.07 mm).
template <class Factor, class Coupling, class Accept>
bool solveImpulses(const Factor& factor, const Coupling& K, const Eigen::VectorXd& now, const Eigen::VectorXd& residual,
                   const Accept& accept, Eigen::VectorXd& next) {
  next = leastSquares(factor, K, K * now + residual);
  if (next.allFinite() && accept(next)) return true;
  next = now + leastSquares(factor, K, residual);
  return next.allFinite() && accept(next);
}

// A small island in a dense matrix (a body resting alone on two or three points needs no sparse machinery),
// a larger one in a sparse one; K's lower triangle given as triplets, summed where they repeat.
template <class Accept>
bool solveDense(const std::vector<Eigen::Triplet<double>>& entries, double shift, const Eigen::VectorXd& now,
                const Eigen::VectorXd& residual, const Accept& accept, Eigen::VectorXd& next) {
  const Eigen::Index size = now.size();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(size, size);
  for (const Eigen::Triplet<double>& e : entries) K(e.row(), e.col()) += e.value();
  K.triangularView<Eigen::StrictlyUpper>() = K.transpose();
  const Eigen::LDLT<Eigen::MatrixXd> factor(K + shift * Eigen::MatrixXd::Identity(size, size));
  return factor.info() == Eigen::Success && solveImpulses(factor, K, now, residual, accept, next);
}
template <class Accept>
bool solveSparse(std::vector<Eigen::Triplet<double>>& entries, double shift, const Eigen::VectorXd& now,
                 const Eigen::VectorXd& residual, const Accept& accept, Eigen::VectorXd& next) {
  const Eigen::Index size = now.size();
  Eigen::SparseMatrix<double> K(size, size), regular(size, size);
  K.setFromTriplets(entries.begin(), entries.end());
  for (Eigen::Index i = 0; i < size; ++i) entries.emplace_back(i, i, shift);
  regular.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor(regular);
  return factor.info() == Eigen::Success &&
         solveImpulses(factor, K.selfadjointView<Eigen::Lower>(), now, residual, accept, next);
}

// Whether every row already holds to what rounding leaves the sweeps: each point's normal and slip
// residuals would move its impulses by at most kNearlyHeld of the island's largest impulse. The sweeps'
// tolerance is 1e-14 of it, and their own rounding reaches 2e-14: an island that missed it by that much is
// not worth a factorisation (settled stacks did, in 2 % of their steps).
bool nearlyHeld(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                const SolveRange& range) {
  double largest_change = 0.0, largest_impulse = 0.0;
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    const SolverBody& a = bodies[c.a];
    const SolverBody& b = bodies[c.b];
    const double normal = std::abs(rowSpeed(c, 0, a, b) - c.target_speed);
    const double slip = c.friction > 0.0 ? std::hypot(rowSpeed(c, 1, a, b), rowSpeed(c, 2, a, b)) : 0.0;
    largest_change = std::max(largest_change, c.normal_mass * std::max(normal, slip));
    largest_impulse = std::max({largest_impulse, c.normal_impulse, c.friction_impulse.lpNorm<Eigen::Infinity>()});
  }
  return largest_change <= kNearlyHeld * largest_impulse;
}

// The impulses and velocities of the range as they were, for a solve that is not kept.
void saveIsland(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
                const SolveRange& range, StickingScratch& s) {
  s.velocities.clear();
  for (std::size_t body = range.body_begin; body < range.body_end; ++body) {
    s.velocities.emplace_back(bodies[body].v, bodies[body].w);
  }
  s.impulses.clear();
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    const SolverContact& c = contacts[k];
    s.impulses.emplace_back(c.normal_impulse, c.friction_impulse.x(), c.friction_impulse.y());
  }
}
StickingOutcome restoreIsland(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                              const SolveRange& range, const StickingScratch& s) {
  for (std::size_t body = range.body_begin; body < range.body_end; ++body) {
    std::tie(bodies[body].v, bodies[body].w) = s.velocities[body - range.body_begin];
  }
  for (std::size_t k = range.contact_begin; k < range.contact_end; ++k) {
    contacts[k].normal_impulse = s.impulses[k - range.contact_begin].x();
    contacts[k].friction_impulse = s.impulses[k - range.contact_begin].tail<2>();
  }
  return StickingOutcome::kRefused;
}

// One solve of the rows as numbered: true with admissible impulses in `next`, false with the last tried.
bool solveRows(const std::vector<SolverContact>& contacts, const std::vector<SolverBody>& bodies,
               const SolveRange& range, double dt, std::size_t rows, StickingScratch& scratch, Eigen::VectorXd& next) {
  const auto size = static_cast<Eigen::Index>(rows);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(size), residual(size), now(size);
  assembleCoupling(contacts, bodies, range, scratch, diagonal);
  rowResiduals(contacts, bodies, range, dt, scratch, residual, now);
  const double shift = kRegularisation * diagonal.mean();  // the same on every row: the least norm is Euclidean
  const auto accept = [&](const Eigen::VectorXd& impulses) { return admissible(contacts, range, scratch, impulses); };
  return rows <= kMostDenseRows ? solveDense(scratch.entries, shift, now, residual, accept, next)
                                : solveSparse(scratch.entries, shift, now, residual, accept, next);
}

}  // namespace

StickingOutcome solveStickingIsland(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                                    const SolveRange& range, double dt, double sliding_speed, StickingScratch& scratch) {
  const std::size_t points = range.contact_end - range.contact_begin;
  if (points > kMostPoints || sliding(contacts, range, sliding_speed) || nearlyHeld(contacts, bodies, range)) {
    return StickingOutcome::kNotTried;
  }
  saveIsland(contacts, bodies, range, scratch);
  scratch.let_go.assign(points, 0);
  Eigen::VectorXd next;
  for (int round = 0;; ++round) {
    const std::size_t rows = numberRows(contacts, range, scratch);
    if (rows == 0 && round == 0) return StickingOutcome::kNotTried;  // every point left out: nothing to solve
    if (rows == 0) return restoreIsland(contacts, bodies, range, scratch);
    next.resize(0);  // a factorisation that fails leaves it so
    if (solveRows(contacts, bodies, range, dt, rows, scratch, next)) break;
    const bool tried = next.size() == static_cast<Eigen::Index>(rows) && next.allFinite();
    if (round + 1 == kMostRounds || !tried || !letGoOfPulling(contacts, bodies, range, next, scratch)) {
      return restoreIsland(contacts, bodies, range, scratch);
    }
  }
  applyImpulses(contacts, bodies, range, scratch, next);
  if (pointsWithoutRowsHold(contacts, bodies, range, dt, scratch)) return StickingOutcome::kSolved;
  return restoreIsland(contacts, bodies, range, scratch);
}

}  // namespace contact
}  // namespace rigid_body
