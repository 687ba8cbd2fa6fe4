// SimBenchmark's three contact scenes, set up as its benchmark/include/*Benchmark.hpp and
// benchmark/res/yaml/*.yaml do, measured by its own metrics (each a mean over the steps of a squared error,
// sampled before every step), and timed over the whole simulated run as its tables are.
#include "simbenchmark.hpp"

#include <fstream>
#include <random>

#include "contact_scene.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/number_format.hpp"

namespace accuracy_report {

namespace {

const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

struct Measured {
  double error;
  double cpu_seconds;
  double body_steps;
};

// Steps `scene` over `duration`, calling `sample()` (the squared error at this instant) before every step as
// SimBenchmark's loops do; the error is the mean of the samples. The CPU time counts the steps only.
template <class Sample>
Measured run(rigid_body::Scene& scene, double duration, const Sample& sample) {
  const std::int64_t steps = stepsFor(duration, scene.dt());
  double sum = 0.0, cpu = 0.0;
  for (std::int64_t i = 0; i < steps; ++i) {
    sum += sample();
    const double start = cpuSeconds();
    scene.step(1);
    cpu += cpuSeconds() - start;
  }
  return {sum / static_cast<double>(steps), cpu, static_cast<double>(steps) * static_cast<double>(scene.bodyCount())};
}

ContactSettings withIterations(int iterations) {
  ContactSettings settings;
  settings.iterations = iterations;
  return settings;
}

// Bouncing: 7 × 7 balls (r = 0.1 m, 10 kg) released from rest with their centres at H = 5 m, 2 m apart, on a
// plane, e = 1 and no friction, 20 s. Error: (E − n² m g H)², E the balls' total energy (kinetic plus m g z
// of the centre), the squared departure from the energy they start with.
Measured bouncing(IntegratorType type, double dt, int iterations, double duration) {
  const int n = 7;
  const double mass = 10.0, radius = 0.1, height = 5.0;
  ContactSetup setup;
  CollisionShape ground = plane(Eigen::Vector3d::UnitZ(), 0.0);
  ground.material.restitution = 1.0;
  setup.environment = {ground};
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      bodies.push_back(body(MassProperties::sphere(mass, radius), Eigen::Vector3d(2.0 * i - 10.0, 2.0 * j - 10.0, height),
                            Eigen::Quaterniond::Identity(), kZero, kZero, kDown));
      setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 1.0));
    }
  }
  rigid_body::Scene scene = makeScene(bodies, setup, type, dt, withIterations(iterations));
  const double expected = n * n * mass * kG * height;
  return run(scene, duration, [&] {
    double energy = 0.0;
    for (std::size_t b = 0; b < scene.bodyCount(); ++b) {
      energy += rigid_body::kineticEnergy(scene.model(b).mass, scene.state(b)) + mass * kG * scene.state(b).p_WB.z();
    }
    return (energy - expected) * (energy - expected);
  });
}

// Rolling: a 20 × 20 × 1 m box of 10 kg on a plane (friction 0.4) carrying 5 × 5 balls (r = 0.5 m, 1 kg,
// friction 0.8 against the box), pushed by 150 N along (1/2, √3/2, 0), diagonal to the box's axes, 4 s.
// SimBenchmark's coefficients combine by product (ground 0.5, box 0.8, ball 1.0); here they combine by the
// geometric mean, so the materials are 0.2, 0.8, 0.8 for the same pairs. Its closed form (docs/references.md
// §4.11): the box slides with a₁ = (F − f₁ − n f₂)/M, f₁ = μ₁ (M + n m) g, and each ball rolls without slip on
// it, f₂ = (F − f₁)/(3.5 M/m + n), a₂ = f₂/m. Error: |v_box − a₁ t|² + |v_ball − a₂ t|² (the first ball).
Measured rolling(IntegratorType type, double dt, int iterations, double duration) {
  const int n = 5;
  const double box_mass = 10.0, ball_mass = 1.0, radius = 0.5, force = 150.0, penetration = 5e-6;
  const Eigen::Vector3d box_size(20.0, 20.0, 1.0), direction(0.5, std::sqrt(3.0) / 2.0, 0.0);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.2)};
  std::vector<BodyDefinition> bodies = {body(MassProperties::box(box_mass, box_size), Eigen::Vector3d(0, 0, 0.5 - penetration),
                                             Eigen::Quaterniond::Identity(), kZero, kZero, kDown)};
  bodies.front().takes_input = true;
  setup.bodies = {shape(ShapeType::kBox, box_size, 0.8, 0.0)};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      bodies.push_back(body(MassProperties::sphere(ball_mass, radius),
                            Eigen::Vector3d(2.0 * i - 4.0, 2.0 * j - 4.0, 1.5 - 3.0 * penetration),
                            Eigen::Quaterniond::Identity(), kZero, kZero, kDown));
      setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.8, 0.0));
    }
  }
  rigid_body::Scene scene = makeScene(bodies, setup, type, dt, withIterations(iterations));
  rigid_body::AppliedWrench push;
  push.world.force = force * direction;
  scene.setInput(0, push);
  const double balls = n * n, f1 = 0.4 * (box_mass + balls * ball_mass) * kG;
  const double f2 = (force - f1) / (3.5 * box_mass / ball_mass + balls);
  const double a_box = (force - f1 - balls * f2) / box_mass, a_ball = f2 / ball_mass;
  std::int64_t step = 0;
  return run(scene, duration, [&] {
    const double t = static_cast<double>(step++) * dt;
    const Eigen::Vector3d v_box = rigid_body::linearVelocity(scene.model(0).mass, scene.state(0));
    const Eigen::Vector3d v_ball = rigid_body::linearVelocity(scene.model(1).mass, scene.state(1));
    return (v_box - a_box * t * direction).squaredNorm() + (v_ball - a_ball * t * direction).squaredNorm();
  });
}

// 666: 6 × 6 × 6 balls (r = 0.1 m, 10 kg) on a grid 0.21 m apart, each moved by up to 1 mm (uniform, seeded)
// along every axis, the lowest layer's centres at 1.101 m, dropped on a plane, no friction, no restitution,
// 10 s. Error: the sum of the squared penetrations, ball–ball (2r − distance of centres) and ball–ground
// (r − z). SimBenchmark seeds its own generator with 42; this one seeds std::mt19937 with 42, so the
// perturbation differs in its draws, not in its distribution.
Measured pile666(IntegratorType type, double dt, int iterations, double duration, int n) {
  const double mass = 10.0, radius = 0.1, gap = 0.21, perturbation = 1e-3, height = 1.101;
  std::mt19937 random(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  ContactSetup setup;
  setup.environment = {plane(Eigen::Vector3d::UnitZ(), 0.0)};
  std::vector<BodyDefinition> bodies;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const double x = i * gap + unit(random) * perturbation - 0.6;
        const double y = j * gap + unit(random) * perturbation;
        const double z = k * gap + unit(random) * perturbation + height;
        bodies.push_back(body(MassProperties::sphere(mass, radius), Eigen::Vector3d(x, y, z),
                              Eigen::Quaterniond::Identity(), kZero, kZero, kDown));
        setup.bodies.push_back(shape(ShapeType::kSphere, Eigen::Vector3d(radius, 0, 0), 0.0, 0.0));
      }
    }
  }
  rigid_body::Scene scene = makeScene(bodies, setup, type, dt, withIterations(iterations));
  return run(scene, duration, [&] {
    double error = 0.0;
    for (std::size_t a = 0; a < scene.bodyCount(); ++a) {
      const Eigen::Vector3d& p = scene.state(a).p_WB;
      for (std::size_t b = a + 1; b < scene.bodyCount(); ++b) {
        const double depth = 2.0 * radius - (p - scene.state(b).p_WB).norm();
        if (depth > 0.0) error += depth * depth;
      }
      if (p.z() < radius) error += (radius - p.z()) * (radius - p.z());
    }
    return error;
  });
}

SimBenchmarkRow row(const std::string& scene, IntegratorType type, double dt, int iterations, const Measured& m) {
  return {scene, rigid_body::integratorName(type), dt, iterations, m.error, m.cpu_seconds, m.cpu_seconds / m.body_steps};
}

}  // namespace

std::vector<SimBenchmarkRow> runSimBenchmark(const Options& options) {
  // SimBenchmark sweeps the step for bouncing and 666 and the solver's iterations at h = 1 ms for rolling;
  // --quick keeps one short run of each (the scenes' durations cut to what the test can afford).
  const bool quick = options.quick;
  const std::vector<double> steps = quick ? std::vector<double>{1e-3} : std::vector<double>{1e-2, 4e-3, 1e-3, 4e-4};
  const std::vector<int> iterations = quick ? std::vector<int>{20} : std::vector<int>{10, 20, 40, 100, 400};
  const std::vector<IntegratorType> methods = {IntegratorType::kSemiImplicitEuler, IntegratorType::kRk4};
  std::vector<SimBenchmarkRow> rows;
  for (IntegratorType type : methods) {
    for (double dt : steps) rows.push_back(row("bouncing", type, dt, 20, bouncing(type, dt, 20, quick ? 2.0 : 20.0)));
    for (int count : iterations) rows.push_back(row("rolling", type, 1e-3, count, rolling(type, 1e-3, count, quick ? 0.5 : 4.0)));
    for (double dt : steps) {
      if (dt < 1e-3 && type == IntegratorType::kRk4) continue;  // the finest step for one method only: its cost
      rows.push_back(row("666", type, dt, 20, pile666(type, dt, 20, quick ? 1.0 : 10.0, quick ? 3 : 6)));
    }
  }
  std::ofstream csv(options.out + "/simbenchmark.csv");
  csv << "scene,integrator,dt,iterations,error,cpu_seconds,cpu_per_body_step\n";
  csv.precision(17);
  for (const SimBenchmarkRow& r : rows) {
    csv << r.scene << "," << r.integrator << "," << r.dt << "," << r.iterations << "," << r.error << "," << r.cpu_seconds
        << "," << r.cpu_per_body_step << "\n";
  }
  return rows;
}

namespace {

// SimBenchmark's published rows at h = 1 ms (its data/bouncing, data/rolling and data/666 sample.csv: its
// machine, its runs; rolling with the force diagonal and 40 solver iterations, all without error reduction).
struct PublishedRow {
  const char* scene;
  const char* engine;
  double error;
  double cpu_seconds;
};
const PublishedRow kPublished[] = {
    {"bouncing", "RaiSim", 0.0186204, 0.235},  {"bouncing", "ODE (quick)", 185.027, 1.89},
    {"bouncing", "Bullet (multibody)", 75245.4, 0.852}, {"bouncing", "DART (Dantzig)", 72274.4, 3.21},
    {"rolling", "RaiSim", 4.08978e-07, 0.486},  {"rolling", "Bullet (multibody)", 4.42287e-15, 0.910},
    {"rolling", "ODE (quick)", 3.14497, 1.22},  {"666", "RaiSim", 1.3534e-4, 1.51},
    {"666", "ODE (standard)", 1.54633e-4, 10.6}, {"666", "DART (Dantzig)", 2.82356e-4, 22.9},
    {"666", "MuJoCo (PGS, Euler)", 0.0950087, 13.2}, {"666", "Bullet (multibody)", 0.38247, 12.0},
};

const char* metricOf(const std::string& scene) {
  if (scene == "bouncing") return "mean (E - E0)^2 [J^2], 49 balls, 20 s";
  if (scene == "rolling") return "mean squared velocity error of box and ball [m^2/s^2], 4 s";
  return "mean sum of squared penetrations [m^2], 216 balls, 10 s";
}

std::string fmt(double value) { return rigid_body::formatNumber(value, 3); }

}  // namespace

void writeSimBenchmarkSection(std::ostream& md, const std::vector<SimBenchmarkRow>& rows, bool quick) {
  md << "\n## SimBenchmark's scenes\n\n"
        "SimBenchmark (leggedrobotics/SimBenchmark) compares RaiSim, Bullet, ODE, MuJoCo and DART on contact "
        "scenes with one metric each; the package runs three of them with the same set-up and the same metric "
        "(src/accuracy_report/simbenchmark.cpp, docs/report.md): **bouncing** (7 x 7 balls dropped from 5 m, "
        "e = 1, no friction: energy error), **rolling** (a box pushed by 150 N diagonally, carrying 5 x 5 balls "
        "that roll on it: velocity error against the closed form) and **666** (6 x 6 x 6 balls dropped in a "
        "block: penetration). CPU seconds are for the whole simulated run, as SimBenchmark publishes them; "
        "its numbers are from its own machine and runs, so compare errors directly and times only as orders.\n\n";
  if (quick) md << "This is a quick run: each scene shortened (bouncing 2 s, rolling 0.5 s, 666 with 3 x 3 x 3 balls for 1 s).\n\n";
  md << "| scene | metric | engine | h [s] | iterations | error | CPU [s] | CPU per body-step [us] |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const SimBenchmarkRow& r : rows) {
    md << "| " << r.scene << " | " << metricOf(r.scene) << " | rigid_body_sim, " << r.integrator << " | " << fmt(r.dt)
       << " | " << r.iterations << " | " << fmt(r.error) << " | " << fmt(r.cpu_seconds) << " | "
       << fmt(1e6 * r.cpu_per_body_step) << " |\n";
  }
  for (const PublishedRow& p : kPublished) {
    md << "| " << p.scene << " | " << metricOf(p.scene) << " | " << p.engine << " (published) | 0.001 | "
       << (std::string(p.scene) == "rolling" ? "40" : "") << " | " << fmt(p.error) << " | " << fmt(p.cpu_seconds)
       << " | |\n";
  }
}

}  // namespace accuracy_report
