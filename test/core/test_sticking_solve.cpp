// An island solved at once as if it stuck (src/contact/sticking_solve.hpp). The result is checked against
// K built here afresh from each point's full Jacobian rows over all the island's bodies (not from the
// solver's products) and its pseudo-inverse: a missing coupling between two faces of one body, a wrong sign
// on a contact's side b, a solve for the change (which keeps the corners' internal pushing) instead of the
// impulses, or a regularisation left unrefined fails it. An island that would have to pull or slide is
// refused and left as it was; a face at zero depth is sunk to the resting depth; a point apart and unpressed
// is no row.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "random_solver_bodies.hpp"
#include "../../src/contact/sticking_solve.hpp"

using namespace rigid_body;
using namespace rigid_body::contact;

namespace {

using test::randomBody;
using test::randomUnit;

// A chain: the environment (0) under body 1 under body 2 under body 3, each pair touching on a face of
// `counts[f]` points about a point between their centres, with a random normal per face.
struct Island {
  std::vector<SolverBody> bodies;
  std::vector<SolverContact> contacts;
};
Island chain(std::mt19937& random, const std::vector<std::size_t>& counts, double friction) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Island island;
  island.bodies.push_back(SolverBody());  // the environment: no inverse mass or inertia
  std::vector<Eigen::Vector3d> centres{Eigen::Vector3d::Zero()};
  for (std::size_t f = 0; f < counts.size(); ++f) {
    island.bodies.push_back(randomBody(random));
    centres.push_back(centres.back() + Eigen::Vector3d(0.0, 0.0, 0.5) + 0.1 * randomUnit(random));
  }
  for (std::size_t f = 0; f < counts.size(); ++f) {
    const std::size_t a = f + 1, b = f;
    const Eigen::Vector3d n = (Eigen::Vector3d::UnitZ() + 0.3 * randomUnit(random)).normalized();
    const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const Eigen::Vector3d middle = 0.5 * (centres[a] + centres[b]);
    const double hx = 0.05 + 0.2 * unit(random), hy = 0.05 + 0.2 * unit(random);
    const Eigen::Vector2d corners[4] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    for (std::size_t i = 0; i < counts[f]; ++i) {
      const Eigen::Vector3d p = middle + corners[i].x() * t1 + corners[i].y() * t2;
      SolverContact c;
      c.a = a, c.b = b == 0 ? kEnvironment : b;
      c.r_a = p - centres[a];
      if (b != 0) c.r_b = p - centres[b];
      c.n = n, c.t1 = t1, c.t2 = t2;
      c.friction = friction;
      c.separation = -1e-5;  // deeper than the resting depth: the target stays zero
      c.sustained = true;
      island.contacts.push_back(c);
    }
  }
  prepareContactRows(island.contacts, island.bodies, SolveOptions(), 0, island.contacts.size());
  return island;
}

// Each point's three rows (n, t1, t2) over all bodies' velocities (6 per body, the environment's too).
Eigen::MatrixXd jacobian(const Island& island) {
  const auto columns = static_cast<Eigen::Index>(6 * island.bodies.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * island.contacts.size()), columns);
  for (std::size_t k = 0; k < island.contacts.size(); ++k) {
    const SolverContact& c = island.contacts[k];
    const Eigen::Vector3d d[3] = {c.n, c.t1, c.t2};
    for (int j = 0; j < 3; ++j) {
      const auto row = static_cast<Eigen::Index>(3 * k) + j;
      J.block<1, 3>(row, static_cast<Eigen::Index>(6 * c.a)) = d[j].transpose();
      J.block<1, 3>(row, static_cast<Eigen::Index>(6 * c.a + 3)) = c.r_a.cross(d[j]).transpose();
      if (c.b == kEnvironment) continue;
      J.block<1, 3>(row, static_cast<Eigen::Index>(6 * c.b)) = -d[j].transpose();
      J.block<1, 3>(row, static_cast<Eigen::Index>(6 * c.b + 3)) = -c.r_b.cross(d[j]).transpose();
    }
  }
  return J;
}

Eigen::MatrixXd inverseMass(const Island& island) {
  const auto size = static_cast<Eigen::Index>(6 * island.bodies.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size);
  for (std::size_t s = 0; s < island.bodies.size(); ++s) {
    const auto at = static_cast<Eigen::Index>(6 * s);
    M.block<3, 3>(at, at) = island.bodies[s].inverse_mass * Eigen::Matrix3d::Identity();
    M.block<3, 3>(at + 3, at + 3) = island.bodies[s].inverse_inertia_W;
  }
  return M;
}

Eigen::VectorXd velocities(const Island& island) {
  Eigen::VectorXd V(static_cast<Eigen::Index>(6 * island.bodies.size()));
  for (std::size_t s = 0; s < island.bodies.size(); ++s) {
    V.segment<3>(static_cast<Eigen::Index>(6 * s)) = island.bodies[s].v;
    V.segment<3>(static_cast<Eigen::Index>(6 * s + 3)) = island.bodies[s].w;
  }
  return V;
}

Eigen::VectorXd impulses(const Island& island) {
  Eigen::VectorXd lambda(static_cast<Eigen::Index>(3 * island.contacts.size()));
  for (std::size_t k = 0; k < island.contacts.size(); ++k) {
    const SolverContact& c = island.contacts[k];
    lambda.segment<3>(static_cast<Eigen::Index>(3 * k)) << c.normal_impulse, c.friction_impulse;
  }
  return lambda;
}

// Slip above which a point counts as sliding (the scene passes a tenth of the slop per step).
constexpr double kSliding = 0.01;

}  // namespace

TEST(StickingSolve, StopsEveryRowWithTheLeastNormImpulses) {
  std::mt19937 random(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    Island island = chain(random, {4, 4, 3, 4}, 1e6);  // a disc no sticking impulse leaves
    const Eigen::MatrixXd J = jacobian(island), K = J * inverseMass(island) * J.transpose();
    // Warm impulses that press hard, with a random part K does not see (a face's corners pushing against
    // each other), and velocities that a rigid island would not have.
    Eigen::VectorXd seen = Eigen::VectorXd::Zero(J.rows());
    for (Eigen::Index r = 0; r < seen.size(); r += 3) seen[r] = 10.0;
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> pseudo(K);
    Eigen::VectorXd unseen = Eigen::VectorXd::NullaryExpr(J.rows(), [&] { return unit(random); });
    unseen -= pseudo.pseudoInverse() * (K * unseen);
    const Eigen::VectorXd warm = seen + unseen;
    for (std::size_t k = 0; k < island.contacts.size(); ++k) {
      island.contacts[k].normal_impulse = warm[static_cast<Eigen::Index>(3 * k)];
      island.contacts[k].friction_impulse = warm.segment<2>(static_cast<Eigen::Index>(3 * k + 1));
    }
    for (std::size_t s = 1; s < island.bodies.size(); ++s) {
      island.bodies[s].v = 0.1 * randomUnit(random), island.bodies[s].w = 0.1 * randomUnit(random);
    }
    const Eigen::VectorXd before = velocities(island);
    StickingScratch scratch;
    const SolveRange all = SolveRange::all(island.contacts.size(), island.bodies.size());
    ASSERT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, all, 1e-3, kSliding, scratch)) << trial;
    // Every row's velocity is zero, the velocities are the ones the impulses' change makes, and the
    // impulses are K⁺ (K λ₀ − J V₀): the least-norm ones that stop the island.
    const Eigen::VectorXd after = velocities(island), lambda = impulses(island);
    EXPECT_LE((J * after).norm(), 1e-10 * (1.0 + (J * before).norm())) << trial;
    EXPECT_LE((after - before - inverseMass(island) * J.transpose() * (lambda - warm)).norm(), 1e-10 * before.norm())
        << trial;
    // To what the shift leaves: rounding over it (1e-16 / 1e-9) along K's null space in each of the four
    // solves, times the spread of K's eigenvalues over the island's mass ratios (up to 100). A solve for the
    // change keeps the corners' random pushing (about 0.1 of the impulses here); a shift weighted by K's
    // diagonal gives a weighted least norm (0.02 to 0.2 off).
    const Eigen::VectorXd expected = pseudo.solve(K * warm - J * before);
    EXPECT_LE((lambda - expected).norm(), 1e-5 * expected.norm()) << trial;
  }
}

// The statics of a face is indeterminate: every λ of λ* + null(K) stops the island alike. A face whose load
// sits towards one corner has a least-norm λ* (a planar spread) that pulls at the opposite corner, though
// the sweeps' own impulses push everywhere; the solve then keeps the least change from those,
// λ₀ + K⁺ (−J V₀). A solve that only tried λ* refuses such an island (a box resting across two others in a
// pyramid at coarse steps was refused every step, and crept).
TEST(StickingSolve, AFaceLoadedOffItsCentreKeepsTheSweepsSpreadWhereTheLeastNormWouldPull) {
  std::mt19937 random(31);
  for (int trial = 0; trial < 20; ++trial) {
    Island island = chain(random, {4}, 0.5);
    const Eigen::MatrixXd J = jacobian(island), M = inverseMass(island), K = J * M * J.transpose();
    Eigen::VectorXd warm = Eigen::VectorXd::Zero(J.rows());
    const double spread[4] = {0.2, 1.0, 3.0, 1.0};  // corners in order round the face: the load towards the third
    for (Eigen::Index k = 0; k < 4; ++k) warm[3 * k] = 10.0 * spread[k];
    for (std::size_t k = 0; k < 4; ++k) island.contacts[k].normal_impulse = warm[static_cast<Eigen::Index>(3 * k)];
    island.bodies[1].v = 1e-3 * randomUnit(random), island.bodies[1].w = 1e-3 * randomUnit(random);
    const Eigen::VectorXd before = velocities(island);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> pseudo(K);
    const Eigen::VectorXd least_norm = pseudo.solve(K * warm - J * before);
    ASSERT_LT(std::min({least_norm[0], least_norm[3], least_norm[6], least_norm[9]}), 0.0) << trial;
    StickingScratch scratch;
    ASSERT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(4, 2), 1e-3, kSliding, scratch))
        << trial;
    const Eigen::VectorXd after = velocities(island), lambda = impulses(island);
    EXPECT_LE((J * after).norm(), 1e-10 * (1.0 + (J * before).norm())) << trial;
    const Eigen::VectorXd least_change = warm + pseudo.solve(-J * before);
    EXPECT_LE((lambda - least_change).norm(), 1e-6 * least_change.norm()) << trial;
    for (const SolverContact& c : island.contacts) {
      EXPECT_GE(c.normal_impulse, 0.0) << trial;
      EXPECT_LE(c.friction_impulse.norm(), c.friction * c.normal_impulse) << trial;
    }
  }
}

// Targets no rigid motion meets (one corner of a face asked to close, the other three to stay) have a part
// outside K's range, which a regularised solve multiplies by the inverse of its shift: impulses of 10⁹ that
// push and pull in turn, and the island refused. The solve takes the least-squares impulses instead: the
// rows' velocities as near their targets as a rigid body allows, K (J V − target) = 0, the impulses of the
// order of the island's own.
TEST(StickingSolve, TargetsNoRigidMotionMeetsGetTheNearestVelocities) {
  std::mt19937 random(37);
  for (int trial = 0; trial < 20; ++trial) {
    Island island = chain(random, {4}, 0.5);
    const Eigen::MatrixXd J = jacobian(island), K = J * inverseMass(island) * J.transpose();
    for (SolverContact& c : island.contacts) c.normal_impulse = 10.0;
    island.contacts[0].target_speed = -1e-4;
    Eigen::VectorXd target = Eigen::VectorXd::Zero(J.rows());
    target[0] = -1e-4;
    StickingScratch scratch;
    ASSERT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(4, 2), 1e-3, kSliding, scratch))
        << trial;
    const Eigen::VectorXd miss = J * velocities(island) - target;
    EXPECT_GT(miss.norm(), 1e-6) << trial;  // the targets cannot all be met
    // To the rounding of the part of b outside the range, multiplied by 1/ε (1e-16 / 1e-9).
    EXPECT_LE((K * miss).norm(), 1e-6 * K.norm() * miss.norm()) << trial;
    EXPECT_LE(impulses(island).lpNorm<Eigen::Infinity>(), 20.0) << trial;
  }
}

TEST(StickingSolve, AnIslandThatWouldPullOrSlideIsLeftAsItWas) {
  std::mt19937 random(23);
  for (const bool pulls : {true, false}) {
    // Pulling: the top body leaves upward faster than its small warm impulses hold it. Sliding: it moves
    // sideways under a friction coefficient of 0.01.
    Island island = chain(random, {4, 4}, pulls ? 1e6 : 0.01);
    for (SolverContact& c : island.contacts) c.normal_impulse = 0.01;
    island.bodies[2].v = pulls ? Eigen::Vector3d(0.0, 0.0, 5.0) : Eigen::Vector3d(2.0, 0.0, 0.0);
    const Island before = island;
    StickingScratch scratch;
    EXPECT_EQ(StickingOutcome::kRefused, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(island.contacts.size(), 3), 1e-3,
                                     kSliding, scratch)) << pulls;
    EXPECT_EQ(impulses(island), impulses(before)) << pulls;
    EXPECT_EQ(velocities(island), velocities(before)) << pulls;
  }
}

// An island one of whose points slipped, in the sweeps' last update, faster than the sliding speed and
// than a tenth of the largest normal speed a point's own impulse makes (fₙ / m_n), its friction at the
// disc's edge, is not tried, though it could stick: it is sliding, and the sweeps' result stands. A slower
// slip, or the same slip with friction to spare, is what unconverged sweeps leave, and is tried. Nor is an
// island tried whose rows the sweeps left holding to rounding (1e-15 of its impulses).
TEST(StickingSolve, AnIslandWithASlidingPointOrAlreadyHeldIsNotTried) {
  std::mt19937 random(29);
  Island island = chain(random, {4, 4}, 1e6);
  double pushed = 0.0;
  for (SolverContact& c : island.contacts) c.normal_impulse = 10.0, pushed = std::max(pushed, 10.0 / c.normal_mass);
  ASSERT_GT(0.1 * pushed, kSliding);
  island.bodies[2].v = Eigen::Vector3d(0.001, 0.0, 0.0);
  StickingScratch scratch;
  struct Case {
    double share_of_disc, slip;
    bool tried;
  };
  for (const Case& c : {Case{1.0, 1.1 * 0.1 * pushed, false}, Case{0.99, 1.1 * 0.1 * pushed, true},
                        Case{1.0, 0.9 * 0.1 * pushed, true}}) {
    Island sliding = island;
    sliding.contacts[5].friction = 0.5;
    sliding.contacts[5].friction_impulse = Eigen::Vector2d(c.share_of_disc * 0.5 * 10.0, 0.0);
    sliding.contacts[5].slip_squared = c.slip * c.slip;
    const StickingOutcome outcome =
        solveStickingIsland(sliding.contacts, sliding.bodies, SolveRange::all(8, 3), 1e-3, kSliding, scratch);
    EXPECT_EQ(outcome, c.tried ? StickingOutcome::kSolved : StickingOutcome::kNotTried)
        << c.share_of_disc << " " << c.slip;
    if (!c.tried) EXPECT_EQ(velocities(sliding), velocities(island));
  }
  island.contacts[5].slip_squared = 0.9 * kSliding * kSliding;
  EXPECT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(8, 3), 1e-3, kSliding, scratch));
  // Now held; disturbed by 1e-15 of the impulses' effect, it is left alone, by 1e-11 it is solved again.
  for (const double disturbance : {1e-15, 1e-11}) {
    Island held = island;
    held.bodies[2].v += disturbance * 10.0 * held.bodies[2].inverse_mass * Eigen::Vector3d::UnitZ();
    const StickingOutcome outcome =
        solveStickingIsland(held.contacts, held.bodies, SolveRange::all(8, 3), 1e-3, kSliding, scratch);
    EXPECT_EQ(outcome, disturbance > 1e-13 ? StickingOutcome::kSolved : StickingOutcome::kNotTried) << disturbance;
  }
}

// A face held at zero depth has points on either side of it by rounding, and those apart ask to close by
// their gap: the sweeps never settle on it. It is sunk to the resting depth (1e-9 m) within the step; a face
// already deeper than half of it is held where it is.
TEST(StickingSolve, AFaceAtZeroDepthSinksToTheRestingDepth) {
  for (const double separation : {0.0, -1e-6}) {
    std::mt19937 random(31);
    Island island = chain(random, {4}, 1e6);
    for (SolverContact& c : island.contacts) c.separation = separation, c.normal_impulse = 1.0;
    island.bodies[1].v = Eigen::Vector3d(0.0, 0.0, -1e-3);  // not yet held: the solve is tried
    const double dt = 1e-3;
    StickingScratch scratch;
    ASSERT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(4, 2), dt, kSliding, scratch));
    const double expected = separation == 0.0 ? -1e-9 / dt : 0.0;
    for (const SolverContact& c : island.contacts) {
      EXPECT_NEAR(normalSpeed(c, island.bodies[c.a], island.bodies[c.b]), expected, 1e-12) << separation;
    }
  }
}

// A point still apart that the sweeps left unpressed is no row. A box's top corners, speculative on the
// ground 0.2 m above its bottom ones and allowed to close at 0.2 m per step, contradict the bottom corners'
// stop as equalities (the least-norm impulses were of order 1e9 N s, and the island was refused): left out,
// the island is solved and they keep no impulse. A point left out that the solve would close faster than its
// target allows (here one on a body that keeps turning about its single pressed point) has the solve refused
// and the island left as it was, to the bit.
TEST(StickingSolve, APointStillApartAndUnpressedIsNoRow) {
  const double dt = 1e-3;
  {
    std::mt19937 random(37);
    Island island = chain(random, {4, 4}, 1e6);
    for (SolverContact& c : island.contacts) c.normal_impulse = 1.0;
    for (std::size_t k = 0; k < 4; ++k) {
      SolverContact top = island.contacts[k];
      top.r_a += 0.2 * top.n;
      top.separation = 0.2;
      top.normal_impulse = 0.0;
      island.contacts.push_back(top);
    }
    prepareContactRows(island.contacts, island.bodies, SolveOptions(), 0, island.contacts.size());
    for (std::size_t k = 8; k < 12; ++k) island.contacts[k].target_speed = -0.2 / dt;
    island.bodies[1].v = Eigen::Vector3d(0.0, 0.0, -1e-3);
    StickingScratch scratch;
    ASSERT_EQ(StickingOutcome::kSolved, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(12, 3), dt, kSliding, scratch));
    for (std::size_t k = 0; k < 8; ++k) {
      const SolverContact& c = island.contacts[k];
      EXPECT_NEAR(normalSpeed(c, island.bodies[c.a], island.bodies[c.b]), 0.0, 1e-12) << k;
    }
    for (std::size_t k = 8; k < 12; ++k) EXPECT_EQ(island.contacts[k].normal_impulse, 0.0) << k;
  }
  {
    std::mt19937 random(41);
    Island island = chain(random, {4, 1}, 1e6);
    for (SolverContact& c : island.contacts) c.normal_impulse = 1.0;
    SolverContact beside = island.contacts[4];
    beside.r_a += 0.3 * beside.t1;
    if (beside.b != kEnvironment) beside.r_b += 0.3 * beside.t1;
    beside.separation = 2e-9;
    beside.normal_impulse = 0.0;
    island.contacts.push_back(beside);
    prepareContactRows(island.contacts, island.bodies, SolveOptions(), 0, island.contacts.size());
    island.contacts[5].target_speed = -2e-9 / dt;
    // Body 2 turns about its one pressed point (which is then at rest) so that the point beside closes at
    // 0.3 m/s; body 1 sinks, so the island is not held and the solve is tried.
    SolverBody& top = island.bodies[2];
    top.w = beside.t2;  // 1 rad/s
    top.v = island.bodies[1].v + island.bodies[1].w.cross(island.contacts[4].r_b) - top.w.cross(island.contacts[4].r_a);
    island.bodies[1].v += Eigen::Vector3d(0.0, 0.0, -1e-3);
    ASSERT_LT(normalSpeed(island.contacts[5], top, island.bodies[1]), -0.1);
    const Island before = island;
    StickingScratch scratch;
    EXPECT_EQ(StickingOutcome::kRefused, solveStickingIsland(island.contacts, island.bodies, SolveRange::all(6, 3), dt, kSliding, scratch));
    EXPECT_EQ(impulses(island), impulses(before));
    EXPECT_EQ(velocities(island), velocities(before));
  }
}
