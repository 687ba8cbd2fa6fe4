// Runs `accuracy_report --quick` into a temporary folder and holds its numbers to their promises: the files
// exist and parse, the fitted orders are the nominal ones, rk4 beats explicit Euler by orders of magnitude
// at equal h, and every threshold a method claims in the stiff and extreme suite is met.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Splits one CSV line; a field in double quotes may hold commas.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.push_back(field);
      field.clear();
    } else {
      field += c;
    }
  }
  out.push_back(field);
  return out;
}

// Rows as maps from the header's column names.
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::map<std::string, std::string>> rows;
  std::string line;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = fields(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> values = fields(line);
    if (values.size() != header.size()) {
      ADD_FAILURE() << path << ": a row with " << values.size() << " fields: " << line;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size(); ++i) row[header[i]] = values[i];
    rows.push_back(row);
  }
  return rows;
}

bool exists(const std::string& path) { return std::ifstream(path).good(); }

class AccuracyReport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char pattern[] = "/tmp/accuracy_report_test_XXXXXX";
    directory_ = mkdtemp(pattern);
    const std::string command = std::string(ACCURACY_REPORT_PATH) + " --quick --out " + directory_ + " 2>&1";
    exit_code_ = std::system(command.c_str());
  }
  static void TearDownTestSuite() { std::system(("rm -rf " + directory_).c_str()); }
  static std::string file(const std::string& name) { return directory_ + "/" + name; }

  static std::string directory_;
  static int exit_code_;
};

std::string AccuracyReport::directory_;
int AccuracyReport::exit_code_ = -1;

}  // namespace

TEST_F(AccuracyReport, WritesEveryFile) {
  ASSERT_EQ(exit_code_, 0);
  for (const char* name : {"REPORT.md", "work_precision.csv", "order.csv", "control_rate.csv", "error_growth.csv",
                           "stability.csv", "contact.csv", "simbenchmark.csv"}) {
    EXPECT_TRUE(exists(file(name))) << name;
  }
  // Figures when gnuplot is there (scripts/test.sh installs it).
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    for (const char* name : {"order.png", "control_rate.png", "error_growth.png", "work_precision_dzhanibekov.png",
                             "work_precision_asymmetric.png", "work_precision_ballistic.png", "contact_bounce.png"}) {
      EXPECT_TRUE(exists(file(name))) << name;
    }
  }
  std::ifstream report(file("REPORT.md"));
  const std::string text((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("## Which integrator when"), std::string::npos);
  EXPECT_NE(text.find("## Stiff and extreme suite"), std::string::npos);
}

TEST_F(AccuracyReport, FittedOrdersAreTheNominalOrders) {
  const auto rows = readCsv(file("order.csv"));
  ASSERT_FALSE(rows.empty());
  std::map<std::string, bool> seen;
  for (const auto& row : rows) {
    EXPECT_NEAR(std::stod(row.at("fitted_order")), std::stod(row.at("nominal_order")), 0.3) << row.at("integrator");
    seen[row.at("integrator")] = true;
  }
  EXPECT_EQ(seen.size(), 7u);  // every fixed-step method
}

TEST_F(AccuracyReport, Rk4BeatsExplicitEulerByOrdersOfMagnitudeAtEqualStep) {
  std::map<std::string, std::map<std::string, double>> error;  // [scene/h][integrator]
  for (const auto& row : readCsv(file("work_precision.csv"))) {
    error[row.at("scene") + "@" + row.at("h")][row.at("integrator")] = std::stod(row.at("error"));
  }
  int compared = 0;
  for (const char* scene : {"asymmetric", "symmetric_top", "dzhanibekov", "off_centre_push"}) {
    for (const char* h : {"0.005", "0.001"}) {
      const auto& at = error[std::string(scene) + "@" + h];
      ASSERT_TRUE(at.count("rk4") && at.count("explicit_euler")) << scene << " " << h;
      EXPECT_LT(at.at("rk4"), 1e-3 * at.at("explicit_euler")) << scene << " h = " << h;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 8);
}

TEST_F(AccuracyReport, BallisticErrorsAreTheClosedFormsDiscreteSignatures) {
  // Absolute accuracy on a closed form (docs/references.md §2.4), for every h of the sweep: the 2 kg box thrown
  // under g = 9.81 m/s² for T = 5 s. Explicit and semi-implicit Euler miss x(T) by exactly g h T/2 (their
  // discrete solutions x_n = x(t_n) ∓ F h t_n/(2m)); every method of order >= 2 is exact but for rounding.
  int checked = 0;
  for (const auto& row : readCsv(file("work_precision.csv"))) {
    if (row.at("scene") != "ballistic") continue;
    const std::string& method = row.at("integrator");
    const double h = std::stod(row.at("h")), error = std::stod(row.at("error"));
    if (method == "explicit_euler" || method == "semi_implicit_euler") {
      EXPECT_NEAR(error, 9.81 * h * 5.0 / 2.0, 1e-9 * (1.0 + 9.81 * h * 5.0)) << method << " h = " << h;
    } else {
      EXPECT_LT(error, 1e-9) << method << " h = " << h;
    }
    ++checked;
  }
  EXPECT_GE(checked, 28);  // 4 steps (quick) × 7 fixed-step methods, and dopri5's tolerances
}

// The verdict of `value` against a threshold written "<= X", ">= X" or "= X", recomputed here rather than read from
// the report's own pass column.
bool meets(double value, const std::string& threshold) {
  std::istringstream in(threshold);
  std::string op;
  double bound = 0.0;
  in >> op >> bound;
  EXPECT_TRUE(in && (op == "<=" || op == ">=" || op == "=")) << "unreadable threshold '" << threshold << "'";
  return op == "<=" ? value <= bound : op == ">=" ? value >= bound : value == bound;
}

// Contact: a located impact keeps rk4's free flight exact (the bounce heights to rounding), while an impact
// resolved at the end of its step is O(h) off; and every closed-form contact scene was run.
TEST_F(AccuracyReport, ContactSectionShowsWhatEventLocationBuys) {
  const auto rows = readCsv(file("contact.csv"));
  ASSERT_FALSE(rows.empty());
  std::set<std::string> scenes;
  double located = -1.0, at_step_end = -1.0;
  for (const auto& row : rows) {
    scenes.insert(row.at("scene"));
    if (row.at("scene") != "bounce" || row.at("integrator") != "rk4" || std::stod(row.at("dt")) != 1e-3) continue;
    if (row.at("setting") == "located, 20 iterations") located = std::stod(row.at("error"));
    if (row.at("setting") == "at step end, 20 iterations") at_step_end = std::stod(row.at("error"));
    EXPECT_GT(std::stod(row.at("cpu_per_simulated_second")), 0.0);
  }
  EXPECT_EQ(scenes, (std::set<std::string>{"bounce", "slide", "incline_slide", "rolling", "head_on", "rod_impact"}));
  ASSERT_GE(located, 0.0);
  ASSERT_GE(at_step_end, 0.0);
  EXPECT_LE(located, 1e-6);
  EXPECT_GE(at_step_end, 1e-4);  // the impact up to a step late: the rebound speed off by about g h
  std::ifstream markdown(file("REPORT.md"));
  const std::string text((std::istreambuf_iterator<char>(markdown)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("### Which contact settings when"), std::string::npos);
}

// SimBenchmark's scenes (docs/report.md). Bouncing: rk4 integrates free flight (a quadratic in t) exactly and
// a located impact with e = 1 and no friction keeps the speed, so the 49 balls' energy E0 = 49 m g H may
// drift by rounding only: the mean squared error is held to (1e-9 E0)². Rolling: the issue's rolling bound,
// 1 % of the closed form, on the box's final speed a₁ T (references.md §4.11), squared, bounds the mean of
// the squared errors of box and ball. 666 is reported only (its penetration is the solver's slop).
TEST_F(AccuracyReport, SimBenchmarkScenesKeepEnergyAndRoll) {
  const auto rows = readCsv(file("simbenchmark.csv"));
  std::set<std::string> scenes;
  for (const auto& row : rows) {
    scenes.insert(row.at("scene"));
    EXPECT_GT(std::stod(row.at("cpu_seconds")), 0.0);
    if (row.at("integrator") != "rk4") continue;
    const double error = std::stod(row.at("error"));
    if (row.at("scene") == "bouncing") {
      const double energy = 49 * 10.0 * 9.81 * 5.0;
      EXPECT_LE(error, std::pow(1e-9 * energy, 2)) << "h " << row.at("dt");
    } else if (row.at("scene") == "rolling") {
      const double f1 = 0.4 * 35.0 * 9.81, f2 = (150.0 - f1) / 60.0, a_box = 3.5 * f2, duration = 0.5;  // quick
      EXPECT_LE(error, std::pow(0.01 * a_box * duration, 2)) << row.at("iterations") << " iterations";
    }
  }
  EXPECT_EQ(scenes, (std::set<std::string>{"bouncing", "rolling", "666"}));
}

TEST_F(AccuracyReport, EveryClaimedThresholdIsMet) {
  const auto rows = readCsv(file("stability.csv"));
  ASSERT_FALSE(rows.empty());
  int claims = 0;
  std::map<std::string, bool> cases;
  for (const auto& row : rows) {
    cases[row.at("case")] = true;
    if (row.at("threshold").empty()) continue;
    const bool verdict = meets(std::stod(row.at("value")), row.at("threshold"));
    const std::string what = row.at("case") + " / " + row.at("integrator") + " / " + row.at("metric") + " = " +
                             row.at("value") + " (" + row.at("threshold") + ")";
    EXPECT_EQ(row.at("pass"), verdict ? "yes" : "no") << "the report's own verdict is wrong: " << what;
    if (row.at("invariant") == "yes") {
      EXPECT_TRUE(verdict) << "invariant broken: " << what;
      continue;  // kept by construction: not an accuracy claim
    }
    if (row.at("claimed") != "yes") continue;
    ++claims;
    EXPECT_TRUE(verdict) << what;
  }
  EXPECT_GT(claims, 0);
  for (const char* name : {"thin_rod", "thin_rod_1e-4", "high_spin", "dzhanibekov_130s", "near_zero_omega",
                           "scale_1e-9_1e9", "large_step_1s", "stiff_damping", "long_run", "contact_stack_10",
                           "contact_tunneling_1000_m_s", "contact_spin_100_rad_s", "contact_painleve",
                           "contact_long_rest"}) {
    EXPECT_TRUE(cases.count(name)) << name;
  }
}

// The claims can fail: with a lower-order method run in a method's place (--substitute CLAIMED:RUN), some
// claim of CLAIMED must fail, by the verdict recomputed here. First-order methods have no lower-order method
// to stand in for them; their order claim is the one a frozen (order 0) update would fail.
class Mutation : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(Mutation, ALowerOrderMethodInAMethodsPlaceFailsItsClaims) {
  const std::string claimed = GetParam().first, run = GetParam().second;
  char pattern[] = "/tmp/accuracy_report_mutation_XXXXXX";
  const std::string directory = mkdtemp(pattern);
  const std::string command = std::string(ACCURACY_REPORT_PATH) + " --quick --only-stability --substitute " + claimed +
                              ":" + run + " --out " + directory + " 2>/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  int claims = 0, failed = 0;
  for (const auto& row : readCsv(directory + "/stability.csv")) {
    if (row.at("integrator") != claimed || row.at("claimed") != "yes" || row.at("invariant") == "yes" ||
        row.at("threshold").empty()) {
      continue;
    }
    ++claims;
    if (!meets(std::stod(row.at("value")), row.at("threshold"))) ++failed;
  }
  std::system(("rm -rf " + directory).c_str());
  EXPECT_GT(claims, 0) << claimed << " claims nothing";
  EXPECT_GT(failed, 0) << claimed << "'s " << claims << " claims all held with " << run << " in its place";
}

INSTANTIATE_TEST_SUITE_P(
    LowerOrderStandIns, Mutation,
    ::testing::Values(std::make_pair("rk4", "symplectic_splitting"), std::make_pair("rkmk4", "buss"),
                      std::make_pair("buss", "explicit_euler"), std::make_pair("symplectic_splitting", "semi_implicit_euler"),
                      std::make_pair("implicit_midpoint", "explicit_euler"), std::make_pair("dopri5", "rk4")),
    [](const ::testing::TestParamInfo<std::pair<const char*, const char*>>& info) {
      return std::string(info.param.first) + "_as_" + info.param.second;
    });

TEST_F(AccuracyReport, ErrorGrowthCoversEveryIntegrator) {
  std::map<std::string, int> samples;
  for (const auto& row : readCsv(file("error_growth.csv"))) ++samples[row.at("integrator")];
  EXPECT_EQ(samples.size(), 8u);
  for (const auto& entry : samples) EXPECT_GE(entry.second, 900) << entry.first;
}
