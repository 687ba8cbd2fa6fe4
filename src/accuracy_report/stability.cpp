#include "stability.hpp"

#include "scenes.hpp"

#include <cmath>
#include <sstream>

#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/number_format.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace accuracy_report {

using namespace rigid_body;

namespace {

using reference::torqueFreeStart;
const Eigen::Quaterniond& kQ0 = reference::testOrientation();

// Max stable step (docs/references.md §3.2): no NaN, finite q and |ΔE/E| < 10 % over a fixed number of steps.
constexpr double kStableEnergyChange = 0.1;

// Exempt from the triangle inequality: the suite uses Principia's published body I = (3, 5, 9).
Model principalBody(const Eigen::Vector3d& moments, double mass = 1.0) {
  return reference::principalBody(moments, mass, InertiaCheck::kPositiveDefiniteOnly);
}


// What a run of N steps saw.
struct RunSummary {
  State end;
  bool finite = true;
  double worst_norm_error = 0.0;    // max ||q| − 1|
  double worst_energy_change = 0.0; // max |E − E0|/E0
  double lowest_energy = 0.0;
  double highest_energy = 0.0;
};

RunSummary runSteps(IntegratorType type, const Model& model, const AppliedWrench& input, const State& start, double h,
                    long steps) {
  Integrator integrator = makeIntegrator(type);
  RunSummary summary;
  summary.end = start;
  const double energy0 = kineticEnergy(model.mass, start);
  summary.lowest_energy = summary.highest_energy = energy0;
  for (long k = 0; k < steps; ++k) {
    if (integrator.step(model, input, h, summary.end) != StepStatus::kOk) {
      summary.finite = false;
      break;
    }
    const double energy = kineticEnergy(model.mass, summary.end);
    summary.worst_norm_error = std::max(summary.worst_norm_error, std::abs(summary.end.q_WB.norm() - 1.0));
    if (energy0 > 0.0) {
      summary.worst_energy_change = std::max(summary.worst_energy_change, std::abs(energy - energy0) / energy0);
    }
    summary.lowest_energy = std::min(summary.lowest_energy, energy);
    summary.highest_energy = std::max(summary.highest_energy, energy);
  }
  return summary;
}

class Rows {
 public:
  void add(const std::string& case_name, IntegratorType type, const std::string& metric, double value,
           const std::string& threshold, bool claimed, bool pass) {
    rows_.push_back({case_name, integratorName(type), metric, value, threshold, claimed, pass});
  }
  void invariant(const std::string& case_name, IntegratorType type, const std::string& metric, double value,
                 const std::string& threshold, bool pass) {
    rows_.push_back({case_name, integratorName(type), metric, value, threshold, true, pass, true});
  }
  std::vector<StabilityRow> take() { return std::move(rows_); }

 private:
  std::vector<StabilityRow> rows_;
};

std::string format(double value) { return formatNumber(value, 6); }

// Thin rod spinning fast about its long axis, I = (ε, 1, 1 + ε), ω_B = (100, 1, 0) rad/s.
void thinRods(Rows& rows, IntegratorType type) {
  {
    const Eigen::Vector3d I(0.01, 1.0, 1.01), m0 = I.cwiseProduct(Eigen::Vector3d(100.0, 1.0, 0.0));
    const RunSummary run = runSteps(type, principalBody(I), AppliedWrench(), torqueFreeStart(m0), 0.001, 1000);
    const double theta = run.finite ? rotationAngleBetween(run.end.q_WB, reference::TorqueFreeBody(I, m0, kQ0).orientation(1.0))
                                    : INFINITY;
    // Reported, not claimed: no threshold here is derived from the methods' orders (one set by hand was
    // withdrawn); the order case holds the claims that can fail.
    rows.add("thin_rod", type, "orientation error at 1 s [rad]", theta, "", false, true);
    rows.add("thin_rod", type, "max |dE/E|", run.finite ? run.worst_energy_change : INFINITY, "", false, true);
  }
  {
    const Eigen::Vector3d I(1e-4, 1.0, 1.0 + 1e-4), m0 = I.cwiseProduct(Eigen::Vector3d(100.0, 1.0, 0.0));
    const RunSummary run = runSteps(type, principalBody(I), AppliedWrench(), torqueFreeStart(m0), 0.001, 1000);
    rows.invariant("thin_rod_1e-4", type, "finite (1 = yes)", run.finite ? 1.0 : 0.0, "= 1", run.finite);
    rows.invariant("thin_rod_1e-4", type, "max ||q| - 1|", run.worst_norm_error, "<= 1e-12", run.finite && run.worst_norm_error <= 1e-12);
  }
}

// High spin: the asymmetric body at |ω|h from 0.01 to π, and the largest stable |ω|h by bisection.
void highSpin(Rows& rows, IntegratorType type, bool quick) {
  const Eigen::Vector3d I(1, 2, 3), m0(1, 0.5, 2);
  const Model model = principalBody(I);
  const double w = angularVelocity(model.mass, torqueFreeStart(m0)).norm();
  for (double wh : {0.01, 0.1, 0.3, 1.0, M_PI}) {
    const RunSummary run = runSteps(type, model, AppliedWrench(), torqueFreeStart(m0), wh / w, 1000);
    rows.invariant("high_spin", type, "max ||q| - 1| at |w|h = " + format(wh), run.finite ? run.worst_norm_error : INFINITY,
             "<= 1e-12", run.finite && run.worst_norm_error <= 1e-12);
  }
  {
    // 100 steps at |ω|h = 0.1: 10 rad of rotation.
    const double h = 0.1 / w;
    const RunSummary run = runSteps(type, model, AppliedWrench(), torqueFreeStart(m0), h, 100);
    const double theta = run.finite ? rotationAngleBetween(run.end.q_WB, reference::TorqueFreeBody(I, m0, kQ0).orientation(run.end.t))
                                    : INFINITY;
    // Reported, not claimed: the 1e-3 rad once claimed here was set by hand, 45× to 45 000× above the values.
    rows.add("high_spin", type, "orientation error after 100 steps at |w|h = 0.1 [rad]", theta, "", false, true);
  }
  // Bisection in log(|ω|h) on [0.01, 100] for stability over a fixed number of steps.
  const long steps = quick ? 200 : 1000;
  const auto stable = [&](double wh) {
    const RunSummary run = runSteps(type, model, AppliedWrench(), torqueFreeStart(m0), wh / w, steps);
    return run.finite && run.worst_energy_change < kStableEnergyChange;
  };
  double low = 0.01, high = 100.0;
  if (stable(high)) {
    low = high;
  } else {
    for (int i = 0; i < (quick ? 12 : 24); ++i) {
      const double middle = std::sqrt(low * high);
      (stable(middle) ? low : high) = middle;
    }
  }
  rows.add("high_spin", type, "largest stable |w|h (" + std::to_string(steps) + " steps, |dE/E| < 10 %)", low, "",
           false, true);
}

// Principia's Dzhanibekov body I = (3, 5, 9), m₀ = (0.01, 2, 0.01), 130 s at h = 0.1 s.
void dzhanibekov(Rows& rows, IntegratorType type) {
  const Eigen::Vector3d I(3, 5, 9), m0(0.01, 2, 0.01);
  const reference::TorqueFreeBody exact(I, m0, kQ0);
  const double h = 0.1, T = 130.0;
  // The reference's sign changes of m₂, on the same grid.
  int expected = 0;
  double previous = m0.y();
  for (long k = 1; k <= std::lround(T / h); ++k) {
    const double m2 = exact.bodyMomentum(k * h).y();
    if ((m2 < 0.0) != (previous < 0.0)) ++expected;
    previous = m2;
  }
  const Model model = principalBody(I);
  State state = torqueFreeStart(m0);
  Integrator integrator = makeIntegrator(type);
  std::vector<double> changes;
  previous = m0.y();
  bool finite = true;
  for (long k = 0; k < std::lround(T / h); ++k) {
    if (integrator.step(model, AppliedWrench(), h, state) != StepStatus::kOk) {
      finite = false;
      break;
    }
    const double m2 = (state.q_WB.conjugate() * state.L_W).y();
    if ((m2 < 0.0) != (previous < 0.0)) changes.push_back(state.t - h * m2 / (m2 - previous));
    previous = m2;
  }
  const int count = finite ? static_cast<int>(changes.size()) : -1;
  rows.add("dzhanibekov_130s", type, "flips (sign changes of m2) in 130 s", count, "= " + std::to_string(expected),
           nominalOrder(type) >= 2, count == expected);
  const double interval = changes.size() >= 2 ? (changes.back() - changes.front()) / (changes.size() - 1) : NAN;
  const double relative = std::abs(interval / exact.flipTime() - 1.0);
  rows.add("dzhanibekov_130s", type, "flip time relative error (t_flip = " + format(exact.flipTime()) + " s)",
           std::isfinite(relative) ? relative : INFINITY, "", false, true);
}

// ω ∈ {0, 1e-300, 1e-12, 1e-8} about a principal axis: one step of 10 ms turns by |ω|h exactly.
void nearZero(Rows& rows, IntegratorType type) {
  const Model model = principalBody(Eigen::Vector3d(1, 2, 3));
  const double h = 0.01;
  double worst = 0.0;
  bool finite = true;
  for (double w : {0.0, 1e-300, 1e-12, 1e-8}) {
    State state = torqueFreeStart(Eigen::Vector3d(w, 0.0, 0.0), Eigen::Quaterniond::Identity());
    Integrator integrator = makeIntegrator(type);
    if (integrator.step(model, AppliedWrench(), h, state) != StepStatus::kOk || !isFinite(state)) {
      finite = false;
      continue;
    }
    const double angle = rotationAngleBetween(Eigen::Quaterniond::Identity(), state.q_WB);
    worst = std::max(worst, w == 0.0 ? angle : std::abs(angle / (w * h) - 1.0));
  }
  rows.invariant("near_zero_omega", type, "finite for w in {0, 1e-300, 1e-12, 1e-8} (1 = yes)", finite ? 1 : 0, "= 1", finite);
  rows.add("near_zero_omega", type, "max relative error of the rotation angle |w|h", finite ? worst : INFINITY,
           "<= 1e-15", true, finite && worst <= 1e-15);  // a few ulps of 1: the rotation is exact but for rounding
}

// Scaling mass, inertia, forces, damping and momenta by s leaves the motion unchanged.
void scaleInvariance(Rows& rows, IntegratorType type) {
  const auto trajectory = [&](double s) {
    Model model = principalBody(s * Eigen::Vector3d(1, 2, 3), s * 2.0);
    model.forces.gravity_W = Eigen::Vector3d(0, 0, -9.81);
    model.forces.linear_damping = 0.05 * s;
    model.forces.angular_damping = 0.01 * s;
    AppliedWrench input;
    input.world.force = s * Eigen::Vector3d(0.3, -0.2, 0.1);
    input.body.torque = s * Eigen::Vector3d(0.01, 0.02, -0.01);
    State start = torqueFreeStart(s * Eigen::Vector3d(1, 0.5, 2));
    start.p_WB = Eigen::Vector3d(1, 2, 3);
    start.P_W = s * 2.0 * Eigen::Vector3d(0.5, 0, 1);
    return runSteps(type, model, input, start, 0.001, 10000).end;
  };
  const State unit = trajectory(1.0);
  double worst = 0.0;
  for (double s : {1e-9, 1e9}) {
    const State scaled = trajectory(s);
    worst = std::max(worst, (scaled.p_WB - unit.p_WB).norm() / unit.p_WB.norm());
    worst = std::max(worst, rotationAngleBetween(scaled.q_WB, unit.q_WB));
  }
  // dopri5's abs_tolerance is an absolute error by definition: its steps depend on the scale.
  // Scaling is exact in real arithmetic; in doubles each of the 1e4 steps may round differently, ~1e-16 a
  // step relative: 1e4 · 1e-16 = 1e-12.
  rows.add("scale_1e-9_1e9", type, "max relative difference of x and q to s = 1 over 1e4 steps", worst, "<= 1e-12",
           !rigid_body::integratorInfo(type).adaptive, worst <= 1e-12);
}

// h = 1 s: no NaN and the energy stays in [G²/2I_max, G²/2I_min]; the error is reported.
void largeStep(Rows& rows, IntegratorType type) {
  const Eigen::Vector3d I(1, 2, 3), m0(1, 0.5, 2);
  const RunSummary run = runSteps(type, principalBody(I), AppliedWrench(), torqueFreeStart(m0), 1.0, 100);
  const double G2 = m0.squaredNorm();
  const bool bounded = run.finite && run.lowest_energy >= G2 / (2 * I(2)) * (1 - 1e-12) &&
                       run.highest_energy <= G2 / (2 * I(0)) * (1 + 1e-12);
  rows.invariant("large_step_1s", type, "finite, energy within [G^2/2I_max, G^2/2I_min] (1 = yes)", bounded ? 1 : 0, "= 1", bounded);
  const double theta = run.finite ? rotationAngleBetween(run.end.q_WB, reference::TorqueFreeBody(I, m0, kQ0).orientation(100.0))
                                  : INFINITY;
  rows.add("large_step_1s", type, "orientation error at 100 s [rad]", theta, "", false, true);
}

// c/m = 1000 1/s (and c_ω/I = 1000 1/s) at h = 10 ms: explicit methods need h < 2m/c = 2 ms.
void stiffDamping(Rows& rows, IntegratorType type) {
  Model model{MassProperties::sphere(1.0, 0.5), ForceModel{}};
  model.forces.linear_damping = 1000.0;
  model.forces.angular_damping = 1000.0 * model.mass.inertia()(0, 0);
  State state = stateFromVelocities(model.mass, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                    Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1));
  Integrator integrator = makeIntegrator(type);
  bool monotone = true;
  for (int k = 0; k < 100; ++k) {
    const State before = state;
    if (integrator.step(model, AppliedWrench(), 0.01, state) != StepStatus::kOk) {
      monotone = false;
      break;
    }
    // Decay without growth or a change of sign, linear and angular.
    monotone = monotone && state.P_W.x() >= 0.0 && state.P_W.x() <= before.P_W.x() && state.L_W.z() >= 0.0 &&
               state.L_W.z() <= before.L_W.z();
  }
  // Claimed where damping is integrated exactly (the Strang methods' exponential flow E). dopri5 adapts
  // and stays stable but chatters around zero at its absolute tolerance: reported, not claimed.
  const bool claims = rigid_body::integratorInfo(type).exact_damping;
  rows.add("stiff_damping", type, "monotone decay at h = 10 ms, c/m = 1000/s (1 = yes)", monotone ? 1 : 0, "= 1", claims,
           monotone);
  rows.add("stiff_damping", type, "|v| after 1 s / |v0| (exact: e^-1000)",
           isFinite(state) ? std::abs(state.P_W.x()) : INFINITY, "", false, true);
}

}  // namespace

// Tolerance proportionality: an error-controlled method's global error follows its tolerance, e ∝ tol^α with
// α = 1 the ideal (Hairer, Nørsett & Wanner, Solving ODEs I, II.4). dopri5 claims α >= ½, halfway between
// the ideal and a method that ignores the tolerance (α = 0), measured from tol = 1e-6 to 1e-8 at the node's
// output step of 10 ms on the asymmetric body over 2 s.
void toleranceClaim(Rows& rows, IntegratorType type) {
  const Scene scene = asymmetricScene(2.0);
  const auto error = [&](double tolerance) {
    IntegratorSettings settings;
    settings.abs_tolerance = settings.rel_tolerance = tolerance;
    Integrator integrator = makeIntegrator(type, settings);
    return errorOf(scene, runScene(scene, integrator, 0.01));
  };
  const double alpha = std::log10(error(1e-6) / error(1e-8)) / 2.0;
  rows.add("order", type, "tolerance exponent a of e ~ tol^a, tol 1e-6 to 1e-8, asymmetric 2 s, output step 0.01 s",
           std::isfinite(alpha) ? alpha : -INFINITY, ">= 0.5", true, alpha >= 0.5);
}

// Order: every fixed-step method claims its nominal order p on two closed-form torque-free scenes, as the
// observed order log2(e(h)/e(h/2)). The threshold is p − ½, halfway between the order claimed and the next
// lower one, so a method of order p − 1 fails it whatever its error constant. The steps are in each order's
// asymptotic range above rounding (the integrator suite's order test uses the same: 0.1 s for order 4,
// 0.02 s for the others). dopri5 chooses its own steps and claims its tolerance instead (high_spin).
void orderClaims(Rows& rows, IntegratorType type) {
  if (rigid_body::integratorInfo(type).adaptive) {
    toleranceClaim(rows, type);
    return;
  }
  const int order = nominalOrder(type);
  const double h = order == 4 ? 0.1 : 0.02;
  const std::vector<Scene> scenes = {
      asymmetricScene(2.0),
      torqueFreeScene("t_handle", "T handle I = (1, 2, 3), m0 = (0.1, 2, 0.1), before its first flip",
                      Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.1, 2, 0.1), 5.0)};
  for (const Scene& scene : scenes) {
    Integrator coarse = makeIntegrator(type), fine = makeIntegrator(type);
    const double observed = std::log2(errorOf(scene, runScene(scene, coarse, h)) / errorOf(scene, runScene(scene, fine, 0.5 * h)));
    rows.add("order", type, "observed order log2(e(h)/e(h/2)), " + scene.name + " " + format(scene.duration) +
             " s, h = " + format(h) + " s", std::isfinite(observed) ? observed : -INFINITY,
             ">= " + format(order - 0.5), true, observed >= order - 0.5);
  }
}

std::vector<StabilityRow> runStabilitySuite(bool quick) {
  Rows rows;
  for (IntegratorType type : allIntegrators()) {
    orderClaims(rows, type);
    thinRods(rows, type);
    highSpin(rows, type, quick);
    dzhanibekov(rows, type);
    nearZero(rows, type);
    scaleInvariance(rows, type);
    largeStep(rows, type);
    stiffDamping(rows, type);
  }
  return rows.take();
}

std::vector<std::pair<std::string, std::string>> stabilityCaseDescriptions(bool quick) {
  return {
      {"order", "every fixed-step method claims its nominal order p as log2(e(h)/e(h/2)) >= p - 1/2 (halfway to the next lower order) on the torque-free asymmetric body (2 s) and the T handle before its flip (5 s); dopri5 claims that its error follows its tolerance, e ~ tol^a with a >= 1/2"},
      {"thin_rod", "I = (0.01, 1, 1.01), w_B = (100, 1, 0) rad/s, h = 1 ms, 1 s; reported"},
      {"thin_rod_1e-4", "I = (1e-4, 1, 1 + 1e-4), same spin, h = 1 ms, 1 s; every method"},
      {"high_spin", std::string("I = (1, 2, 3), m0 = (1, 0.5, 2) at |w|h in {0.01, 0.1, 0.3, 1, pi}, 1000 steps; ") +
                        "orientation error at |w|h = 0.1 reported; largest stable |w|h by bisection over " +
                        (quick ? "200" : "1000") + " steps"},
      {"dzhanibekov_130s", "I = (3, 5, 9), m0 = (0.01, 2, 0.01), h = 0.1 s, 130 s; flip count claimed by order >= 2 (an exact count), flip time reported"},
      {"near_zero_omega", "w in {0, 1e-300, 1e-12, 1e-8} rad/s about a principal axis, one step of 10 ms; every method"},
      {"scale_1e-9_1e9", "mass, inertia, forces, damping and momenta times s in {1e-9, 1e9}, 1e4 steps of 1 ms, against s = 1; every method but dopri5 (absolute tolerance)"},
      {"large_step_1s", "I = (1, 2, 3), m0 = (1, 0.5, 2), h = 1 s, 100 steps; every method"},
      {"stiff_damping", "sphere, c/m = c_w/I = 1000 1/s, h = 10 ms (explicit limit 2 ms); claimed by the methods with exact damping (symplectic_splitting, implicit_midpoint)"},
      {"long_run", std::string(quick ? "1e5" : "1e6") + " steps of 50 ms, I = (1, 2, 3), m0 = (1, 0.5, 2); ||q|-1| and |dL|/|L| every method, |dE/E| by symplectic_splitting (<= 2e-5) and rk4 (<= 2e-4)"},
  };
}

}  // namespace accuracy_report
