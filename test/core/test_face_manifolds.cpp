// Contact points by face clipping (src/contact/face_manifold.hpp): what the detection gives a cylinder, a
// capsule or a hull on a box, and on each other, against the geometry worked out by hand; then what that
// does to bodies: tipping over an edge exactly where the centre of mass passes it, and rolling and sliding
// on a tilted box at the closed forms of docs/references.md §4. Thresholds come from the geometry and the
// physics, before any run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../../src/contact/collision_world.hpp"
#include "../../src/contact/face_manifold.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"
#include "rigid_body_sim/scene.hpp"

using namespace rigid_body;
using contact::CollisionWorld;
using contact::ContactPoint;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr double kNear = 1e-4;    // the detection's reach: the default penetration slop [m]
constexpr double kSink = 5e-4;    // how far the tests set a body into the box below [m]
constexpr double kExact = 1e-9;   // rounding in positions and depths of order 1 m [m]
const Eigen::Vector3d kDown(0.0, 0.0, -kG);

// A table: the environment box 1 × 0.6 × 0.2 m whose top face is z = 0, x ∈ [−0.5, 0.5], y ∈ [−0.3, 0.3].
CollisionShape table() {
  CollisionShape box = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(1.0, 0.6, 0.2), 0.5, 0.0);
  box.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  return box;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}

// The points of body 0 (first the body, then the environment) at `X_WB`, seen from the body: each point's
// position on the body, on the other object, and the normal from the other object towards the body.
struct BodyPoint {
  Eigen::Vector3d on_body, on_other, normal;
  double distance;
};
std::vector<BodyPoint> detectBody(const std::vector<CollisionShape>& environment, const std::vector<CollisionShape>& bodies,
                                  const std::vector<Eigen::Isometry3d>& poses, double near = kNear) {
  CollisionWorld world(environment, bodies, poses);
  std::vector<ContactPoint> points;
  world.detect(points, near);
  std::vector<BodyPoint> seen;
  for (const ContactPoint& p : points) {
    if (p.a == 0) seen.push_back({p.on_a, p.on_b, p.normal, p.distance});
    if (p.b == 0) seen.push_back({p.on_b, p.on_a, -p.normal, p.distance});
  }
  return seen;
}

// Whether one of `points` lies within kExact of `where` on the body.
bool hasPoint(const std::vector<BodyPoint>& points, const Eigen::Vector3d& where) {
  return std::any_of(points.begin(), points.end(), [&](const BodyPoint& p) { return (p.on_body - where).norm() <= kExact; });
}

std::string describe(const std::vector<BodyPoint>& points) {
  std::string text;
  for (const BodyPoint& p : points) {
    text += "(" + std::to_string(p.on_body.x()) + ", " + std::to_string(p.on_body.y()) + ", " +
            std::to_string(p.on_body.z()) + ") d " + std::to_string(p.distance) + "; ";
  }
  return text;
}

// A hexagonal prism (circumradius 0.1 m, 0.08 m tall), as a mesh whose hull has two hexagonal faces.
TriangleMesh hexagonalPrism() {
  std::vector<Eigen::Vector2d> hexagon;
  for (int k = 0; k < 6; ++k) hexagon.emplace_back(0.1 * std::cos(k * kPi / 3.0), 0.1 * std::sin(k * kPi / 3.0));
  return primitives::extrudedPolygon(hexagon, 0.08);
}

}  // namespace

// A cylinder lying on the table, its axis diagonal to the table's edges (30° from x) and its end beyond the
// edge x = 0.5: the line it touches along is cut by the edge, so the points are its near end and the point
// where the line leaves the table, both at the depth it was set to. Multi-point perturbation puts its
// points wherever the perturbed queries land, and a point past the edge would hold up the overhanging end.
TEST(FaceManifolds, ACylinderLyingAcrossATableEdgeTouchesAlongTheLineUpToTheEdge) {
  const double radius = 0.05, length = 0.4, yaw = kPi / 6.0;
  const Eigen::Vector3d axis(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d centre(0.45, 0.05, radius - kSink);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
  const auto points = detectBody({table()}, {reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(radius, length, 0), 0.5, 0)},
                                 {pose(centre, q)});
  const Eigen::Vector3d bottom = centre - radius * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d near_end = bottom - 0.5 * length * axis;
  const Eigen::Vector3d at_edge = bottom + ((0.5 - bottom.x()) / axis.x()) * axis;
  ASSERT_EQ(points.size(), 2u) << describe(points);
  EXPECT_TRUE(hasPoint(points, near_end)) << describe(points);
  EXPECT_TRUE(hasPoint(points, at_edge)) << describe(points);
  for (const BodyPoint& p : points) {
    EXPECT_NEAR(p.distance, -kSink, kExact);
    EXPECT_NEAR(p.on_other.z(), 0.0, kExact);
    EXPECT_LE((p.normal - Eigen::Vector3d::UnitZ()).norm(), kExact);
  }
}

// A capsule lying level touches with both end spheres' lowest points; tilted by 2° it touches with the
// lower one only (the upper is 0.3 sin 2° = 10 mm up, beyond the reach): two points always would prop a
// tilted capsule up on a point it does not touch.
TEST(FaceManifolds, ACapsuleTouchesWithBothEndsLevelAndWithTheLowerEndTilted) {
  const double radius = 0.04, length = 0.3;
  const CollisionShape capsule = reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(radius, length, 0), 0.5, 0);
  for (double tilt : {0.0, 2.0 * kPi / 180.0}) {
    const Eigen::Vector3d axis(std::cos(tilt) * std::cos(0.4), std::cos(tilt) * std::sin(0.4), std::sin(tilt));
    const Eigen::Vector3d low_end(-0.1, 0.05, radius - kSink);
    const Eigen::Vector3d centre = low_end + 0.5 * length * axis;
    const auto points = detectBody({table()}, {capsule},
                                   {pose(centre, Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis))});
    const Eigen::Vector3d down = -radius * Eigen::Vector3d::UnitZ();
    ASSERT_EQ(points.size(), tilt == 0.0 ? 2u : 1u) << "tilt " << tilt << ": " << describe(points);
    EXPECT_TRUE(hasPoint(points, low_end + down)) << describe(points);
    if (tilt == 0.0) {
      EXPECT_TRUE(hasPoint(points, low_end + length * axis + down)) << describe(points);
    }
    for (const BodyPoint& p : points) EXPECT_NEAR(p.distance, -kSink, kExact);
  }
}

// A hexagonal prism (a hull) standing on the table's corner, turned 17°: the face it touches with is the
// hexagon cut by two of the table's edges, a polygon of up to eight corners, of which four are kept. Each
// kept point must be a corner of that polygon (worked out here independently: the hexagon's corners on the
// table, the table's corner in the hexagon, and where edges cross) at the depth it was set to.
TEST(FaceManifolds, AHullOnATableCornerTouchesAtCornersOfTheOverlap) {
  const double turn = 17.0 * kPi / 180.0;
  const Eigen::Vector3d centre(0.46, 0.27, 0.04 - kSink);  // the prism's frame at its centre, 0.04 above its base
  CollisionShape prism = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0);
  prism.mesh = hexagonalPrism();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()));
  const auto points = detectBody({table()}, {prism}, {pose(centre, q)});
  // The overlap's corners in the plane z = −kSink.
  std::vector<Eigen::Vector2d> hexagon, corners;
  for (int k = 0; k < 6; ++k) {
    const double phi = turn + k * kPi / 3.0;
    hexagon.emplace_back(centre.x() + 0.1 * std::cos(phi), centre.y() + 0.1 * std::sin(phi));
  }
  const auto on_table = [](const Eigen::Vector2d& p) { return std::abs(p.x()) <= 0.5 + 1e-12 && std::abs(p.y()) <= 0.3 + 1e-12; };
  const auto in_hexagon = [&](const Eigen::Vector2d& p) {
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector2d e = hexagon[(k + 1) % 6] - hexagon[k], r = p - hexagon[k];
      if (e.x() * r.y() - e.y() * r.x() < -1e-12) return false;
    }
    return true;
  };
  for (const auto& v : hexagon) {
    if (on_table(v)) corners.push_back(v);
  }
  if (in_hexagon(Eigen::Vector2d(0.5, 0.3))) corners.emplace_back(0.5, 0.3);
  for (int k = 0; k < 6; ++k) {  // the hexagon's edges across the table's edges x = 0.5 and y = 0.3
    const Eigen::Vector2d a = hexagon[k], b = hexagon[(k + 1) % 6];
    for (int axis = 0; axis < 2; ++axis) {
      const double line = axis == 0 ? 0.5 : 0.3;
      if ((a[axis] - line) * (b[axis] - line) >= 0.0) continue;
      const Eigen::Vector2d p = a + (line - a[axis]) / (b[axis] - a[axis]) * (b - a);
      if (on_table(p)) corners.push_back(p);
    }
  }
  ASSERT_GE(corners.size(), 5u) << "the scene should cut the hexagon to more than four corners";
  ASSERT_EQ(points.size(), 4u) << describe(points);
  for (const BodyPoint& p : points) {
    EXPECT_NEAR(p.distance, -kSink, kExact);
    const bool a_corner = std::any_of(corners.begin(), corners.end(),
                                      [&](const Eigen::Vector2d& c) { return (p.on_body.head<2>() - c).norm() <= kExact; });
    double closest = 1.0;
    for (const auto& c : corners) closest = std::min(closest, (p.on_body.head<2>() - c).norm());
    EXPECT_TRUE(a_corner) << "the nearest corner is " << closest << " m away: " << describe(points);
  }
}

namespace {

// The round table: the top end (z = 0) of a standing cylinder of the environment, 1 m across.
CollisionShape roundTable() {
  CollisionShape cylinder = reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.5, 0.2, 0), 0.5, 0);
  cylinder.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  return cylinder;
}

}  // namespace

// A body rocking on an edge (tilted 20° about its x axis, turned 30° about the vertical), 0.5 mm into the
// face below: the face below lies along the normal and the body's lowest face, 20° off it, is clipped to it,
// so the pair touches at the edge's two ends, to 1e-9 m. A cube hull on the table, and a box on the round
// table (a box's and a cylinder's collision margins round their edges inside them: GJK alone would see this
// edge only once it is 1.1 mm in).
TEST(FaceManifolds, ABodyOnAnEdgeTouchesAtTheEdgesEnds) {
  CollisionShape cube = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0);
  cube.mesh = primitives::box(Eigen::Vector3d::Constant(0.1));
  const CollisionShape box = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(0.2, 0.16, 0.1), 0.5, 0);
  struct Case {
    CollisionShape below, body;
    Eigen::Vector3d half;  // the body's half extents: its lowest edge runs from (h, −h, −h) to (−h, −h, −h)
  };
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 6.0, Eigen::Vector3d::UnitZ())) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 9.0, Eigen::Vector3d::UnitX()));
  for (const Case& c : {Case{table(), cube, Eigen::Vector3d::Constant(0.05)}, Case{roundTable(), box, Eigen::Vector3d(0.1, 0.08, 0.05)}}) {
    const Eigen::Vector3d corner_a(c.half.x(), -c.half.y(), -c.half.z()), corner_b(-c.half.x(), -c.half.y(), -c.half.z());
    const Eigen::Vector3d centre(0.1, -0.2, -(q * corner_a).z() - kSink);
    const auto points = detectBody({c.below}, {c.body}, {pose(centre, q)});
    const std::string what = shapeTypeName(c.body.type);
    ASSERT_EQ(points.size(), 2u) << what << ": " << describe(points);
    EXPECT_TRUE(hasPoint(points, centre + q * corner_a)) << what << ": " << describe(points);
    EXPECT_TRUE(hasPoint(points, centre + q * corner_b)) << what << ": " << describe(points);
    for (const BodyPoint& p : points) EXPECT_NEAR(p.distance, -kSink, kExact) << what;
  }
}

// A small cube (8 cm) standing on a corner on the round table, 0.5 mm into it: the corner, exactly. Its 4 mm
// margin rounds the corner 2.9 mm inside it, farther than the pair's Bullet manifold keeps points (1.5 mm
// for this cube), so the query must reach beyond the near distance by the margins (docs/contact.md,
// "Shapes"). The first detection, with the cube 1 cm up, makes the pair's manifold, as the steps before a
// landing do.
TEST(FaceManifolds, ASmallBoxOnACornerOnARoundTableTouchesAtTheCorner) {
  const CollisionShape round_table = roundTable();
  const CollisionShape cube = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d::Constant(0.08), 0.5, 0);
  const Eigen::Vector3d corner(-0.04, -0.04, -0.04);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(corner, -Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d centre(0.2, -0.1, -(q * corner).z() - kSink);
  CollisionWorld world({round_table}, {cube}, {pose(centre + Eigen::Vector3d(0, 0, 0.01), q)});
  std::vector<ContactPoint> points;
  world.detect(points, kNear);
  EXPECT_TRUE(points.empty());
  world.setPose(0, centre, q);
  world.detect(points, kNear);
  ASSERT_EQ(points.size(), 1u);
  const Eigen::Vector3d on_cube = points[0].a == 0 ? points[0].on_a : points[0].on_b;
  EXPECT_LE((on_cube - (centre + q * corner)).norm(), kExact);
  EXPECT_NEAR(points[0].distance, -kSink, kExact);
}

// Capsule on capsule: crossed, one point at the crossing; parallel and offset along their axes, the two
// ends of their overlap. (Two segments that are not parallel would otherwise clip to the whole upper
// capsule's length, far from where the two touch.)
TEST(FaceManifolds, CapsulesCrossedTouchAtOnePointAndParallelAlongTheirOverlap) {
  const double radius = 0.03, length = 0.2;
  const CollisionShape capsule = reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(radius, length, 0), 0.5, 0);
  const Eigen::Vector3d below(0.0, 0.0, 0.2);
  const Eigen::Vector3d along_below(std::cos(0.3), std::sin(0.3), 0.0);
  const Eigen::Quaterniond q_below = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), along_below);
  for (bool crossed : {true, false}) {
    const Eigen::Vector3d along = crossed ? Eigen::Vector3d(-along_below.y(), along_below.x(), 0.0) : along_below;
    const Eigen::Vector3d above = below + Eigen::Vector3d(0, 0, 2.0 * radius - kSink) + (crossed ? 0.02 : 0.08) * along;
    const auto points = detectBody({}, {capsule, capsule},
                                   {pose(above, Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), along)),
                                    pose(below, q_below)});
    const Eigen::Vector3d down = -radius * Eigen::Vector3d::UnitZ();
    if (crossed) {
      ASSERT_EQ(points.size(), 1u) << describe(points);
      EXPECT_LE((points[0].on_body - (below + Eigen::Vector3d(0, 0, radius - kSink))).norm(), 1e-6) << describe(points);
    } else {
      ASSERT_EQ(points.size(), 2u) << describe(points);
      EXPECT_TRUE(hasPoint(points, above - 0.5 * length * along + down)) << describe(points);
      EXPECT_TRUE(hasPoint(points, below + 0.5 * length * along_below + Eigen::Vector3d(0, 0, radius - kSink))) << describe(points);
    }
    for (const BodyPoint& p : points) EXPECT_NEAR(p.distance, -kSink, crossed ? 1e-6 : kExact);
  }
}

// Two cube hulls meeting edge on edge (one turned 45° about x, the other 45° about y), their edges 5 mm into
// each other (their rounded edges, 4 mm margins, a little less): no face lies along the normal, so the pair
// keeps the one point its query found, where the edges cross.
TEST(FaceManifolds, HullsMeetingEdgeOnEdgeKeepOnePoint) {
  CollisionShape cube = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0);
  cube.mesh = primitives::box(Eigen::Vector3d::Constant(0.1));
  const double half_diagonal = 0.05 * std::sqrt(2.0);
  const auto points = detectBody(
      {}, {cube, cube},
      {pose(Eigen::Vector3d(0, 0, 2.0 * half_diagonal - 5e-3), Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitX()))),
       pose(Eigen::Vector3d::Zero(), Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitY())))});
  ASSERT_EQ(points.size(), 1u) << describe(points);
  EXPECT_LE(points[0].on_body.head<2>().norm(), 1e-3) << describe(points);
}

namespace {

// A scene of `bodies` (each at rest where placed) on the environment `environment`, rk4 at h = 1 ms.
Scene sceneOf(const std::vector<CollisionShape>& environment, const std::vector<CollisionShape>& shapes,
              const std::vector<MassProperties>& masses, const std::vector<Eigen::Isometry3d>& poses,
              const Eigen::Vector3d& v0 = Eigen::Vector3d::Zero()) {
  ContactSetup setup;
  setup.environment = environment;
  setup.bodies.assign(shapes.begin(), shapes.end());
  std::vector<BodyDefinition> bodies;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    bodies.push_back(reference::contactBody(masses[i], poses[i].translation(), Eigen::Quaterniond(poses[i].linear()),
                                            i == 0 ? v0 : Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDown));
  }
  return Scene(bodies, IntegratorType::kRk4, 1e-3, IntegratorSettings(), StepAssembly::kLeaveOut, setup);
}

// How far a body's axis `axis_B` has turned from where it started [rad].
double turned(const Scene& scene, std::size_t body, const Eigen::Quaterniond& q0, const Eigen::Vector3d& axis_B) {
  const Eigen::Vector3d now = scene.state(body).q_WB * axis_B, then = q0 * axis_B;
  return std::atan2(now.cross(then).norm(), now.dot(then));
}

}  // namespace

// A body resting over a table's edge stays where its centre of mass is over the table and tips where it is
// beyond, by as little as 3 mm either way: the points must reach the edge and no farther (the support
// polygon is the contact face cut by the edge). A capsule lying diagonally across the edge, a cylinder
// standing at it and a hexagonal hull standing at it. Staying: it may sink by the slop (1e-4 m) and turn by
// what that allows across its support, 1e-4 / 0.05 = 2e-3 rad at most; tipping: with the centre 3 mm beyond,
// the slowest of them (the capsule) turns at g d / (k² + ρ²) ≥ 2.4 rad/s² at first (docs/references.md
// §4.13), so by 2 s it has turned by more than 0.5 rad or left the table.
TEST(FaceManifolds, BodiesOverATableEdgeStayOrTipAsTheirCentreOfMassIsOverItOrBeyond) {
  const double offset = 3e-3;
  struct Case {
    std::string name;
    CollisionShape shape;
    MassProperties mass;
    Eigen::Vector3d axis_B;  // the axis whose turning tells a tip
    Eigen::Quaterniond q;
    double height;  // of the centre above the table when touching
  };
  CollisionShape prism = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0);
  prism.mesh = hexagonalPrism();
  const Eigen::Vector3d diagonal(std::cos(0.6), std::sin(0.6), 0.0);
  const std::vector<Case> cases = {
      {"capsule lying", reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(0.03, 0.3, 0), 0.5, 0),
       MassProperties::cylinder(1.0, 0.03, 0.36), Eigen::Vector3d::UnitZ(),
       Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), diagonal), 0.03},
      {"cylinder standing", reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.05, 0.2, 0), 0.5, 0),
       MassProperties::cylinder(1.0, 0.05, 0.2), Eigen::Vector3d::UnitZ(), Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())), 0.1},
      {"hexagonal hull standing", prism, MassProperties::box(1.0, Eigen::Vector3d(0.17, 0.17, 0.08)),
       Eigen::Vector3d::UnitZ(), Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())), 0.04},
  };
  for (const Case& c : cases) {
    for (double side : {-1.0, 1.0}) {
      const Eigen::Vector3d start(0.5 + side * offset, 0.1, c.height);
      Scene scene = sceneOf({table()}, {c.shape}, {c.mass}, {pose(start, c.q)});
      scene.step(2000);
      const State& s = scene.state(0);
      const double tilt = turned(scene, 0, c.q, c.axis_B);
      if (side < 0.0) {
        EXPECT_LE((s.p_WB - start).norm(), 2e-4) << c.name << " over the table moved";
        EXPECT_LE(tilt, 2e-3) << c.name << " over the table turned";
      } else {
        EXPECT_TRUE(tilt > 0.5 || s.p_WB.z() < 0.0) << c.name << " beyond the edge turned only " << tilt << " rad";
      }
    }
  }
}

// A cylinder on a tilted table (a box, 15°) rolls without slipping at (2/3) g sin θ where μ ≥ tan θ / 3,
// and with μ = 0.05 below that slides at g (sin θ − μ cos θ) while its spin grows at 2 μ g cos θ / r. Its
// contact is the line of its side on the table's face, two points from one query. Within 1 % after 1 s
// (the closed forms of docs/references.md §4, as on a half-space).
TEST(FaceManifolds, ACylinderOnATiltedTableRollsOrSlidesAtTheClosedForms) {
  const double theta = 15.0 * kPi / 180.0, radius = 0.05, length = 0.2, t = 1.0;
  const Eigen::Quaterniond incline(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d down_slope = incline * Eigen::Vector3d::UnitX(), normal = incline * Eigen::Vector3d::UnitZ();
  for (double mu : {0.5, 0.05}) {
    CollisionShape slope = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(4.0, 2.0, 0.2), mu, 0.0);
    slope.pose.linear() = incline.toRotationMatrix();
    slope.pose.translation() = incline * Eigen::Vector3d(0.0, 0.0, -0.1);
    const Eigen::Vector3d start = -1.5 * down_slope + radius * normal;
    // The cylinder's axis (its z) along the table's y: level, across the slope.
    const Eigen::Quaterniond q = incline * Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
    Scene scene = sceneOf({slope}, {reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(radius, length, 0), mu, 0)},
                          {MassProperties::cylinder(1.0, radius, length)}, {pose(start, q)});
    scene.step(static_cast<std::int64_t>(std::llround(t / 1e-3)));
    const State& s = scene.state(0);
    const bool rolls = mu >= std::tan(theta) / 3.0;
    const double a = rolls ? 2.0 / 3.0 * kG * std::sin(theta) : kG * (std::sin(theta) - mu * std::cos(theta));
    const double travelled = (s.p_WB - start).dot(down_slope);
    EXPECT_NEAR(travelled, 0.5 * a * t * t, 0.01 * 0.5 * a * t * t) << "mu " << mu;
    EXPECT_LE(std::abs((s.p_WB - start).dot(normal)), 2e-4) << "mu " << mu << ": left the face";
    const Eigen::Vector3d w_W = s.q_WB * (MassProperties::cylinder(1.0, radius, length).inverseInertia() * (s.q_WB.conjugate() * s.L_W));
    const double spin = std::abs(w_W.dot(incline * Eigen::Vector3d::UnitY()));
    const double expected_spin = rolls ? a * t / radius : 2.0 * mu * kG * std::cos(theta) / radius * t;
    EXPECT_NEAR(spin, expected_spin, 0.01 * expected_spin) << "mu " << mu;
  }
}

// A hexagonal hull pushed at 1 m/s along a diagonal of a flat table, μ = 0.4, slides to a stop after
// v₀²/(2 μ g) (0.5 %, as the box's test), on its line (its four points share μ M g between them, whatever
// the share, as long as they all slide the same way).
TEST(FaceManifolds, AHullSlidesToAStopAtTheClosedFormOnItsLine) {
  const double mu = 0.4, v0 = 1.0;
  CollisionShape prism = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), mu, 0);
  prism.mesh = hexagonalPrism();
  CollisionShape floor = reference::collisionShape(ShapeType::kBox, Eigen::Vector3d(3.0, 3.0, 0.2), mu, 0.0);
  floor.pose.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  const Eigen::Vector3d direction(std::cos(0.7), std::sin(0.7), 0.0);
  const Eigen::Vector3d start(-0.2, -0.1, 0.04);
  Scene scene = sceneOf({floor}, {prism}, {MassProperties::box(1.0, Eigen::Vector3d(0.17, 0.17, 0.08))},
                        {pose(start, Eigen::Quaterniond(Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitZ())))}, v0 * direction);
  scene.step(600);  // more than twice the stop time v₀/(μ g) = 0.255 s
  const Eigen::Vector3d moved = scene.state(0).p_WB - start;
  const double stop = v0 * v0 / (2.0 * mu * kG);
  EXPECT_NEAR(moved.dot(direction), stop, 0.005 * stop);
  EXPECT_LE(std::abs(moved.x() * direction.y() - moved.y() * direction.x()), 0.01 * stop);
  EXPECT_LE(scene.state(0).P_W.norm(), 1e-9);
}

// Five cylinders standing on each other's ends (each end's rim against the next end's rim: two polygons
// clipped) stand for 5 s: the top one within 1 mm of where it started, as the stack of boxes is asked.
TEST(FaceManifolds, AStackOfStandingCylindersStands) {
  const double radius = 0.05, length = 0.1;
  std::vector<CollisionShape> shapes;
  std::vector<MassProperties> masses;
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 5; ++i) {
    shapes.push_back(reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(radius, length, 0), 0.5, 0));
    masses.push_back(MassProperties::cylinder(1.0, radius, length));
    poses.push_back(pose(Eigen::Vector3d(0.01 * i, 0.0, 0.5 * length + length * i), Eigen::Quaterniond(Eigen::AngleAxisd(0.4 * i, Eigen::Vector3d::UnitZ()))));
  }
  Scene scene = sceneOf({table()}, shapes, masses, poses);
  scene.step(5000);
  EXPECT_LE((scene.state(4).p_WB - poses[4].translation()).norm(), 1e-3);
}

// A body dropped flat onto the table's face lands on its whole face at once: the located impact takes every
// point of the patch (docs/contact.md, step 3), and for a cylinder on its end, a hexagonal hull on its
// hexagon and a capsule lying level, all symmetric about the centre of mass, the impulses add up to no
// torque. So it bounces straight up (e = 0.5: to e² of its drop height, as the ball of §4.1) without turning
// (an off-centre impulse of one point at the rim would spin it at ~ v r M / I: rad/s). Dropped from
// 0.2 m, followed to the top of its first bounce.
TEST(FaceManifolds, BodiesDroppedFlatBounceStraightUpWithoutTurning) {
  CollisionShape prism = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0.5);
  prism.mesh = hexagonalPrism();
  const Eigen::Vector3d diagonal(std::cos(0.6), std::sin(0.6), 0.0);
  struct Case {
    std::string name;
    CollisionShape shape;
    MassProperties mass;
    Eigen::Quaterniond q;
    double height;  // of the centre above the face when touching
  };
  const std::vector<Case> cases = {
      {"cylinder on its end", reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(0.05, 0.2, 0), 0.5, 0.5),
       MassProperties::cylinder(1.0, 0.05, 0.2), Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())), 0.1},
      {"hexagonal hull", prism, MassProperties::box(1.0, Eigen::Vector3d(0.17, 0.17, 0.08)),
       Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())), 0.04},
      {"capsule lying", reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(0.03, 0.3, 0), 0.5, 0.5),
       MassProperties::cylinder(1.0, 0.03, 0.36), Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), diagonal), 0.03},
  };
  const double drop = 0.2, e = 0.5;
  for (const Case& c : cases) {
    CollisionShape floor = table();
    floor.material.restitution = e;
    const Eigen::Vector3d start(0.1, -0.05, c.height + drop);
    Scene scene = sceneOf({floor}, {c.shape}, {c.mass}, {pose(start, c.q)});
    double previous_vz = 0.0, apex = 0.0;
    for (int i = 0; i < 2000; ++i) {
      scene.step(1);
      const double vz = scene.state(0).P_W.z();
      if (previous_vz > 0.0 && vz <= 0.0) {
        apex = scene.state(0).p_WB.z() - c.height + vz * vz / (2.0 * kG);
        break;
      }
      previous_vz = vz;
    }
    const State& s = scene.state(0);
    EXPECT_NEAR(apex, e * e * drop, 1e-6 * drop) << c.name;
    EXPECT_LE(s.L_W.norm(), 1e-9) << c.name << " turns";
    EXPECT_LE((s.p_WB - start).head<2>().norm(), 1e-9) << c.name << " moved sideways";
  }
}

namespace {

// How far a point (in the shape's frame) lies outside the exact shape: > 0 outside, < 0 inside [m]. The
// hexagonal prism by its eight planes (apothem 0.1 cos 30°).
double outside(const CollisionShape& shape, const Eigen::Vector3d& p) {
  const Eigen::Vector3d& s = shape.size;
  switch (shape.type) {
    case ShapeType::kBox:
      return (p.cwiseAbs() - 0.5 * s).maxCoeff();
    case ShapeType::kCylinder:
      return std::max(p.head<2>().norm() - s.x(), std::abs(p.z()) - 0.5 * s.y());
    case ShapeType::kCapsule:
      return Eigen::Vector3d(p.x(), p.y(), std::max(0.0, std::abs(p.z()) - 0.5 * s.y())).norm() - s.x();
    default: {
      double worst = std::abs(p.z()) - 0.04;
      for (int k = 0; k < 6; ++k) {
        const double phi = (k + 0.5) * kPi / 3.0;
        worst = std::max(worst, p.x() * std::cos(phi) + p.y() * std::sin(phi) - 0.1 * std::cos(kPi / 6.0));
      }
      return worst;
    }
  }
}

}  // namespace

// Two thousand pairs of a box, cylinder, capsule or hexagonal hull (not two boxes), turned at random, of
// sizes from a centimetre to a few metres, placed touching or up to a third into each other: every point the detection
// gives is finite, with a unit normal, a distance within the reach, and witness points on the two shapes'
// surfaces (no point outside either shape, none deeper inside than the rounding a collision margin makes,
// 4 mm, plus the depth), to EPA's accuracy (1e-4 of the scale). A clipping that put a point off a face, past
// an edge or on the wrong side fails (clipped to the reference face's sides by planes containing its normal
// instead of n, points left a box's face by 1 mm; partners projected onto a plane instead of a capsule's
// segment left a cylinder by 9 cm; a hull's face normals from Bullet's rounded hull put points 0.2 mm out).
TEST(FaceManifolds, RandomPairsGetPointsOnBothSurfaces) {
  std::mt19937 random(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  const auto turn = [&] { return Eigen::Quaterniond(unit(random), unit(random), unit(random), unit(random)).normalized(); };
  CollisionShape prism = reference::collisionShape(ShapeType::kMesh, Eigen::Vector3d::Zero(), 0.5, 0);
  prism.mesh = hexagonalPrism();
  int pairs_with_points = 0;
  for (int k = 0; k < 2000; ++k) {
    const double scale = std::pow(10.0, std::floor(3.0 * fraction(random)) - 1.0);  // 0.1, 1, 10 (the prism: 1)
    std::vector<CollisionShape> shapes;
    int types[2] = {static_cast<int>(4.0 * fraction(random)) % 4, static_cast<int>(4.0 * fraction(random)) % 4};
    if (types[0] == 0 && types[1] == 0) types[1] = 1;  // not two boxes: theirs are Bullet's box–box detector's
    for (int side = 0; side < 2; ++side) {
      const int type = types[side];
      const Eigen::Vector3d size = scale * Eigen::Vector3d(0.1 + 0.2 * fraction(random), 0.1 + 0.3 * fraction(random),
                                                           0.1 + 0.2 * fraction(random));
      if (type == 0) shapes.push_back(reference::collisionShape(ShapeType::kBox, size, 0.5, 0));
      if (type == 1) shapes.push_back(reference::collisionShape(ShapeType::kCylinder, Eigen::Vector3d(size.x(), size.y(), 0), 0.5, 0));
      if (type == 2) shapes.push_back(reference::collisionShape(ShapeType::kCapsule, Eigen::Vector3d(0.5 * size.x(), size.y(), 0), 0.5, 0));
      if (type == 3) shapes.push_back(prism);
    }
    const Eigen::Isometry3d X_B = pose(Eigen::Vector3d::Zero(), turn());
    const Eigen::Vector3d direction = Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized();
    // Along `direction` from B's centre, A's centre where the two bounding spheres are apart by the gap;
    // then brought in until they touch or overlap.
    const double reach = outerRadius(shapes[0]) + outerRadius(shapes[1]);
    Eigen::Isometry3d X_A = pose(reach * direction, turn());
    std::vector<ContactPoint> points;
    const double near = 1e-4;
    for (double along = 1.0; along > 0.3 && points.empty(); along -= 0.01) {
      X_A.translation() = along * reach * direction;
      CollisionWorld world({}, {shapes[0], shapes[1]}, {X_A, X_B});
      world.detect(points, near);
    }
    if (!points.empty()) ++pairs_with_points;
    for (const ContactPoint& p : points) {
      const std::string what = "case " + std::to_string(k) + ": " + shapeTypeName(shapes[0].type) + " on " +
                               shapeTypeName(shapes[1].type) + ", scale " + std::to_string(scale);
      ASSERT_TRUE(p.on_a.allFinite() && p.on_b.allFinite() && p.normal.allFinite() && std::isfinite(p.distance)) << what;
      EXPECT_NEAR(p.normal.norm(), 1.0, 1e-9) << what;
      EXPECT_LE(p.distance, near + 1e-12) << what;
      const Eigen::Isometry3d& X_a = p.a == 0 ? X_A : X_B;
      const Eigen::Isometry3d& X_b = p.a == 0 ? X_B : X_A;
      const CollisionShape& shape_a = shapes[p.a], &shape_b = shapes[p.b];
      // Bullet's EPA places its points to 1e-4 (of its unit, here the shapes' scale); clipped points are exact.
      const double tolerance = 1e-4 * scale, rounding = 0.004 + std::max(0.0, -p.distance);
      const double out_a = outside(shape_a, X_a.inverse() * p.on_a), out_b = outside(shape_b, X_b.inverse() * p.on_b);
      EXPECT_LE(out_a, tolerance) << what << ": a point off a's surface, outside it by " << out_a;
      EXPECT_LE(out_b, tolerance) << what << ": a point off b's surface, outside it by " << out_b;
      EXPECT_GE(out_a, -rounding - tolerance) << what << ": a point " << -out_a << " m inside a";
      EXPECT_GE(out_b, -rounding - tolerance) << what << ": a point " << -out_b << " m inside b";
    }
  }
  EXPECT_GE(pairs_with_points, 1900);  // the search above brings nearly every pair into contact
}
