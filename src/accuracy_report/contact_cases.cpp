// The stiff and extreme contact cases of the accuracy report's stability suite (docs/report.md): stacks, mass
// ratios, tunnelling, Newton's cradle, the friction angle, a spinning ball, Painlevé's rod, a pile and a long
// rest, each with what it claims and what a wrong solver it would catch.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "contact_report.hpp"
#include "contact_scene.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/number_format.hpp"

namespace accuracy_report {

namespace {

class CaseRows {
 public:
  void claim(const std::string& c, IntegratorType type, const std::string& metric, double value, const std::string& op,
             double bound) {
    const bool pass = op == "<=" ? value <= bound : value >= bound;
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, op + " " + rigid_body::formatNumber(bound, 6),
                     true, pass});
  }
  // Kept by construction: checked and shown apart, never counted as a claim.
  void invariant(const std::string& c, IntegratorType type, const std::string& metric, double value, double bound) {
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, "<= " + rigid_body::formatNumber(bound, 6),
                     true, value <= bound, true});
  }
  void report(const std::string& c, IntegratorType type, const std::string& metric, double value) {
    rows_.push_back({c, rigid_body::integratorName(type), metric, value, "", false, false});
  }
  std::vector<StabilityRow> take() { return std::move(rows_); }

 private:
  std::vector<StabilityRow> rows_;
};

const Eigen::Vector3d kBoxSize(0.3, 0.3, 0.2);
constexpr double kStackDrift = 0.01;  // [m] the top box's claimed largest displacement (10 and 20 boxes)
constexpr int kPerturbedStarts = 8;   // the stack of 20 also from this many starts moved by k·1e-12 m

struct StackResult {
  double drift = 0.0;        // [m] the top box's largest displacement from its start
  double penetration = 0.0;  // [m] the deepest penetration
  double slip = 0.0;         // [m] the largest slip at an interface
};

// Boxes of `masses` stacked on the ground from below, over `duration`: the top box's largest displacement, the
// deepest penetration, and the largest slip at an interface (the horizontal offset of a box's bottom-face
// centre from the top-face centre of the box below, or from the ground point under the first box's start;
// the boxes' tilts move it only to second order). `offset` moves box i by offset·(i mod 3) along x at the
// start (a start that differs from the aligned one by rounding-sized amounts).
StackResult stack(const std::vector<double>& masses, IntegratorType type, double duration, double offset = 0.0) {
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
  std::vector<BodyDefinition> bodies;
  for (std::size_t i = 0; i < masses.size(); ++i) {
    bodies.push_back(body(MassProperties::box(masses[i], kBoxSize), Eigen::Vector3d(offset * double(i % 3), 0, 0.1 + 0.2 * i),
                          Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
    setup.bodies.push_back(shape(ShapeType::kBox, kBoxSize, 0.5, 0.0));
  }
  rigid_body::Scene scene = makeScene(bodies, setup, type, 1e-3, ContactSettings());
  StackResult result;
  const Eigen::Vector3d half_height(0.0, 0.0, 0.5 * kBoxSize.z());
  for (std::int64_t i = 0, n = stepsFor(duration, 1e-3); i < n; i += 100) {
    scene.step(100);
    const State& top = scene.state(masses.size() - 1);
    result.drift = std::max(result.drift, (top.p_WB - scene.initialState(masses.size() - 1).p_WB).norm());
    if (!(result.drift < 1.0)) break;  // fallen
    Eigen::Vector3d below = scene.initialState(0).p_WB - half_height;
    for (std::size_t b = 0; b < masses.size(); ++b) {
      const State& box = scene.state(b);
      result.slip = std::max(result.slip, (box.p_WB - box.q_WB * half_height - below).head<2>().norm());
      below = box.p_WB + box.q_WB * half_height;
    }
  }
  result.penetration = scene.contactStatistics().max_penetration;
  return result;
}

void stacks(CaseRows& rows, bool quick) {
  const double duration = quick ? 2.0 : 10.0;
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    for (std::size_t height : {10u, 20u, 50u}) {
      const std::string name = "contact_stack_" + std::to_string(height);
      const StackResult result = stack(std::vector<double>(height, 1.0), type, duration);
      if (height <= 20) {
        rows.claim(name, type, "largest top-box displacement [m]", result.drift, "<=", kStackDrift);
      } else {
        rows.report(name, type, "largest top-box displacement [m]", result.drift);
      }
      rows.report(name, type, "deepest penetration [m]", result.penetration);
      rows.report(name, type, "largest slip at an interface [m]", result.slip);
    }
    if (quick) continue;
    // How much of the stack of 20's drift is the draw of rounding: the same stack from starts moved by
    // k·1e-12 m (k = 1 … kPerturbedStarts; box i by k·1e-12·(i mod 3)), reported.
    double largest = 0.0;
    int over = 0;
    for (int k = 1; k <= kPerturbedStarts; ++k) {
      const double drift = stack(std::vector<double>(20, 1.0), type, duration, 1e-12 * k).drift;
      largest = std::max(largest, drift);
      over += drift > kStackDrift ? 1 : 0;
    }
    const std::string starts = std::to_string(kPerturbedStarts);
    rows.report("contact_stack_20", type, "largest top-box displacement over " + starts + " starts moved by <= 2e-11 m [m]",
                largest);
    rows.report("contact_stack_20", type, "of those " + starts + " starts, top box beyond 1 cm", over);
  }
}

void massRatios(CaseRows& rows, bool quick) {
  const double duration = quick ? 1.0 : 5.0;
  const IntegratorType type = IntegratorType::kRk4;
  for (double ratio : {100.0, 1000.0}) {
    for (bool heavy_on_top : {true, false}) {
      const std::string name = std::string("contact_mass_ratio_") + (ratio == 100.0 ? "100" : "1000") +
                               (heavy_on_top ? "_heavy_on_light" : "_light_on_heavy");
      const StackResult result = stack(heavy_on_top ? std::vector<double>{1.0, ratio} : std::vector<double>{ratio, 1.0},
                                       type, duration);
      rows.claim(name, type, "deepest penetration [m]", result.penetration, "<=", 1e-3);
      rows.claim(name, type, "largest top-box displacement [m]", result.drift, "<=", 1e-3);
    }
  }
}

// A sphere (r = 5 cm) shot at a 1 mm plate at `speed` (down, and sideways a fifth of that), h = 10 ms, from
// eight start heights spread over one step's travel (so that the touch falls early, late and mid-step on a
// path that gravity bends off the step's chord): the lowest its centre ends above the plate's top, one step
// after its first impact. It catches a continuous test that sweeps the chord, one that drops a touch it
// cannot bracket, and one that lets the remainder of a step pass the plate after an impact.
void tunneling(CaseRows& rows) {
  const double radius = 0.05, thickness = 1e-3, h = 1e-2;
  for (double speed : {10.0, 100.0, 1000.0}) {
    for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
      double lowest = std::numeric_limits<double>::infinity();
      for (int start = 0; start < 8; ++start) {
        CollisionShape plate = shape(ShapeType::kBox, Eigen::Vector3d(12.0, 12.0, thickness), 0.5, 0.0);
        plate.name = "plate";
        ContactSetup setup;
        setup.environment = {plate};
        setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.5, 0.0)};
        const double height = 1.0 + (start + 0.5) / 8.0 * speed * h;
        rigid_body::Scene scene = makeScene({body(MassProperties::sphere(0.5, radius), Eigen::Vector3d(0, 0, height),
                                                  Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.2 * speed, 0, -speed),
                                                  Eigen::Vector3d::Zero(), kDown)},
                                            setup, type, h, ContactSettings());
        const std::int64_t flight = stepsFor((height + 0.5) / speed, h) + 1;
        for (std::int64_t i = 0; i < flight && scene.impacts().empty(); ++i) scene.step(1);
        scene.step(1);
        lowest = std::min(lowest, scene.state().p_WB.z() - 0.5 * thickness);
      }
      const std::string name = "contact_tunneling_" + rigid_body::formatNumber(speed, 4) + "_m_s";
      rows.claim(name, type, "lowest centre height above the plate's top [m]", lowest, ">=", radius - 1e-3);
    }
  }
}

// Newton's cradle: a ball at 1 m/s strikes a row of four touching equal balls (e = 1, no friction), h = 1 ms.
// The impulse crosses the row pair by pair, so the last ball leaves at 1 m/s and the rest stand still: the
// largest velocity error of the five balls. It catches a solver that shares the impact among the touching
// contacts at once (the three-ball cradle then ends at (−1/3, 2/3, 2/3) v).
void cradle(CaseRows& rows) {
  const double radius = 0.05;
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    ContactSetup setup;
    std::vector<BodyDefinition> balls;
    for (int i = 0; i < 5; ++i) {
      setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0));
      balls.push_back(body(MassProperties::sphere(1.0, radius), Eigen::Vector3d(i == 0 ? -0.3 : 2.0 * radius * (i - 1), 0, 0),
                           Eigen::Quaterniond::Identity(), Eigen::Vector3d(i == 0 ? 1.0 : 0.0, 0, 0),
                           Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
    }
    rigid_body::Scene scene = makeScene(balls, setup, type, 1e-3, ContactSettings());
    scene.step(stepsFor(0.5, 1e-3));
    double error = 0.0;
    for (std::size_t i = 0; i < 5; ++i) error = std::max(error, std::abs(scene.state(i).P_W.x() - (i == 4 ? 1.0 : 0.0)));
    rows.claim("contact_cradle", type, "largest velocity error [m/s]", error, "<=", 1e-9);
  }
}

// A box on an incline at 0.98 of its friction angle, yawed by 0.5 rad so that the slip it would have is
// diagonal to the contact's tangent basis: it must hold (claimed: ≤ 0.1 mm in the run). It catches friction
// whose corners saturate early in directions that cancel. At exactly the angle (tan θ = μ) the rigid model with
// Coulomb friction is at its limit, where rounding decides: what the solver does is reported.
void frictionAngle(CaseRows& rows, bool quick) {
  const double mu = 0.5, duration = quick ? 1.0 : 5.0;
  const IntegratorType type = IntegratorType::kRk4;
  for (double share : {0.98, 1.0}) {
    const double theta = std::atan(share * mu);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
    ContactSetup setup;
    setup.environment = {plane(q * Eigen::Vector3d::UnitZ(), mu)};
    const Eigen::Vector3d size(0.2, 0.2, 0.1);
    setup.bodies = {shape(ShapeType::kBox, size, mu, 0.0)};
    const Eigen::Vector3d start = 0.05 * (q * Eigen::Vector3d::UnitZ());
    const Eigen::Quaterniond yawed = share < 1.0 ? q * Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())) : q;
    rigid_body::Scene scene = makeScene({body(MassProperties::box(1.0, size), start, yawed, Eigen::Vector3d::Zero(),
                                              Eigen::Vector3d::Zero(), kDown)},
                                        setup, type, 1e-3, ContactSettings());
    scene.step(stepsFor(duration, 1e-3));
    const double slid = (scene.state().p_WB - start).norm();
    if (share < 1.0) {
      rows.claim("contact_friction_angle_0.98", type, "distance slid [m]", slid, "<=", 1e-4);
    } else {
      rows.report("contact_friction_angle", type, "distance slid [m]", slid);
    }
  }
}

// A sphere spun at 100 rad/s about a horizontal axis and set on the ground: it skids, friction μ M g
// speeding it up (a = μ g) and slowing its spin (α = μ M g r / I), until v = ω r at t = 2 ω₀ r/(7 μ g); it then
// rolls at v = (2/7) ω₀ r. The rolling speed follows from the angular momentum about the contact point, which
// impulses at that point keep by construction: an invariant. When the skid ends is the accuracy claim.
void spinningBall(CaseRows& rows) {
  const double radius = 0.1, w0 = 100.0, mu = 0.5, dt = 1e-3;
  for (IntegratorType type : kMethods) {
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), mu)};
    setup.bodies = {shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), mu, 0.0)};
    const MassProperties ball = MassProperties::sphere(1.0, radius);
    rigid_body::Scene scene = makeScene({body(ball, Eigen::Vector3d(0, 0, radius), Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d(0, w0, 0), kDown)},
                                        setup, type, dt, ContactSettings());
    double rolling_from = -1.0;
    for (std::int64_t i = 1, n = stepsFor(1.0, dt); i <= n; ++i) {
      scene.step(1);
      const Eigen::Vector3d v = rigid_body::linearVelocity(ball, scene.state());
      const Eigen::Vector3d w = rigid_body::angularVelocity(ball, scene.state());
      const double slip = (v + w.cross(Eigen::Vector3d(0, 0, -radius))).norm();
      if (rolling_from < 0.0 && slip <= 1e-9 * w0 * radius) rolling_from = static_cast<double>(i) * dt;
    }
    const double skid_end = 2.0 * w0 * radius / (7.0 * mu * kG);
    rows.claim("contact_spin_100_rad_s", type, "relative error of the time rolling begins",
               std::abs(rolling_from - skid_end) / skid_end, "<=", 1e-2);
    const double expected = 2.0 / 7.0 * w0 * radius;
    rows.invariant("contact_spin_100_rad_s", type, "relative error of the rolling speed (L about the contact point)",
                   std::abs(scene.state().P_W.norm() - expected) / expected, 1e-9);
  }
}

// Painlevé's case: a rod sliding on its lower end with friction μ = 2, more than the rigid model can take
// consistently (no solution, or two). The velocity-level solver always returns one: the end sticks by a
// tangential impulse (Stewart's "impact without collision"). Claimed: no energy is gained.
void painleve(CaseRows& rows) {
  const double r = 0.02, l = 1.0, m = 1.0, mu = 2.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-60.0 * kPi / 180.0, Eigen::Vector3d::UnitY()));  // 60° from vertical
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
  for (IntegratorType type : {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4}) {
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), mu)};
    setup.bodies = {shape(ShapeType::kCapsule, Eigen::Vector3d(r, l, 0), mu, 0.0)};
    const MassProperties rod = MassProperties::cylinder(m, r, l + 2.0 * r);
    rigid_body::Scene scene = makeScene({body(rod, Eigen::Vector3d(0, 0, 0.5 * l * std::abs(axis.z()) + r), q,
                                              Eigen::Vector3d(-3.0, 0, 0), Eigen::Vector3d::Zero(), kDown)},
                                        setup, type, 1e-3, ContactSettings());
    const auto energy = [&] {
      return rigid_body::kineticEnergy(rod, scene.state()) +
             rigid_body::potentialEnergy(rod, scene.model().forces, scene.state());
    };
    const double initial = energy();
    double gained = 0.0;
    for (int i = 0; i < 1000; ++i) {
      scene.step(1);
      gained = std::max(gained, energy() - initial);
    }
    rows.claim("contact_painleve", type, "largest energy gained [J]", gained, "<=", 1e-6 * initial);
    rows.report("contact_painleve", type, "speed after 1 s [m/s]", scene.state().P_W.norm() / m);
  }
}

// N bodies of mixed shapes dropped in a 2 m bin; semi-implicit Euler at 2 ms, as a game engine would run it.
void pile(CaseRows& rows, bool quick) {
  const std::size_t count = quick ? 100 : 1000;
  const double duration = quick ? 2.0 : 5.0, dt = 2e-3;
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
  for (int side = 0; side < 4; ++side) {
    CollisionShape wall = shape(ShapeType::kBox, side < 2 ? Eigen::Vector3d(0.1, 2.2, 3.0) : Eigen::Vector3d(2.0, 0.1, 3.0), 0.5, 0.0);
    wall.pose.translation() = side < 2 ? Eigen::Vector3d(side == 0 ? 1.05 : -1.05, 0, 1.5)
                                       : Eigen::Vector3d(0, side == 2 ? 1.05 : -1.05, 1.5);
    setup.environment.push_back(wall);
  }
  std::vector<BodyDefinition> bodies;
  double potential = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d p(-0.75 + 0.25 * static_cast<double>(i % 7), -0.75 + 0.25 * static_cast<double>((i / 7) % 7),
                            0.3 + 0.25 * static_cast<double>(i / 49));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3 * static_cast<double>(i % 5), Eigen::Vector3d(1, 1, 0).normalized()));
    switch (i % 3) {
      case 0:
        bodies.push_back(body(MassProperties::box(0.5, Eigen::Vector3d(0.15, 0.1, 0.08)), p, q, Eigen::Vector3d::Zero(),
                              Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kBox, Eigen::Vector3d(0.15, 0.1, 0.08), 0.5, 0.0));
        break;
      case 1:
        bodies.push_back(body(MassProperties::sphere(0.5, 0.06), p, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(0.06, 0, 0), 0.5, 0.0));
        break;
      default:
        bodies.push_back(body(MassProperties::cylinder(0.5, 0.05, 0.12), p, q, Eigen::Vector3d::Zero(),
                              Eigen::Vector3d::Zero(), kDown));
        setup.bodies.push_back(shape(ShapeType::kCylinder, Eigen::Vector3d(0.05, 0.12, 0), 0.5, 0.0));
    }
    potential += 0.5 * kG * p.z();
  }
  const IntegratorType type = IntegratorType::kSemiImplicitEuler;
  rigid_body::Scene scene = makeScene(bodies, setup, type, dt, ContactSettings());
  const double start = cpuSeconds();
  const std::int64_t steps = stepsFor(duration, dt);
  scene.step(steps);
  const double cpu = cpuSeconds() - start;
  double kinetic = 0.0;
  for (std::size_t i = 0; i < count; ++i) kinetic += rigid_body::kineticEnergy(scene.model(i).mass, scene.state(i));
  // The deepest penetration now: a fresh step at rest measures it (statistics since the start include the drop).
  const std::string name = "contact_pile_" + std::to_string(count);
  rows.claim(name, type, "kinetic energy at the end / potential energy at the start", kinetic / potential, "<=", 1e-2);
  rows.report(name, type, "deepest penetration during the drop [m]", scene.contactStatistics().max_penetration);
  rows.report(name, type, "CPU per body and step [us]", 1e6 * cpu / (static_cast<double>(steps) * count));
}

// A box resting on the ground for 10⁶ steps of 1 ms (10⁵ quick): no creep, no energy gained.
void longRest(CaseRows& rows, bool quick) {
  const std::int64_t steps = quick ? 100000 : 1000000;
  for (IntegratorType type : kMethods) {
    const Eigen::Vector3d size(0.4, 0.2, 0.1);
    ContactSetup setup;
    setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.5)};
    setup.bodies = {shape(ShapeType::kBox, size, 0.5, 0.0)};
    const MassProperties box = MassProperties::box(1.0, size);
    rigid_body::Scene scene = makeScene({body(box, Eigen::Vector3d(0, 0, 0.05), Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown)},
                                        setup, type, 1e-3, ContactSettings());
    const auto energy = [&] {
      return rigid_body::kineticEnergy(box, scene.state()) + rigid_body::potentialEnergy(box, scene.model().forces, scene.state());
    };
    const double initial = energy();
    scene.step(steps);
    rows.claim("contact_long_rest", type, "displacement [m]", (scene.state().p_WB - Eigen::Vector3d(0, 0, 0.05)).norm(),
               "<=", 1e-6);
    rows.claim("contact_long_rest", type, "energy gained [J]", energy() - initial, "<=", 1e-9);
  }
}

}  // namespace

std::vector<StabilityRow> runContactStability(bool quick) {
  CaseRows rows;
  stacks(rows, quick);
  massRatios(rows, quick);
  tunneling(rows);
  cradle(rows);
  frictionAngle(rows, quick);
  spinningBall(rows);
  painleve(rows);
  pile(rows, quick);
  longRest(rows, quick);
  return rows.take();
}

std::vector<std::pair<std::string, std::string>> contactCaseDescriptions(bool quick) {
  const std::string stack_time = quick ? "2 s" : "10 s";
  std::vector<std::pair<std::string, std::string>> cases;
  for (const char* height : {"10", "20", "50"}) {
    cases.push_back({std::string("contact_stack_") + height,
                     std::string("a stack of ") + height + " boxes (0.3 x 0.3 x 0.2 m, 1 kg, friction 0.5) on the ground, h = 1 ms, " +
                         stack_time + "; displacement of the top box claimed <= 1 cm for 10 and 20, reported for 50" +
                         "; reported: the largest slip at an interface (a box's bottom-face centre against the top-face "
                         "centre of the box below, horizontally)" +
                         (std::string(height) == "20" && !quick
                              ? "; also reported: the same stack from " + std::to_string(kPerturbedStarts) +
                                    " starts moved by k 1e-12 m (box i by k 1e-12 (i mod 3) along x, k = 1 ... " +
                                    std::to_string(kPerturbedStarts) + "), how far its top box goes then"
                              : "")});
  }
  const std::string ratio_time = quick ? "1 s" : "5 s";
  for (const char* name : {"contact_mass_ratio_100_heavy_on_light", "contact_mass_ratio_100_light_on_heavy",
                           "contact_mass_ratio_1000_heavy_on_light", "contact_mass_ratio_1000_light_on_heavy"}) {
    cases.push_back({name, "two boxes stacked on the ground with masses 1 and 100 (or 1000) kg, rk4, h = 1 ms, " + ratio_time +
                               "; claimed: penetration and displacement <= 1 mm (catches a solve that stops before the weight "
                               "has crossed the mass ratio)"});
  }
  for (const char* speed : {"10", "100", "1000"}) {
    cases.push_back({std::string("contact_tunneling_") + speed + "_m_s",
                     std::string("a sphere (r = 5 cm) shot at ") + speed +
                         " m/s down (and a fifth of that sideways) onto a 1 mm plate, h = 10 ms, from 8 start heights spread "
                         "over a step's travel: it must end on the plate (centre >= r - 1 mm above it) from every one "
                         "(catches a chord sweep on a curved path, a dropped touch, a remainder of a step passing the plate)"});
  }
  cases.push_back({"contact_cradle", "Newton's cradle: a ball at 1 m/s strikes four touching equal balls (e = 1, no friction), "
                                     "h = 1 ms, 0.5 s; claimed: the last ball leaves at 1 m/s, the rest at rest, to 1e-9 "
                                     "(catches an impact shared among the touching contacts at once)"});
  cases.push_back({"contact_friction_angle_0.98", std::string("a box on an incline at 0.98 of its friction angle (mu = 0.5), yawed 0.5 rad, ") +
                                                      (quick ? "1 s" : "5 s") + "; claimed: slides <= 0.1 mm (catches corners "
                                                      "whose friction saturates early in directions that cancel)"});
  cases.push_back({"contact_friction_angle", std::string("a box on an incline at exactly its friction angle (tan theta = mu = 0.5), ") +
                                                 (quick ? "1 s" : "5 s") + "; reported: the rigid Coulomb model is at its limit"});
  cases.push_back({"contact_spin_100_rad_s", "a sphere (r = 0.1 m) spun at 100 rad/s about a horizontal axis, set on the ground (mu = 0.5): it skids until 2 w0 r/(7 mu g) = 0.58 s (claimed to 1 %), then rolls at (2/7) w0 r (an invariant: L about the contact point); 1 s, every method"});
  cases.push_back({"contact_painleve", "Painleve's case: a capsule rod at 60 deg from the vertical, sliding at 3 m/s on its lower end with mu = 2 (the rigid model has no consistent solution); the solver sticks the end by a tangential impulse; claimed: no energy gained in 1 s"});
  cases.push_back({std::string("contact_pile_") + (quick ? "100" : "1000"),
                   std::string(quick ? "100" : "1000") + " boxes, spheres and cylinders dropped into a 2 m bin, semi-implicit Euler at 2 ms, " +
                       (quick ? "2 s" : "5 s") + "; claimed: settled (kinetic energy <= 1 % of the potential energy at the start); penetration and cost reported"});
  cases.push_back({"contact_long_rest", std::string("a box resting on the ground for ") + (quick ? "1e5" : "1e6") +
                                            " steps of 1 ms: displacement <= 1 um and no energy gained (<= 1e-9 J)"});
  return cases;
}

}  // namespace accuracy_report
