// A manifold's normal impulses solved together (docs/contact.md, "A face's normals together";
// src/contact/joint_normals.hpp). The matrix is K's Moore–Penrose inverse, K built here afresh from the
// contacts' 12-column Jacobians (not from the solver's products): a missing inertia term, an uncentred face,
// a plain inverse of the singular four-point K or a wrong reduction fails the Penrose conditions. One sweep
// stops a face that the point-by-point updates leave moving; faces that cannot be solved together (a line of
// points, a lone point) are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "random_solver_bodies.hpp"
#include "../../src/contact/joint_normals.hpp"

using namespace rigid_body;
using namespace rigid_body::contact;

namespace {

using Jacobian = Eigen::Matrix<double, 1, 12>;

using test::randomBody;
using test::randomUnit;

// `count` points of a face with normal n (from b towards a) about a centre c, their arms from a's centre
// xa and b's centre xb, and each one's Jacobian row J_i = (n, r_a × n, −n, −r_b × n).
struct Face {
  std::vector<SolverContact> points;
  std::vector<Jacobian> rows;
};
Face face(const std::vector<Eigen::Vector2d>& on_face, const Eigen::Vector3d& n, const Eigen::Vector3d& centre,
          const Eigen::Vector3d& xa, const Eigen::Vector3d& xb, bool b_is_body) {
  Face f;
  const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  for (const Eigen::Vector2d& uv : on_face) {
    const Eigen::Vector3d p = centre + uv.x() * t1 + uv.y() * t2;
    SolverContact c;
    c.a = 1, c.b = b_is_body ? 2 : kEnvironment;
    c.r_a = p - xa;
    if (b_is_body) c.r_b = p - xb;
    c.n = n, c.t1 = t1, c.t2 = t2;
    c.sustained = true;
    f.points.push_back(c);
    Jacobian row = Jacobian::Zero();
    row.segment<3>(0) = n.transpose(), row.segment<3>(3) = c.r_a.cross(n).transpose();
    if (b_is_body) row.segment<3>(6) = -n.transpose(), row.segment<3>(9) = -c.r_b.cross(n).transpose();
    f.rows.push_back(row);
  }
  return f;
}

Eigen::Matrix<double, 12, 12> inverseMass(const SolverBody& a, const SolverBody& b) {
  Eigen::Matrix<double, 12, 12> M = Eigen::Matrix<double, 12, 12>::Zero();
  M.block<3, 3>(0, 0) = a.inverse_mass * Eigen::Matrix3d::Identity(), M.block<3, 3>(3, 3) = a.inverse_inertia_W;
  M.block<3, 3>(6, 6) = b.inverse_mass * Eigen::Matrix3d::Identity(), M.block<3, 3>(9, 9) = b.inverse_inertia_W;
  return M;
}

// The solver's products (r × n, I⁻¹ (r × n), ...) for the face's points, as a step prepares them.
void prepare(Face& f, std::vector<SolverBody>& bodies) {
  prepareContactRows(f.points, bodies, SolveOptions(), 0, f.points.size());
}

}  // namespace

TEST(JointNormals, TheMatrixIsThePseudoInverseOfTheFacesCouplingOnAnyFace) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int faces = 0;
  for (int trial = 0; trial < 400; ++trial) {
    // Three or four points of a rectangle or of a skewed quadrilateral, on a body or on the environment.
    const std::size_t count = 3 + trial % 2;
    const bool b_is_body = trial % 3 != 0;
    std::vector<SolverBody> bodies{environmentBody(), randomBody(random), randomBody(random)};
    if (!b_is_body) bodies[2] = environmentBody();
    const double hx = 0.02 + 0.5 * unit(random), hy = 0.02 + 0.5 * unit(random);
    std::vector<Eigen::Vector2d> on_face{{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    for (Eigen::Vector2d& p : on_face) p += 0.3 * Eigen::Vector2d(unit(random) - 0.5, unit(random) - 0.5).cwiseProduct(Eigen::Vector2d(hx, hy));
    on_face.resize(count);
    const Eigen::Vector3d n = randomUnit(random), centre = randomUnit(random);
    Face f = face(on_face, n, centre, centre + 0.4 * randomUnit(random), centre - 0.4 * randomUnit(random), b_is_body);
    prepare(f, bodies);
    JointInverse inverse;
    ASSERT_TRUE(jointNormalInverse(f.points.data(), count, bodies[1].inverse_mass, bodies[2].inverse_mass, inverse))
        << trial;
    Eigen::MatrixXd J(count, 12);
    for (std::size_t i = 0; i < count; ++i) J.row(i) = f.rows[i];
    const Eigen::MatrixXd K = J * inverseMass(bodies[1], bodies[2]) * J.transpose();
    Eigen::MatrixXd B(count, count);
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t j = 0; j < count; ++j) B(i, j) = inverse[jointEntry(i, j)];
    }
    const double scale = K.norm() * B.norm();
    EXPECT_LE((K * B * K - K).norm(), 1e-9 * scale * K.norm()) << trial;
    EXPECT_LE((B * K * B - B).norm(), 1e-9 * scale * B.norm()) << trial;
    EXPECT_LE((K * B - (K * B).transpose()).norm(), 1e-9 * scale) << trial;
    EXPECT_LE((B - B.transpose()).norm(), 1e-9 * B.norm()) << trial;
    // A residual any relative motion of the two bodies leaves is removed exactly.
    Eigen::Matrix<double, 12, 1> V;
    for (int k = 0; k < 12; ++k) V(k) = unit(random) - 0.5;
    const Eigen::VectorXd r = J * V;
    EXPECT_LE((K * (B * r) - r).norm(), 1e-9 * scale * r.norm()) << trial;
    ++faces;
  }
  EXPECT_EQ(faces, 400);
}

TEST(JointNormals, TwoPointsInvertTheirCouplingAndALineOrALonePointIsRefused) {
  std::mt19937 random(9);
  std::vector<SolverBody> bodies{environmentBody(), randomBody(random), randomBody(random)};
  const Eigen::Vector3d n = randomUnit(random), centre(0.1, 0.2, 0.3);
  Face edge = face({{-0.2, 0.0}, {0.2, 0.0}}, n, centre, centre + 0.3 * n, centre - 0.3 * n, true);
  prepare(edge, bodies);
  JointInverse inverse;
  ASSERT_TRUE(jointNormalInverse(edge.points.data(), 2, bodies[1].inverse_mass, bodies[2].inverse_mass, inverse));
  Eigen::Matrix2d K, B;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      K(i, j) = edge.rows[i] * inverseMass(bodies[1], bodies[2]) * edge.rows[j].transpose();
      B(i, j) = inverse[jointEntry(i, j)];
    }
  }
  EXPECT_LE((B * K - Eigen::Matrix2d::Identity()).norm(), 1e-12);

  Face line = face({{-0.2, 0.0}, {0.0, 0.0}, {0.2, 0.0}}, n, centre, centre + 0.3 * n, centre - 0.3 * n, true);
  prepare(line, bodies);
  EXPECT_FALSE(jointNormalInverse(line.points.data(), 3, bodies[1].inverse_mass, bodies[2].inverse_mass, inverse));
  EXPECT_FALSE(jointNormalInverse(line.points.data(), 1, bodies[1].inverse_mass, bodies[2].inverse_mass, inverse));
}

// A cube resting on the ground, falling at g h at the start of the step (what one step of gravity leaves) and
// rocking a little: one sweep of the readable solver stops all four corners at once. Point by point, each
// corner's impulse turns the cube about the others and one sweep leaves them moving (docs/performance_log.md,
// "A settled stack's sweeps do not converge").
TEST(JointNormals, OneSweepStopsEveryCornerOfAFace) {
  std::vector<SolverBody> bodies{environmentBody(), SolverBody()};
  SolverBody& cube = bodies[1];
  cube.inverse_mass = 1.0;
  cube.inverse_inertia_W = Eigen::Matrix3d::Identity() / (0.2 * 0.2 / 6.0);
  cube.v = Eigen::Vector3d(0.0, 0.0, -9.81e-3);
  cube.w = Eigen::Vector3d(0.02, -0.01, 0.0);
  Face f = face({{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(),
                Eigen::Vector3d(0.0, 0.0, 0.1), Eigen::Vector3d::Zero(), false);
  SolveOptions options;
  options.iterations = 1;
  options.sweep_budget_contacts = 0;  // one sweep, not a small scene's extra ones
  prepareContacts(f.points, bodies, options);
  solveVelocities(f.points, bodies, options);
  for (const SolverContact& c : f.points) {
    const double v_n = c.n.dot(cube.v) + c.cross_a.col(0).dot(cube.w);
    EXPECT_NEAR(v_n, 0.0, 1e-12);
    EXPECT_GT(c.normal_impulse, 0.0);
  }
}
