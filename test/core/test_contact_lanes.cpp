// The resting solve in vector lanes (docs/contact.md, "The solver's lanes"): the colouring never puts two
// manifolds that share a body in one colour and sweeps every contact once; four and eight lanes give the
// bits of one lane, with and without the wide instructions, whatever islands share a block; and the readable solver
// swept over the same contacts in the same order gets the same impulses to rounding.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include "../../src/contact/contact_lanes.hpp"
#include "../../src/contact/solver_islands.hpp"
#include "rigid_body_sim/mass_properties.hpp"

using namespace rigid_body;
using namespace rigid_body::contact;

namespace {

constexpr double kH = 1e-3;
const Eigen::Vector3d kBox(0.3, 0.3, 0.2);

// Solver lists built island by island: each island's bodies follow each other, and so do its contacts.
struct Lists {
  std::vector<SolverBody> bodies{environmentBody()};
  std::vector<SolverContact> contacts;
  std::vector<std::size_t> body_start;  // per island, then the end
  std::mt19937 random{7};

  std::size_t addBody(double mass, const Eigen::Matrix3d& inverse_inertia) {
    std::uniform_real_distribution<double> speed(-0.05, 0.05);
    SolverBody body;
    body.inverse_mass = 1.0 / mass;
    body.inverse_inertia_W = inverse_inertia;
    body.v = Eigen::Vector3d(speed(random), speed(random), -9.81 * kH + speed(random));
    body.w = Eigen::Vector3d(speed(random), speed(random), speed(random)) * 4.0;
    bodies.push_back(body);
    return bodies.size() - 1;
  }
  // Four corners of a box's lower face on `below` (a box or the environment), offset (dx, dy) from its
  // centre, the tangent basis turned by `yaw` (slip diagonal to it).
  void corners(std::size_t self, std::size_t below, double dx, double dy, double yaw, double friction) {
    for (const double x : {-0.15, 0.15}) {
      for (const double y : {-0.15, 0.15}) {
        SolverContact c;
        c.a = self, c.b = below;
        c.r_a = Eigen::Vector3d(x, y, -0.1);
        if (below != kEnvironment) c.r_b = Eigen::Vector3d(x + dx, y + dy, 0.1);
        c.n = Eigen::Vector3d::UnitZ();
        c.t1 = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0), c.t2 = c.n.cross(c.t1);
        c.separation = -2e-5;
        c.friction = friction;
        c.sustained = true;
        contacts.push_back(c);
      }
    }
  }
  void startIsland() { body_start.push_back(bodies.size()); }
  void finish() { body_start.push_back(bodies.size()); }

  std::vector<std::pair<std::size_t, std::size_t>> links() const {
    std::vector<std::pair<std::size_t, std::size_t>> out;
    const std::size_t environment = bodies.size();
    for (const SolverContact& c : contacts) out.emplace_back(c.a - 1, c.b == kEnvironment ? environment : c.b - 1);
    return out;
  }
};

// Islands of every kind in one list: stacks of 1 to 7 boxes (interfaces turned and shifted), a box bridging
// two (two manifolds on one body), a 50:1 heavy box on a light one (far from converged in a few sweeps),
// fast sliders whose friction is on the disc's edge, and a plate under 70 balls (more manifolds on one body
// than there are colours: the overflow).
Lists mixedIslands() {
  Lists lists;
  const Eigen::Matrix3d box_inertia = MassProperties::box(1.0, kBox).inverseInertia();
  for (int height = 1; height <= 7; ++height) {
    lists.startIsland();
    std::size_t below = kEnvironment;
    for (int i = 0; i < height; ++i) {
      const std::size_t self = lists.addBody(1.0, box_inertia);
      lists.corners(self, below, 0.01 * i, -0.007 * i, 0.3 * i, 0.5);
      below = self;
    }
  }
  lists.startIsland();  // the bridge
  const std::size_t left = lists.addBody(1.0, box_inertia), right = lists.addBody(1.0, box_inertia);
  lists.corners(left, kEnvironment, 0, 0, 0, 0.6);
  lists.corners(right, kEnvironment, 0, 0, 0, 0.6);
  const std::size_t bridge = lists.addBody(2.0, MassProperties::box(2.0, kBox).inverseInertia());
  lists.corners(bridge, left, 0.15, 0.0, 0.0, 0.6);
  lists.corners(bridge, right, -0.15, 0.0, 0.0, 0.6);
  lists.startIsland();  // heavy on light
  const std::size_t light = lists.addBody(1.0, box_inertia);
  lists.corners(light, kEnvironment, 0, 0, 0, 0.4);
  lists.corners(lists.addBody(50.0, MassProperties::box(50.0, kBox).inverseInertia()), light, 0.03, 0, 0, 0.4);
  for (int i = 0; i < 3; ++i) {  // sliders: 2 m/s along a diagonal of the tangent basis
    lists.startIsland();
    const std::size_t self = lists.addBody(1.0, box_inertia);
    lists.bodies[self].v += Eigen::Vector3d(1.4, 1.4, 0.0);
    lists.corners(self, kEnvironment, 0, 0, 0.1 * i, 0.3);
  }
  lists.startIsland();  // the plate and its balls
  const std::size_t plate = lists.addBody(20.0, MassProperties::box(20.0, Eigen::Vector3d(3, 3, 0.2)).inverseInertia());
  lists.corners(plate, kEnvironment, 0, 0, 0, 0.5);
  const Eigen::Matrix3d ball_inertia = MassProperties::sphere(0.1, 0.02).inverseInertia();
  for (int i = 0; i < 70; ++i) {
    const std::size_t ball = lists.addBody(0.1, ball_inertia);
    SolverContact c;
    c.a = ball, c.b = plate;
    c.r_a = Eigen::Vector3d(0, 0, -0.02);
    c.r_b = Eigen::Vector3d(-1.4 + 0.04 * i, 0.3 * std::sin(i), 0.1);
    c.n = Eigen::Vector3d::UnitZ(), c.t1 = Eigen::Vector3d::UnitX(), c.t2 = Eigen::Vector3d::UnitY();
    c.separation = -1e-5;
    c.friction = 0.5;
    c.sustained = true;
    lists.contacts.push_back(c);
  }
  lists.finish();
  return lists;
}

RestingSolveSettings sweeps(int iterations) {
  RestingSolveSettings settings;
  settings.options.iterations = iterations;
  settings.options.dt = kH;
  settings.move_weight = 0.5 * kH;
  return settings;
}

bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}

TEST(ContactLanes, NoColourHasTwoManifoldsOnOneBodyAndEveryContactIsSweptOnce) {
  const Lists lists = mixedIslands();
  std::vector<SolveRange> islands;
  std::size_t contact = 0;
  for (std::size_t i = 0; i + 1 < lists.body_start.size(); ++i) {
    SolveRange range{contact, contact, lists.body_start[i], lists.body_start[i + 1]};
    while (contact < lists.contacts.size() && lists.contacts[contact].a < range.body_end) ++contact;
    range.contact_end = contact;
    islands.push_back(range);
  }
  ASSERT_EQ(contact, lists.contacts.size());
  ManifoldColouring colouring;
  colouring.colour(lists.contacts, islands.data(), islands.size(), lists.bodies.size());
  std::vector<int> swept(lists.contacts.size(), 0);
  for (std::size_t colour = 0; colour <= ManifoldColouring::kColours; ++colour) {
    std::set<std::size_t> used;
    std::size_t last_first = 0;
    for (std::size_t m = colouring.colourStart(colour); m < colouring.colourStart(colour + 1); ++m) {
      const Manifold& manifold = colouring.manifolds()[m];
      ASSERT_GE(manifold.count, 1u);
      ASSERT_LE(manifold.count, kMaxManifoldPoints);
      EXPECT_TRUE(m == colouring.colourStart(colour) || manifold.first > last_first);  // the lists' order
      last_first = manifold.first;
      const SolverContact& first = lists.contacts[manifold.first];
      for (std::size_t p = 0; p < manifold.count; ++p) {
        const SolverContact& c = lists.contacts[manifold.first + p];
        EXPECT_TRUE(c.a == first.a && c.b == first.b);
        ++swept[manifold.first + p];
        const SolveRange& island = islands[manifold.island];
        EXPECT_TRUE(manifold.first + p >= island.contact_begin && manifold.first + p < island.contact_end);
      }
      if (colour == ManifoldColouring::kColours) continue;  // the overflow is swept one manifold at a time
      for (const std::size_t body : {first.a, first.b}) {
        if (body == kEnvironment) continue;
        EXPECT_TRUE(used.insert(body).second) << "colour " << colour << " has body " << body << " twice";
      }
    }
  }
  for (std::size_t k = 0; k < swept.size(); ++k) EXPECT_EQ(swept[k], 1) << k;
  // The plate's 71 manifolds (its four ground points, one manifold; a point under each of 70 balls) take
  // all 64 colours, and the last 7 overflow.
  EXPECT_EQ(colouring.colourStart(ManifoldColouring::kColours + 1) - colouring.colourStart(ManifoldColouring::kColours),
            71u - 64u);
}

// Solves the mixed islands with the given lanes; returns the lists afterwards.
Lists solvedInLanes(std::size_t lanes, bool wide, int iterations) {
  Lists lists = mixedIslands();
  SolverIslands islands;
  islands.group(lists.links(), lists.bodies.size() - 1);
  std::vector<std::size_t> identity(lists.contacts.size());
  for (std::size_t k = 0; k < identity.size(); ++k) identity[k] = k;
  EXPECT_EQ(islands.order(), identity);
  EXPECT_EQ(islands.islands(), lists.body_start.size() - 1);
  RestingSolveSettings settings = sweeps(iterations);
  settings.lanes.lanes = lanes;
  settings.lanes.wide_instructions = wide;
  islands.solve(lists.contacts, lists.bodies, lists.body_start, settings, nullptr);
  return lists;
}

TEST(ContactLanes, FourAndEightLanesGiveTheBitsOfOneWithAndWithoutWideInstructions) {
  for (const int iterations : {3, 20}) {  // islands stopped unconverged; and most converged, some not
    const Lists one = solvedInLanes(1, false, iterations);
    bool some_on_the_disc = false;
    // 0: the width this CPU runs best (bestLaneCount), what a scene uses.
    for (const auto& [lanes, wide] : {std::pair<std::size_t, bool>{4, false}, {4, true}, {8, false}, {8, true}, {0, true}}) {
      const Lists other = solvedInLanes(lanes, wide, iterations);
      for (std::size_t s = 0; s < one.bodies.size(); ++s) {
        for (Eigen::Vector3d SolverBody::*field : {&SolverBody::v, &SolverBody::w, &SolverBody::dP, &SolverBody::dL,
                                                   &SolverBody::dx, &SolverBody::dtheta}) {
          EXPECT_TRUE(sameBits(one.bodies[s].*field, other.bodies[s].*field))
              << "body " << s << ", " << lanes << " lanes, wide " << wide;
        }
      }
      for (std::size_t k = 0; k < one.contacts.size(); ++k) {
        const SolverContact &a = one.contacts[k], &b = other.contacts[k];
        EXPECT_TRUE(a.normal_impulse == b.normal_impulse && a.friction_impulse == b.friction_impulse &&
                    a.slip_squared == b.slip_squared)
            << "contact " << k << ", " << lanes << " lanes, wide " << wide;
        some_on_the_disc = some_on_the_disc || (a.friction_impulse.norm() > (1.0 - 1e-9) * a.friction * a.normal_impulse &&
                                                a.normal_impulse > 0.0);
      }
    }
    EXPECT_TRUE(some_on_the_disc);  // the sliders' friction went through the disc's projection
  }
}

TEST(ContactLanes, TheReadableSolverInTheSweepOrderGetsTheSameImpulsesToRounding) {
  const Lists original = mixedIslands();
  Lists lanes = original;
  SolveRange all = SolveRange::all(lanes.contacts.size(), lanes.bodies.size());
  all.body_begin = 1;  // the environment is no island's
  SolveOptions options = sweeps(6).options;
  options.sweep_budget_contacts = 1;  // exactly 6 sweeps unless converged
  prepareContacts(lanes.contacts, lanes.bodies, options, all);
  LaneContactSolver solver;
  char converged = 0;
  solver.solve(lanes.contacts, lanes.bodies, options, &all, 1, &converged, LaneSettings());
  ASSERT_FALSE(converged);
  // The same contacts in the order the lanes swept them, prepared and swept by the readable loop.
  const std::vector<std::size_t> order = solver.sweepOrder();
  ASSERT_EQ(order.size(), original.contacts.size());
  std::vector<SolverContact> readable;
  for (std::size_t k : order) readable.push_back(original.contacts[k]);
  std::vector<SolverBody> bodies = original.bodies;
  prepareContacts(readable, bodies, options);
  EXPECT_FALSE(solveVelocities(readable, bodies, options));
  double largest = 0.0;
  for (const SolverContact& c : readable) largest = std::max(largest, c.normal_impulse);
  // Rounding: a few hundred operations per impulse, each within 2⁻⁵³ of its result.
  for (std::size_t j = 0; j < order.size(); ++j) {
    const SolverContact &l = lanes.contacts[order[j]], &r = readable[j];
    EXPECT_NEAR(l.normal_impulse, r.normal_impulse, 1e-12 * largest) << j;
    EXPECT_NEAR((l.friction_impulse - r.friction_impulse).norm(), 0.0, 1e-12 * largest) << j;
  }
  for (std::size_t s = 1; s < bodies.size(); ++s) {
    EXPECT_NEAR((lanes.bodies[s].v - bodies[s].v).norm(), 0.0, 1e-12 * (1.0 + bodies[s].v.norm())) << s;
    EXPECT_NEAR((lanes.bodies[s].w - bodies[s].w).norm(), 0.0, 1e-12 * (1.0 + bodies[s].w.norm())) << s;
  }
  // The lists' own order gives other impulses after six sweeps: the comparison tells orders apart.
  std::vector<SolverContact> listed = original.contacts;
  std::vector<SolverBody> listed_bodies = original.bodies;
  prepareContacts(listed, listed_bodies, options);
  solveVelocities(listed, listed_bodies, options);
  double differs = 0.0;
  for (std::size_t j = 0; j < order.size(); ++j) {
    differs = std::max(differs, std::abs(lanes.contacts[order[j]].normal_impulse - listed[order[j]].normal_impulse));
  }
  EXPECT_GT(differs, 1e-6 * largest);
}

// A full slot loaded by transposes (four lanes where the CPU has AVX, eight where it has AVX-512) holds the
// bits of the lane-by-lane loads: the contacts' fields all different, every one of the slot's fields compared.
template <class T>
void expectTransposedSlotHoldsTheLaneByLaneLoads() {
  constexpr std::size_t kWidth = kLaneCount<T>;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<SolverContact> contacts(kWidth);
  for (SolverContact& c : contacts) {
    for (Eigen::Vector3d* v : {&c.r_a, &c.r_b, &c.n, &c.t1, &c.t2}) {
      *v = Eigen::Vector3d(value(random), value(random), value(random));
    }
    for (Eigen::Matrix3d* m : {&c.cross_a, &c.cross_b, &c.response_a, &c.response_b}) {
      for (int i = 0; i < 9; ++i) m->data()[i] = value(random);
    }
    for (double* x : {&c.separation, &c.friction, &c.restitution, &c.target_speed, &c.slip_squared, &c.normal_floor,
                      &c.normal_impulse, &c.normal_mass}) {
      *x = value(random);
    }
    c.friction_impulse = Eigen::Vector2d(value(random), value(random));
    for (int i = 0; i < 4; ++i) c.tangent_mass.data()[i] = value(random), c.tangent_response.data()[i] = value(random);
  }
  const SolverContact* lanes[kWidth];
  for (std::size_t l = 0; l < kWidth; ++l) lanes[l] = &contacts[l];
  auto transposed = std::make_unique<PointLanes<T>>();
  auto lane_by_lane = std::make_unique<PointLanes<T>>();
  loadFullSlot(*transposed, lanes);
  for (std::size_t l = 0; l < kWidth; ++l) loadPoint(*lane_by_lane, l, contacts[l]);
  const auto* a = reinterpret_cast<const double*>(transposed.get());
  const auto* b = reinterpret_cast<const double*>(lane_by_lane.get());
  for (std::size_t i = 0; i < sizeof(PointLanes<T>) / sizeof(double); ++i) {
    EXPECT_EQ(std::memcmp(a + i, b + i, sizeof(double)), 0)
        << kWidth << " lanes, field " << i / kWidth << ", lane " << i % kWidth;
  }
}

TEST(ContactLanes, ASlotLoadedByTransposesHoldsTheLaneByLaneLoads) {
  bool any = false;
  if (slotLoadsTransposed<integrators::Lanes>()) {
    any = true, expectTransposedSlotHoldsTheLaneByLaneLoads<integrators::Lanes>();
  }
  if (slotLoadsTransposed<EightLanes>()) any = true, expectTransposedSlotHoldsTheLaneByLaneLoads<EightLanes>();
  if (!any) GTEST_SKIP() << "this CPU or build loads the slots lane by lane only";
}

}  // namespace
