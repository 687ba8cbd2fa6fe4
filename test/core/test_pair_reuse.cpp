// Box pairs' points kept from one detection to the next (src/contact/pair_reuse.hpp): reused only while no
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

struct Detection {
  CollisionWorld world;
  std::vector<ContactPoint> points;
  explicit Detection(const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& sizes)
      : world({}, shapes(sizes), isometries(poses)) {}
  static std::vector<CollisionShape> shapes(const std::vector<Eigen::Vector3d>& sizes) {
    std::vector<CollisionShape> out;
    for (const Eigen::Vector3d& size : sizes) out.push_back(reference::collisionShape(ShapeType::kBox, size, 0.5, 0.0));
    return out;
  }
  static std::vector<Eigen::Isometry3d> isometries(const std::vector<Pose>& poses) {
    std::vector<Eigen::Isometry3d> out;
    for (const Pose& pose : poses) out.push_back(pose.isometry());
    return out;
  }
  void place(const std::vector<Pose>& poses) {
    for (std::size_t i = 0; i < poses.size(); ++i) world.setPose(i, poses[i].p, poses[i].q);
  }
  const std::vector<ContactPoint>& detect() {
    world.detect(points, kNear);
    return points;
  }
};

// The points the reuse gives against a fresh detection at the same poses: as many, the deepest as deep to
// the bound, the normal turned by no more than the bound over the box's half diagonal, and each witness on
// its own box's surface to the bound.
void expectWithinBound(const std::vector<ContactPoint>& reused, const std::vector<ContactPoint>& fresh,
                       const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& sizes, std::size_t a,
                       std::size_t b, const char* what) {
  const std::vector<ContactPoint> kept = pairPoints(reused, a, b), made = pairPoints(fresh, a, b);
  ASSERT_EQ(kept.size(), made.size()) << what;
  if (kept.empty()) return;
  const auto deepest = [](const std::vector<ContactPoint>& points) {
    double d = points[0].distance;
    for (const ContactPoint& p : points) d = std::min(d, p.distance);
    return d;
  };
  EXPECT_NEAR(deepest(kept), deepest(made), kBound + kRounding) << what;
  const double reach = 0.5 * std::max(sizes[a].norm(), sizes[b].norm());
  for (const ContactPoint& p : kept) {
    EXPECT_LE((p.normal - made[0].normal).norm(), kBound / reach + kRounding) << what;
    EXPECT_LE(offSurface(poses[a].isometry(), 0.5 * sizes[a], p.on_a), kBound + kRounding) << what;
    EXPECT_LE(offSurface(poses[b].isometry(), 0.5 * sizes[b], p.on_b), kBound + kRounding) << what;
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
      Detection history(poses, {kCube, kCube});
      ASSERT_FALSE(history.detect().empty());
      const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()));
      const Eigen::Vector3d shift(1.0, 0.4, -0.7);
      for (Pose& pose : poses) pose.p = turn * pose.p + shift, pose.q = turn * pose.q;
      history.place(poses);
      const std::vector<ContactPoint> reused = pairPoints(history.detect(), 0, 1);
      EXPECT_EQ(history.world.reusedPairs(), 1u);
      Detection fresh(poses, {kCube, kCube});
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
      Detection history(start, {kCube, kCube});
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
      Detection fresh(poses, {kCube, kCube});
      expectWithinBound(reused, fresh.detect(), poses, {kCube, kCube}, 0, 1, "moved");
    }
  }
}

// Boxes of five sizes in two stacks, each step left where it was, nudged by a third of the bound, moved anew
// by up to 3 mm and 0.03 rad about its place, or lifted out of every other box's reach (its pairs leave the
// broad phase and come back later: the dispatcher's manifolds change places in its list, and a place's
// stored points may belong to another pair), 300 steps:
// at every step each pair's points against a fresh world's at the same poses, as many and within the
// bound; a pair made afresh exactly the fresh world's.
TEST(PairReuse, PairsThatComeAndGoAlwaysGetTheirOwnPoints) {
  const std::vector<Eigen::Vector3d> sizes = {Eigen::Vector3d(0.6, 0.5, 0.2), Eigen::Vector3d(0.3, 0.2, 0.15),
                                              Eigen::Vector3d(0.2, 0.2, 0.2), Eigen::Vector3d(0.5, 0.4, 0.1),
                                              Eigen::Vector3d(0.25, 0.3, 0.12)};
  std::vector<Pose> base(sizes.size());
  base[0].p = Eigen::Vector3d(0.0, 0.0, 0.1);
  base[1].p = Eigen::Vector3d(0.05, -0.04, 0.2 + 0.075);
  base[2].p = Eigen::Vector3d(0.02, 0.03, 0.35 + 0.1);
  base[3].p = Eigen::Vector3d(0.9, 0.0, 0.05);
  base[4].p = Eigen::Vector3d(0.85, 0.05, 0.1 + 0.06);
  for (std::size_t i = 1; i < base.size(); ++i) {
    base[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * static_cast<double>(i), Eigen::Vector3d::UnitZ()));
  }
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto randomVector = [&] { return Eigen::Vector3d(unit(random), unit(random), unit(random)); };
  std::vector<Pose> poses = base;
  Detection history(poses, sizes);
  std::size_t reused_pairs = 0, fresh_pairs = 0;
  for (int step = 0; step < 300; ++step) {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const int choice = static_cast<int>(random() % 10);
      if (choice < 3) continue;
      if (choice < 6) {  // each point of the box moves by at most a sixth of the bound from each part
        const double r = 0.5 * sizes[i].norm();
        poses[i].p += (kBound / 6.0) * randomVector().normalized();
        const double angle = (kBound / 6.0) / (r * 2.0 * std::sqrt(2.0));
        poses[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, randomVector().normalized())) * poses[i].q;
      } else if (choice < 9) {
        poses[i].p = base[i].p + 3e-3 * randomVector();
        poses[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.03, randomVector().normalized())) * base[i].q;
      } else {  // out of every other box's reach: its pairs leave the broad phase, and come back later
        poses[i].p = base[i].p + Eigen::Vector3d(0.0, 0.0, 5.0 + static_cast<double>(i));
      }
    }
    history.place(poses);
    const std::vector<ContactPoint> kept = history.detect();
    reused_pairs += history.world.reusedPairs();
    Detection fresh(poses, sizes);
    const std::vector<ContactPoint> made = fresh.detect();
    for (std::size_t a = 0; a < sizes.size(); ++a) {
      for (std::size_t b = a + 1; b < sizes.size(); ++b) {
        expectWithinBound(kept, made, poses, sizes, a, b, "step");
        fresh_pairs += pairPoints(made, a, b).empty() ? 0 : 1;
      }
    }
    if (HasFailure()) FAIL() << "at step " << step;
  }
  // The walk keeps the stacks touching and both kinds of pair happen (a check on the test, not the code).
  EXPECT_GT(reused_pairs, 30u);
  EXPECT_GT(fresh_pairs, 300u);
}

// A detection asked with another near distance makes the points afresh (what is within one is not what is
// within the other), and a pair at the same poses asked again with the first reuses them.
TEST(PairReuse, AnotherNearDistanceGetsFreshPoints) {
  const std::vector<Pose> poses = restingPair(0.2, 0.0);
  Detection history(poses, {kCube, kCube});
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
  Detection detection(poses, {kCube, kCube});
  const std::vector<ContactPoint> points = detection.detect();
  ASSERT_FALSE(points.empty());
  const Eigen::Isometry3d X_WA = poses[points[0].a].isometry(), X_WB = poses[points[0].b].isometry();
  contact::PairReuse reuse;
  reuse.store(points[0].a, points[0].b, X_WA, X_WB, kNear, points, 0);
  std::vector<ContactPoint> out;
  EXPECT_TRUE(reuse.reuse(points[0].a, points[0].b, X_WA, X_WB, 0.2, kNear, out));
  EXPECT_EQ(out.size(), points.size());
  out.clear();
  EXPECT_FALSE(reuse.reuse(points[0].a + 2, points[0].b + 2, X_WA, X_WB, 0.2, kNear, out));
  EXPECT_FALSE(reuse.reuse(points[0].b, points[0].a, X_WA, X_WB, 0.2, kNear, out));
  EXPECT_TRUE(out.empty());
}
