// Pairs' points kept from one detection to the next (src/contact/pair_reuse.hpp): reused only while no
// point of one box has moved relative to the other by more than kReuseShare of the near distance since they
// were made, and then where a fresh detection puts them, to that bound. Thresholds are rounding's (positions
// of order 1 m) or the reuse bound itself, set from the documented rule before any run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "../../src/contact/collision_world.hpp"
#include "../../src/contact/pair_reuse.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;
using contact::CollisionWorld;
using contact::ContactPoint;
using contact::kReuseShare;

namespace {

constexpr double kRounding = 1e-12;  // of lengths of order 1 m after a few products [m]
constexpr double kNear = 1e-4;       // the detection's reach: the default penetration slop [m]
constexpr double kBound = kReuseShare * kNear;  // how far a reused pair may have moved [m]

struct Pose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = q.toRotationMatrix();
    X.translation() = p;
    return X;
  }
};

// A point's pair written with the lower object first (the normal then from the higher towards the lower).
ContactPoint ordered(ContactPoint point) {
  if (point.a > point.b) {
    std::swap(point.a, point.b);
    std::swap(point.on_a, point.on_b);
    point.normal = -point.normal;
  }
  return point;
}

std::vector<ContactPoint> pairPoints(const std::vector<ContactPoint>& points, std::size_t a, std::size_t b) {
  std::vector<ContactPoint> out;
  for (const ContactPoint& point : points) {
    const ContactPoint o = ordered(point);
    if (o.a == a && o.b == b) out.push_back(o);
  }
  return out;
}

// The distance from a point to a box's surface (half extents `half` at X).
double offSurface(const Eigen::Isometry3d& X, const Eigen::Vector3d& half, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d local = X.inverse() * p_W;
  const Eigen::Vector3d outside = (local.cwiseAbs() - half).cwiseMax(0.0);
  if (outside.squaredNorm() > 0.0) return outside.norm();
  return (half - local.cwiseAbs()).minCoeff();  // inside: to the nearest face
}

// A cube of side 0.2 resting on another, turned by `yaw` and set off sideways; gap `gap`.
std::vector<Pose> restingPair(double yaw, double gap) {
  Pose lower, upper;
  lower.p = Eigen::Vector3d(0.3, -0.2, 0.1);
  upper.q = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  upper.p = lower.p + Eigen::Vector3d(0.03, -0.02, 0.2 + gap);
  return {lower, upper};
}

const Eigen::Vector3d kCube = Eigen::Vector3d::Constant(0.2);

std::vector<CollisionShape> boxes(const std::vector<Eigen::Vector3d>& sizes) {
  std::vector<CollisionShape> out;
  for (const Eigen::Vector3d& size : sizes) out.push_back(reference::collisionShape(ShapeType::kBox, size, 0.5, 0.0));
  return out;
}

std::vector<Eigen::Isometry3d> isometries(const std::vector<Pose>& poses) {
  std::vector<Eigen::Isometry3d> out;
  for (const Pose& pose : poses) out.push_back(pose.isometry());
  return out;
}

struct Detection {
  CollisionWorld world;
  std::vector<ContactPoint> points;
  Detection(const std::vector<Pose>& poses, const std::vector<CollisionShape>& shapes,
            const std::vector<CollisionShape>& environment = {})
      : world(environment, shapes, isometries(poses)) {}
  void place(const std::vector<Pose>& poses) {
    for (std::size_t i = 0; i < poses.size(); ++i) world.setPose(i, poses[i].p, poses[i].q);
  }
  const std::vector<ContactPoint>& detect() {
    world.detect(points, kNear);
    return points;
  }
};

// The points the reuse gives against a fresh detection at the same poses: as many, the deepest as deep to
// the bound, the normal turned by no more than the bound over the smaller shape's reach, and each witness
// on a box's surface to the bound. `shapes`: objects' shapes and poses, bodies then environment.
void expectWithinBound(const std::vector<ContactPoint>& reused, const std::vector<ContactPoint>& fresh,
                       const std::vector<CollisionShape>& shapes, const std::vector<Eigen::Isometry3d>& poses,
                       std::size_t a, std::size_t b, const char* what) {
  const std::vector<ContactPoint> kept = pairPoints(reused, a, b), made = pairPoints(fresh, a, b);
  ASSERT_EQ(kept.size(), made.size()) << what << " " << a << " " << b;
  if (kept.empty()) return;
  const auto deepest = [](const std::vector<ContactPoint>& points) {
    double d = points[0].distance;
    for (const ContactPoint& p : points) d = std::min(d, p.distance);
    return d;
  };
  EXPECT_NEAR(deepest(kept), deepest(made), kBound + kRounding) << what << " " << a << " " << b;
  const double reach = std::min(outerRadius(shapes[a]), outerRadius(shapes[b]));
  const auto onSurface = [&](std::size_t object, const Eigen::Vector3d& p_W) {
    if (shapes[object].type != ShapeType::kBox) return 0.0;
    return offSurface(poses[object], 0.5 * shapes[object].size, p_W);
  };
  for (const ContactPoint& p : kept) {
    EXPECT_LE((p.normal - made[0].normal).norm(), kBound / reach + kRounding) << what << " " << a << " " << b;
    EXPECT_LE(onSurface(a, p.on_a), kBound + kRounding) << what << " " << a << " " << b;
    EXPECT_LE(onSurface(b, p.on_b), kBound + kRounding) << what << " " << a << " " << b;
    EXPECT_NEAR(p.distance, p.normal.dot(p.on_a - p.on_b), kRounding) << what;
  }
}

}  // namespace

// Both boxes carried together by a large motion (a turn of 0.9 rad about a slanted axis and a metre away):
// nothing moved between them, so the pair's points are reused, and they must be the fresh detection's at the
// new poses to rounding. Points kept in the world's frame, or a normal not carried by its box, are off by
// centimetres.
TEST(PairReuse, APairCarriedTogetherKeepsItsPointsWhereAFreshTestPutsThem) {
  for (const double yaw : {0.0, 0.3, 0.7}) {
    for (const double gap : {0.0, 0.5 * kNear, -0.3 * kNear}) {
      std::vector<Pose> poses = restingPair(yaw, gap);
      Detection history(poses, boxes({kCube, kCube}));
      ASSERT_FALSE(history.detect().empty());
      const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()));
      const Eigen::Vector3d shift(1.0, 0.4, -0.7);
      for (Pose& pose : poses) pose.p = turn * pose.p + shift, pose.q = turn * pose.q;
      history.place(poses);
      const std::vector<ContactPoint> reused = pairPoints(history.detect(), 0, 1);
      EXPECT_EQ(history.world.reusedPairs(), 1u);
      Detection fresh(poses, boxes({kCube, kCube}));
      const std::vector<ContactPoint> made = pairPoints(fresh.detect(), 0, 1);
      ASSERT_EQ(reused.size(), made.size()) << yaw << " " << gap;
      for (const ContactPoint& p : reused) {
        const ContactPoint* nearest = &made[0];
        const auto apart = [&](const ContactPoint& q) { return (p.on_a - q.on_a).norm() + (p.on_b - q.on_b).norm(); };
        for (const ContactPoint& q : made) nearest = apart(q) < apart(*nearest) ? &q : nearest;
        EXPECT_LE(apart(*nearest), kRounding) << yaw << " " << gap;
        EXPECT_LE((p.normal - nearest->normal).norm(), kRounding) << yaw << " " << gap;
        EXPECT_NEAR(p.distance, nearest->distance, kRounding) << yaw << " " << gap;
      }
    }
  }
}

// The upper box moved relative to the lower one: by translations and turns about its centre whose reach (the
// bound ‖R − R₀‖_F r + |p − p₀|, r its half diagonal) is half the allowed motion, the points are reused
// and within the bound of a fresh test's; by twice the allowed motion, in any one of the six directions of
// translation or axes of turning, they are made afresh. A bound that left out the turn, or read the motion
// in the world's frame, or compared a square with a length, reuses where it must not.
TEST(PairReuse, APairThatMovedMoreThanTheBoundGetsFreshPoints) {
  const double reach = 0.5 * kCube.norm();
  for (const double share : {0.5, 2.0}) {
    for (int kind = 0; kind < 12; ++kind) {
      const std::vector<Pose> start = restingPair(0.4, 0.2 * kNear);
      Detection history(start, boxes({kCube, kCube}));
      history.detect();
      std::vector<Pose> poses = start;
      const Eigen::Vector3d axis = Eigen::Vector3d::Unit(kind % 3) * (kind % 6 < 3 ? 1.0 : -1.0);
      if (kind < 6) {
        poses[1].p += share * kBound * axis;
      } else {
        // ‖R(θ) − 1‖_F = 2√2 sin(θ/2) for a turn by θ.
        const double angle = 2.0 * std::asin(share * kBound / (reach * 2.0 * std::sqrt(2.0)));
        poses[1].q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) * poses[1].q;
      }
      history.place(poses);
      const std::vector<ContactPoint> reused = history.detect();
      EXPECT_EQ(history.world.reusedPairs(), share < 1.0 ? 1u : 0u) << share << " " << kind;
      Detection fresh(poses, boxes({kCube, kCube}));
      expectWithinBound(reused, fresh.detect(), boxes({kCube, kCube}), isometries(poses), 0, 1, "moved");
    }
  }
}

// Two stacks on a floor box of the environment, of boxes, a standing cylinder and a capsule lying on its side
// (pairs by the boxes' own test and by face clipping after a query, and a body on the environment), each
// body at each step left where it was, nudged by a sixth of the bound, moved anew by up to 3 mm and 0.03 rad
// about its place, or lifted out of every other shape's reach (its pairs leave the broad phase and come back
// later: the dispatcher's manifolds change places in its list, and a place's stored points may belong to
// another pair), 300 steps: at every step each pair's points against a fresh world's at the same poses, as
// many and within the bound (the box pairs: see below).
TEST(PairReuse, PairsThatComeAndGoAlwaysGetTheirOwnPoints) {
  const auto shape = [](ShapeType type, const Eigen::Vector3d& size) { return reference::collisionShape(type, size, 0.5, 0.0); };
  const std::vector<CollisionShape> shapes = {
      shape(ShapeType::kBox, Eigen::Vector3d(0.6, 0.5, 0.2)), shape(ShapeType::kCylinder, Eigen::Vector3d(0.08, 0.15, 0)),
      shape(ShapeType::kBox, Eigen::Vector3d(0.2, 0.2, 0.2)), shape(ShapeType::kBox, Eigen::Vector3d(0.5, 0.4, 0.1)),
      shape(ShapeType::kCapsule, Eigen::Vector3d(0.05, 0.2, 0)), shape(ShapeType::kBox, Eigen::Vector3d(0.25, 0.3, 0.12))};
  CollisionShape floor = shape(ShapeType::kBox, Eigen::Vector3d(3.0, 3.0, 0.2));
  floor.pose.translation() = Eigen::Vector3d(0.4, 0.0, -0.1);
  std::vector<Pose> base(shapes.size());
  base[0].p = Eigen::Vector3d(0.0, 0.0, 0.1);
  base[1].p = Eigen::Vector3d(0.05, -0.04, 0.2 + 0.075);
  base[2].p = Eigen::Vector3d(0.02, 0.03, 0.35 + 0.1);
  base[3].p = Eigen::Vector3d(0.9, 0.0, 0.05);
  base[4].p = Eigen::Vector3d(0.85, 0.05, 0.1 + 0.05);
  base[5].p = Eigen::Vector3d(0.9, 0.0, 0.2 + 0.06);
  for (std::size_t i = 1; i < base.size(); ++i) {
    base[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * static_cast<double>(i), Eigen::Vector3d::UnitZ()));
  }
  base[4].q = base[4].q * Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX()));  // lying
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto randomVector = [&] { return Eigen::Vector3d(unit(random), unit(random), unit(random)); };
  std::vector<Pose> poses = base;
  Detection history(poses, shapes, {floor});
  std::vector<CollisionShape> objects = shapes;
  objects.push_back(floor);
  std::size_t reused_pairs = 0, touching_pairs = 0;
  for (int step = 0; step < 300; ++step) {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const int choice = static_cast<int>(random() % 10);
      if (choice < 3) continue;
      if (choice < 6) {  // each point of the shape moves by at most a sixth of the bound from each part
        const double r = outerRadius(shapes[i]);
        poses[i].p += (kBound / 6.0) * randomVector().normalized();
        const double angle = (kBound / 6.0) / (r * 2.0 * std::sqrt(2.0));
        poses[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, randomVector().normalized())) * poses[i].q;
      } else if (choice < 9) {
        poses[i].p = base[i].p + 3e-3 * randomVector();
        poses[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.03, randomVector().normalized())) * base[i].q;
      } else {  // out of every other shape's reach
        poses[i].p = base[i].p + Eigen::Vector3d(0.0, 0.0, 5.0 + static_cast<double>(i));
      }
    }
    history.place(poses);
    const std::vector<ContactPoint> kept = history.detect();
    reused_pairs += history.world.reusedPairs();
    Detection fresh(poses, shapes, {floor});
    const std::vector<ContactPoint> made = fresh.detect();
    std::vector<Eigen::Isometry3d> placed = isometries(poses);
    placed.push_back(floor.pose);
    for (std::size_t a = 0; a < objects.size(); ++a) {
      for (std::size_t b = a + 1; b < objects.size(); ++b) {
        // A pair by a query is compared where it stands still (below): Bullet's query depends on the pair's
        // history (its cached separating axis), so two worlds disagree on it by more than the bound anyway.
        if (objects[a].type != ShapeType::kBox || objects[b].type != ShapeType::kBox) continue;
        expectWithinBound(kept, made, objects, placed, a, b, "step");
        touching_pairs += pairPoints(made, a, b).empty() ? 0 : 1;
      }
    }
    if (HasFailure()) FAIL() << "at step " << step;
  }
  // The walk keeps the stacks touching and both kinds of pair happen (a check on the test, not the code).
  EXPECT_GT(reused_pairs, 30u);
  EXPECT_GT(touching_pairs, 300u);
}

// A detection asked with another near distance makes the points afresh (what is within one is not what is
// within the other), and a pair at the same poses asked again with the first reuses them.
TEST(PairReuse, AnotherNearDistanceGetsFreshPoints) {
  const std::vector<Pose> poses = restingPair(0.2, 0.0);
  Detection history(poses, boxes({kCube, kCube}));
  std::vector<ContactPoint> points;
  history.world.detect(points, kNear);
  history.world.detect(points, 2.0 * kNear);
  EXPECT_EQ(history.world.reusedPairs(), 0u);
  history.world.detect(points, 2.0 * kNear);
  EXPECT_EQ(history.world.reusedPairs(), 1u);
}

// The points kept for one pair are never another's: asked for another pair at the very same poses (another
// pair of boxes, of other sizes, can stand as the first did), the store refuses.
TEST(PairReuse, StoredPointsAnswerOnlyTheirOwnPair) {
  const std::vector<Pose> poses = restingPair(0.3, 0.0);
  Detection detection(poses, boxes({kCube, kCube}));
  const std::vector<ContactPoint> points = detection.detect();
  ASSERT_FALSE(points.empty());
  const Eigen::Isometry3d X_WA = poses[points[0].a].isometry(), X_WB = poses[points[0].b].isometry();
  contact::PairReuse reuse;
  reuse.store(points[0].a, points[0].b, X_WA, X_WB, kNear, points, 0);
  EXPECT_TRUE(reuse.standsStill(points[0].a, points[0].b, X_WA, X_WB, 0.2, 0.2, kNear));
  std::vector<ContactPoint> out;
  reuse.appendPoints(X_WA, X_WB, kNear, out);
  EXPECT_EQ(out.size(), points.size());
  EXPECT_FALSE(reuse.standsStill(points[0].a + 2, points[0].b + 2, X_WA, X_WB, 0.2, 0.2, kNear));
  EXPECT_FALSE(reuse.standsStill(points[0].b, points[0].a, X_WA, X_WB, 0.2, 0.2, kNear));
}

// Pairs whose points come from a query and face clipping (a cylinder standing on a box, a box on the
// cylinder's end, a capsule lying on a box): carried together by a large motion, every touching pair is
// reused, its query skipped, and its points are those of the detection before, carried by the motion, to
// rounding (a skipped query whose points were not given back, or given back where they were, fails); then
// the top box alone moved by twice the bound: its pair, and only it, is made afresh.
TEST(PairReuse, QueriedPairsCarriedTogetherKeepTheirPointsAndOneMovedIsQueriedAgain) {
  const auto shape = [](ShapeType type, const Eigen::Vector3d& size) { return reference::collisionShape(type, size, 0.5, 0.0); };
  const std::vector<CollisionShape> shapes = {
      shape(ShapeType::kBox, Eigen::Vector3d(0.6, 0.5, 0.2)), shape(ShapeType::kCylinder, Eigen::Vector3d(0.08, 0.15, 0)),
      shape(ShapeType::kBox, Eigen::Vector3d(0.2, 0.2, 0.2)), shape(ShapeType::kCapsule, Eigen::Vector3d(0.05, 0.2, 0))};
  std::vector<Pose> poses(shapes.size());
  poses[0].p = Eigen::Vector3d(0.0, 0.0, 0.1);
  poses[1].p = Eigen::Vector3d(0.05, -0.04, 0.2 + 0.075 - 0.2 * kNear);
  poses[2].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  poses[2].p = Eigen::Vector3d(0.06, -0.03, 0.35 + 0.1 + 0.3 * kNear);
  poses[3].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX()));
  poses[3].p = Eigen::Vector3d(-0.15, 0.1, 0.2 + 0.05 - 0.1 * kNear);
  Detection history(poses, shapes);
  const std::vector<ContactPoint> before = history.detect();
  const std::size_t pairs = 3;  // box–cylinder, cylinder–box, box–capsule
  for (const auto& [a, b] : {std::pair<std::size_t, std::size_t>{0, 1}, {1, 2}, {0, 3}}) {
    ASSERT_FALSE(pairPoints(before, a, b).empty()) << a << " " << b;
  }
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(1.1, Eigen::Vector3d(-0.3, 1.0, 0.4).normalized()));
  const Eigen::Vector3d shift(-0.6, 2.0, 0.3);
  std::vector<Pose> carried = poses;
  for (Pose& pose : carried) pose.p = turn * pose.p + shift, pose.q = turn * pose.q;
  history.place(carried);
  const std::vector<ContactPoint> after = history.detect();
  EXPECT_EQ(history.world.reusedPairs(), pairs);
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].a, before[i].a);
    EXPECT_EQ(after[i].b, before[i].b);
    EXPECT_LE((after[i].on_a - (turn * before[i].on_a + shift)).norm(), kRounding) << i;
    EXPECT_LE((after[i].on_b - (turn * before[i].on_b + shift)).norm(), kRounding) << i;
    EXPECT_LE((after[i].normal - turn * before[i].normal).norm(), kRounding) << i;
    EXPECT_NEAR(after[i].distance, before[i].distance, kRounding) << i;
  }
  carried[2].p += 2.0 * kBound * Eigen::Vector3d::UnitX();
  history.place(carried);
  history.detect();
  EXPECT_EQ(history.world.reusedPairs(), pairs - 1);
}

namespace {

constexpr double kG = 9.81;
constexpr double kH = 1e-3;
const Eigen::Vector3d kDown(0.0, 0.0, -kG);

BodyDefinition resting(const MassProperties& mass, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  return reference::contactBody(mass, p, q, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown);
}

// On a floor box of the environment: a tower of five boxes, each turned and set off; a cylinder standing on
// a box with a box on its end; a capsule lying on a box. Sleeping off, contact/reuse_points as asked.
Scene mixedStacks(bool reuse) {
  ContactSetup setup;
  setup.settings.sleep = false;
  setup.settings.reuse_points = reuse;
  CollisionShape floor = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(4.0, 4.0, 0.2), 0.5, 0.0);
  floor.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  setup.environment = {floor};
  std::vector<BodyDefinition> bodies;
  const auto add = [&](ShapeType type, const Eigen::Vector3d& size, const MassProperties& mass, const Eigen::Vector3d& p,
                       const Eigen::Quaterniond& q) {
    bodies.push_back(resting(mass, p, q));
    setup.bodies.push_back(reference::collisionShape(type, size, 0.5, 0.0));
  };
  const Eigen::Vector3d cube(0.2, 0.2, 0.2);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Quaterniond yaw(Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d::UnitZ()));
    add(ShapeType::kBox, cube, MassProperties::box(1.0, cube), Eigen::Vector3d(0.004 * i, -0.003 * i, 0.1 + 0.2 * i), yaw);
  }
  const Eigen::Vector3d slab(0.4, 0.4, 0.1);
  add(ShapeType::kBox, slab, MassProperties::box(2.0, slab), Eigen::Vector3d(1.0, 0.0, 0.05), Eigen::Quaterniond::Identity());
  add(ShapeType::kCylinder, Eigen::Vector3d(0.08, 0.15, 0.0), MassProperties::cylinder(1.0, 0.08, 0.15),
      Eigen::Vector3d(1.02, 0.01, 0.1 + 0.075), Eigen::Quaterniond::Identity());
  add(ShapeType::kBox, cube, MassProperties::box(1.0, cube), Eigen::Vector3d(1.03, 0.0, 0.25 + 0.1),
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())));
  add(ShapeType::kBox, slab, MassProperties::box(2.0, slab), Eigen::Vector3d(-1.0, 0.0, 0.05), Eigen::Quaterniond::Identity());
  add(ShapeType::kCapsule, Eigen::Vector3d(0.05, 0.2, 0.0), MassProperties::cylinder(1.0, 0.05, 0.3),
      Eigen::Vector3d(-1.0, 0.05, 0.1 + 0.05), Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX())));
  return Scene(bodies, IntegratorType::kRk4, kH, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

}  // namespace

// The same stacks stepped for 2 s with and without reused points: every body within the slop of where it is
// without (the bound is a thousandth of it), and not to the bit (the setting takes effect: a reused point's
// witnesses, carried by their shapes, round otherwise than a fresh test's).
TEST(PairReuse, StacksOfEveryPairKindStayWithinTheSlopOfTheirTrajectoriesWithoutReuse) {
  Scene with = mixedStacks(true), without = mixedStacks(false);
  for (int i = 0; i < 2000; ++i) with.step(1), without.step(1);
  double largest = 0.0;
  for (std::size_t body = 0; body < with.bodyCount(); ++body) {
    largest = std::max(largest, (with.state(body).p_WB - without.state(body).p_WB).norm());
    EXPECT_LT((without.state(body).p_WB - mixedStacks(false).state(body).p_WB).norm(), 1e-3) << body;  // stood
  }
  EXPECT_LT(largest, ContactSettings().penetration_slop);
  EXPECT_GT(largest, 0.0);
}

// A block on an incline of the environment's (a tilted box, so that the pair is a box pair and its points
// are reused) at tan θ = μ (1 + ε): at ε = 5e-5 it slides at a = g (sin θ − μ cos θ) = 2.2e-4 m/s², moving by
// less than the reuse bound per step for its first 0.45 s, so its points are kept while it creeps, and it
// must still travel ½ a t² (5 %) in 3 s; at ε = −1e-2 it sticks (less than the slop).
TEST(PairReuse, ABlockCreepingAtTheFrictionAngleOnABoxTravelsAsCoulombSays) {
  const double mu = 0.5;
  for (const double epsilon : {5e-5, -1e-2}) {
    const double theta = std::atan(mu * (1.0 + epsilon));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
    const Eigen::Vector3d up = q * Eigen::Vector3d::UnitZ(), along = q * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d size(0.2, 0.2, 0.1);
    CollisionShape incline = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(6.0, 2.0, 0.2), mu, 0.0);
    incline.pose.linear() = q.toRotationMatrix();
    incline.pose.translation() = -0.1 * up;  // its top face through the origin
    ContactSetup setup;
    setup.settings.sleep = false;
    setup.environment = {incline};
    setup.bodies = {reference::collisionShape(ShapeType::kBox, size, mu, 0.0)};
    const Eigen::Vector3d start = 0.05 * up;
    Scene scene({resting(MassProperties::box(1.0, size), start, q)}, IntegratorType::kRk4, kH, IntegratorSettings(),
                StepAssembly::kLeaveOut, setup);
    const double duration = 3.0;
    for (int i = 0; i < 3000; ++i) scene.step(1);
    const double travelled = (scene.state().p_WB - start).dot(along);
    if (epsilon > 0.0) {
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(travelled, 0.5 * a * duration * duration, 0.05 * 0.5 * a * duration * duration);
    } else {
      EXPECT_LT(std::abs(travelled), ContactSettings().penetration_slop);
    }
  }
}
