#include "rigid_body_sim/references.hpp"

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {
namespace reference {

namespace {
// Keep away from the separatrix Δ₂ = 0, where k → 1 and the elliptic form degenerates (docs/references.md §2.2).
constexpr double kSeparatrixGuard = 1e-9;
// ψ is integrated with 20-point Gauss–Legendre on sub-intervals of at most T_m/64 (docs/references.md §2.2 finds
// 16 points on T_m/64 accurate to 2.7e-13 rad).
constexpr int kQuadratureSubintervalsPerPeriod = 64;

// S = Rot_{e₂}(π), the relabelling for σ = −1.
const Eigen::Quaterniond kFlip(0.0, 0.0, 1.0, 0.0);
}  // namespace

Eigen::Vector3d ballisticPosition(const Eigen::Vector3d& x0, const Eigen::Vector3d& v0, const Eigen::Vector3d& force,
                                  double mass, double t) {
  return x0 + v0 * t + force * (t * t / (2.0 * mass));
}

Eigen::Vector3d dampedVelocity(const Eigen::Vector3d& v0, double damping, double mass, double t) {
  return v0 * std::exp(-damping * t / mass);
}

Eigen::Quaterniond sphereUnderBodyTorque(const Eigen::Quaterniond& q0, double I0, const Eigen::Vector3d& tau_B,
                                         double t) {
  const double theta = tau_B.norm() * t * t / (2.0 * I0);
  return q0 * quaternionExp(theta * tau_B.normalized());
}

SolidMassProperties lBracket(double density, double leg, double width, double thickness) {
  const Eigen::Vector3d size_a(leg, width, thickness), size_b(width, leg - width, thickness);
  const Eigen::Vector3d centre_a(leg / 2, width / 2, 0), centre_b(width / 2, (leg + width) / 2, 0);
  const double mass_a = density * size_a.prod(), mass_b = density * size_b.prod();
  SolidMassProperties out;
  out.mass = mass_a + mass_b;
  out.centre = (mass_a * centre_a + mass_b * centre_b) / out.mass;
  // Each box about its own centre, I = M/12 diag(y²+z², x²+z², x²+y²), moved to the common centre.
  const auto moved = [&](double m, const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
    const Eigen::Vector3d d = centre - out.centre;
    const Eigen::Matrix3d own = boxPrincipalMoments(m, size).asDiagonal();
    return Eigen::Matrix3d(own + m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  out.inertia = moved(mass_a, size_a, centre_a) + moved(mass_b, size_b, centre_b);
  return out;
}

Eigen::Quaterniond symmetricTop(double I_perp, double I_s, const Eigen::Quaterniond& q0, const Eigen::Vector3d& L_W,
                                double t) {
  const double m3 = (q0.conjugate() * L_W).z();
  return quaternionExp(t * L_W / I_perp) * q0 * quaternionExp(Eigen::Vector3d(0.0, 0.0, t * (1.0 / I_s - 1.0 / I_perp) * m3));
}

TorqueFreeBody::TorqueFreeBody(const Eigen::Vector3d& I, const Eigen::Vector3d& m0_B, const Eigen::Quaterniond& q0)
    : I_(I) {
  if (!(I(0) < I(1) && I(1) < I(2))) throw std::invalid_argument("TorqueFreeBody needs I1 < I2 < I3");
  const double I1 = I(0), I2 = I(1), I3 = I(2);
  const double m1 = m0_B(0), m2 = m0_B(1), m3 = m0_B(2);
  G_ = m0_B.norm();
  if (!(G_ > 0.0)) throw std::invalid_argument("TorqueFreeBody needs m0 != 0");
  two_T_ = m1 * m1 / I1 + m2 * m2 / I2 + m3 * m3 / I3;
  L_W_ = q0 * m0_B;
  // Δᵢ = G² − 2T Iᵢ written without cancellation (Leroy).
  const double delta1 = m2 * m2 * (I2 - I1) / I2 + m3 * m3 * (I3 - I1) / I3;
  const double delta3 = m1 * m1 * (I1 - I3) / I1 + m2 * m2 * (I2 - I3) / I2;
  const double delta2 = m1 * m1 * (I1 - I2) / I1 + m3 * m3 * (I3 - I2) / I3;
  if (std::abs(delta2) <= kSeparatrixGuard * G_ * G_) {
    throw std::invalid_argument("TorqueFreeBody: initial momentum on the separatrix (Delta2 ~ 0)");
  }
  circulates_about_3_ = delta2 > 0.0;
  const double m_a = circulates_about_3_ ? m3 : m1;  // the dn component keeps its sign
  flipped_ = m_a < 0.0;
  // In the relabelled frame m' = S m: S = Rot_{e₂}(π) negates components 1 and 3.
  const Eigen::Vector3d m = flipped_ ? Eigen::Vector3d(-m1, m2, -m3) : m0_B;
  const Eigen::Quaterniond q0_relabelled = flipped_ ? Eigen::Quaterniond(q0 * kFlip.conjugate()) : q0;

  B_(0) = std::sqrt(-delta3 * I1 / (I3 - I1));
  B_(2) = std::sqrt(delta1 * I3 / (I3 - I1));
  double phi0;
  if (circulates_about_3_) {
    k2_ = (I2 - I1) * (-delta3) / ((I3 - I2) * delta1);
    lambda_ = std::sqrt(delta1 * (I3 - I2) / (I1 * I2 * I3));
    B_(1) = std::sqrt(-delta3 * I2 / (I3 - I2));
    phi0 = std::atan2(m(1) / B_(1), m(0) / B_(0));
  } else {
    k2_ = (I3 - I2) * delta1 / ((I2 - I1) * (-delta3));
    lambda_ = std::sqrt(-delta3 * (I2 - I1) / (I1 * I2 * I3));
    B_(1) = std::sqrt(delta1 * I2 / (I2 - I1));
    phi0 = std::atan2(m(1) / B_(1), m(2) / B_(2));
  }
  nu_ = boost::math::ellint_1(std::sqrt(k2_), phi0);  // Boost takes the modulus k, not k²
  Q0_ = q0_relabelled * alignToAxis(relabelledMomentum(0.0)).conjugate();
}

Eigen::Vector3d TorqueFreeBody::relabelledMomentum(double t) const {
  // u = −σλt − ν with σ = +1 in the relabelled frame.
  const double u = -lambda_ * t - nu_;
  double cn, dn;
  const double sn = boost::math::jacobi_elliptic(std::sqrt(k2_), u, &cn, &dn);
  if (circulates_about_3_) return Eigen::Vector3d(B_(0) * cn, -B_(1) * sn, B_(2) * dn);
  return Eigen::Vector3d(B_(0) * dn, -B_(1) * sn, B_(2) * cn);
}

Eigen::Vector3d TorqueFreeBody::bodyMomentum(double t) const {
  const Eigen::Vector3d m = relabelledMomentum(t);
  return flipped_ ? Eigen::Vector3d(-m(0), m(1), -m(2)) : m;
}

double TorqueFreeBody::period() const {
  return 4.0 * boost::math::ellint_1(std::sqrt(k2_)) / lambda_;
}

Eigen::Quaterniond TorqueFreeBody::alignToAxis(const Eigen::Vector3d& m) const {
  const double G = G_;
  if (circulates_about_3_) {
    const double s = std::sqrt(2.0 * G * (G + m(2)));
    return Eigen::Quaterniond(std::sqrt((1.0 + m(2) / G) / 2.0), m(1) / s, -m(0) / s, 0.0);
  }
  const double s = std::sqrt(2.0 * G * (G + m(0)));
  return Eigen::Quaterniond(std::sqrt((1.0 + m(0) / G) / 2.0), 0.0, m(2) / s, -m(1) / s);
}

double TorqueFreeBody::psiRate(double t) const {
  const Eigen::Vector3d m = relabelledMomentum(t);
  const int a = circulates_about_3_ ? 2 : 0;
  return (two_T_ + G_ * m(a) / I_(a)) / (G_ + m(a));
}

Eigen::Quaterniond TorqueFreeBody::orientation(double t) const {
  const int intervals =
      std::max(1, static_cast<int>(std::ceil(std::abs(t) / period() * kQuadratureSubintervalsPerPeriod)));
  const double width = t / intervals;
  double psi = 0.0;
  for (int i = 0; i < intervals; ++i) {
    psi += boost::math::quadrature::gauss<double, 20>::integrate([this](double s) { return psiRate(s); }, i * width,
                                                                 (i + 1) * width);
  }
  const Eigen::Vector3d axis = circulates_about_3_ ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Quaterniond relabelled = Q0_ * quaternionExp(psi * axis) * alignToAxis(relabelledMomentum(t));
  return flipped_ ? Eigen::Quaterniond(relabelled * kFlip) : relabelled;
}

double leastSquaresSlope(const std::vector<std::pair<double, double>>& points) {
  if (points.size() < 2) return std::nan("");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(points.size());
  for (const auto& p : points) sx += p.first, sy += p.second, sxx += p.first * p.first, sxy += p.first * p.second;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double logLogSlope(const std::vector<std::pair<double, double>>& points) {
  std::vector<std::pair<double, double>> logs;
  for (const auto& p : points) logs.push_back({std::log(p.first), std::log(p.second)});
  return leastSquaresSlope(logs);
}

State bodyFixedPush(const MassProperties& mass, const Eigen::Vector3d& F_B, const Eigen::Vector3d& r_B,
                         double duration, double h) {
  using Vector13 = Eigen::Matrix<double, 13, 1>;  // q (w, x, y, z), ω_B, x, v
  const Eigen::Matrix3d& I = mass.inertia();
  const Eigen::Matrix3d I_inv = I.inverse();
  const Eigen::Vector3d tau_B = r_B.cross(F_B);
  const auto rate = [&](const Vector13& y) {
    const Eigen::Quaterniond q(y(0), y(1), y(2), y(3));
    const Eigen::Vector3d w = y.segment<3>(4);
    const Eigen::Quaterniond q_dot = q * Eigen::Quaterniond(0.0, w.x(), w.y(), w.z());
    Vector13 d;
    d << 0.5 * q_dot.w(), 0.5 * q_dot.x(), 0.5 * q_dot.y(), 0.5 * q_dot.z(), I_inv * (tau_B - w.cross(I * w)),
        y.segment<3>(10), q.normalized().toRotationMatrix() * F_B / mass.mass();
    return d;
  };
  Vector13 y = Vector13::Zero();
  y(0) = 1.0;
  const long steps = std::lround(duration / h);
  for (long k = 0; k < steps; ++k) {
    const Vector13 k1 = rate(y), k2 = rate(y + 0.5 * h * k1), k3 = rate(y + 0.5 * h * k2), k4 = rate(y + h * k3);
    y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    y.head<4>().normalize();
  }
  State state;
  state.q_WB = Eigen::Quaterniond(y(0), y(1), y(2), y(3));
  state.p_WB = y.segment<3>(7);
  state.P_W = mass.mass() * y.segment<3>(10);
  state.L_W = state.q_WB * (I * y.segment<3>(4));
  state.t = duration;
  return state;
}

const Eigen::Quaterniond& testOrientation() {
  static const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  return q0;
}

Model principalBody(const Eigen::Vector3d& moments, double mass, InertiaCheck check) {
  return Model{MassProperties::fromInertia(mass, moments.asDiagonal().toDenseMatrix(), check), ForceModel{}};
}

State torqueFreeStart(const Eigen::Vector3d& m0_B, const Eigen::Quaterniond& q0) {
  State state;
  state.q_WB = q0;
  state.L_W = q0 * m0_B;
  return state;
}

CollisionShape groundPlane(const Eigen::Vector3d& normal, double friction, double restitution, double offset) {
  CollisionShape shape;
  shape.type = ShapeType::kPlane;
  shape.name = "ground";
  shape.normal = normal.normalized();
  shape.offset = offset;
  shape.material = {restitution, friction};
  return shape;
}

CollisionShape collisionShape(ShapeType type, const Eigen::Vector3d& size, double friction, double restitution) {
  CollisionShape shape;
  shape.type = type;
  shape.size = size;
  shape.material = {restitution, friction};
  return shape;
}

MassProperties solidMass(const CollisionShape& shape, double mass) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return MassProperties::sphere(mass, shape.size.x());
    case ShapeType::kCylinder:
      return MassProperties::cylinder(mass, shape.size.x(), shape.size.y());
    default:
      return MassProperties::box(mass, shape.size);
  }
}

double depthBelowGround(const State& state, const CollisionShape& shape) {
  const Eigen::Matrix3d R = state.q_WB.toRotationMatrix();
  const double z = state.p_WB.z(), axis_z = std::abs(R(2, 2)), half = 0.5 * shape.size.y();
  switch (shape.type) {
    case ShapeType::kSphere:
      return shape.size.x() - z;
    case ShapeType::kCapsule:
      return half * axis_z + shape.size.x() - z;
    case ShapeType::kCylinder:  // its rim: the axis's half length and the radius across it
      return half * axis_z + shape.size.x() * std::sqrt(std::max(0.0, 1.0 - axis_z * axis_z)) - z;
    default:  // a box: its lowest corner, Σ |R(2, i)| size_i / 2 below the centre
      return 0.5 * (std::abs(R(2, 0)) * shape.size.x() + std::abs(R(2, 1)) * shape.size.y() +
                    std::abs(R(2, 2)) * shape.size.z()) - z;
  }
}

BodyDefinition contactBody(const MassProperties& mass, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB,
                           const Eigen::Vector3d& v_WB_W, const Eigen::Vector3d& w_WB_B, const Eigen::Vector3d& gravity_W) {
  BodyDefinition body;
  body.model.mass = mass;
  body.model.forces.gravity_W = gravity_W;
  body.initial = stateFromVelocities(mass, p_WB, q_WB, v_WB_W, w_WB_B);
  body.takes_input = false;
  return body;
}

double mechanicalEnergy(const Scene& scene) {
  double energy = 0.0;
  for (std::size_t i = 0; i < scene.bodyCount(); ++i) {
    energy += kineticEnergy(scene.model(i).mass, scene.state(i)) +
              potentialEnergy(scene.model(i).mass, scene.model(i).forces, scene.state(i));
  }
  return energy;
}

}  // namespace reference
}  // namespace rigid_body
