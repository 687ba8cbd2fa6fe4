#include "face_manifold.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace rigid_body {
namespace contact {

namespace {

// Two segments (a capsule's or a cylinder's side on another's) make a line contact only where they are
// parallel: within the face angle, |d_a × d_b| ≤ sin 10°.
constexpr double kFaceAngleSine = 0.17364817766693034885;

// How far outside the reference face's sides an incident vertex may lie and still count as inside, as a
// share of the reference face's size. Two faces of the same outline resting on each other (a stack of equal
// boxes) have their sides within rounding of each other: clipped exactly, an incident side that crosses a
// reference side at an angle of rounding's order meets it anywhere along its length, and the point made there
// jumps by millimetres from step to step and loses its warm start (Bullet's box–box detector, which clips
// exactly, did so to a tower of 1 m cubes at h = 10 ms, which collapsed after 8 s at rest). Within the
// margin the incident corner is kept as it is (at most the margin beyond the reference's side).
constexpr double kClipMargin = 1e-9;

// How much better than rounding a later point must be to be kept instead (keepFourPoints), as a share of
// the points' spread.
constexpr double kChoiceTolerance = 1e-9;

// A clipped incident point p and its partner q on the reference face made into a contact point, apart by
// `distance` along n (from b towards a); kept where that is within max_distance.
void addClippedPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double distance, const Eigen::Vector3d& n,
                     bool reference_is_b, double max_distance, const ContactPoint& pair, std::vector<ContactPoint>& points) {
  if (!(distance <= max_distance)) return;
  ContactPoint point = pair;
  point.normal = n;
  point.feature = -1;
  point.on_a = reference_is_b ? p : q;
  point.on_b = reference_is_b ? q : p;
  point.distance = distance;
  points.push_back(point);
}

// Sutherland–Hodgman: keeps the part of `polygon` (closed) or of a segment (`closed` false, two points)
// with s·x ≤ offset, a vertex beyond it by no more than `margin` (in units of s·x) kept as it is. An edge
// from a vertex within to one beyond is cut where it meets the plane, when that lies on the edge (not when
// the vertex within is itself in the margin).
void clipAgainstPlane(const std::vector<Eigen::Vector3d>& in, std::vector<Eigen::Vector3d>& out, const Eigen::Vector3d& s,
                      double offset, double margin, bool closed) {
  out.clear();
  const std::size_t count = in.size();
  if (count == 0) return;
  const std::size_t edges = closed ? count : count - 1;
  if (!closed && s.dot(in[0]) - offset <= margin) out.push_back(in[0]);
  for (std::size_t e = 0; e < edges; ++e) {
    const Eigen::Vector3d& from = in[e];
    const Eigen::Vector3d& to = in[(e + 1) % count];
    const double d_from = s.dot(from) - offset, d_to = s.dot(to) - offset;
    if ((d_from <= margin) != (d_to <= margin)) {
      const double t = d_from / (d_from - d_to);
      if (t >= 0.0 && t <= 1.0) out.push_back(from + t * (to - from));
    }
    if (d_to <= margin) out.push_back(to);
  }
}

}  // namespace

bool clipFaces(const SupportFace& face_a, const SupportFace& face_b, const Eigen::Vector3d& n, double max_distance,
               const ContactPoint& pair, std::vector<ContactPoint>& points) {
  const std::size_t count_a = face_a.vertices.size(), count_b = face_b.vertices.size();
  if (count_a < 2 || count_b < 2) return false;
  // The reference: the polygon nearer to normal to n (a's face looks along −n, b's along n).
  const double along_a = count_a >= 3 ? -face_a.normal.dot(n) : -1.0;
  const double along_b = count_b >= 3 ? face_b.normal.dot(n) : -1.0;
  bool reference_is_b = true;
  Eigen::Vector3d m = n;  // the reference plane's outward normal
  if (count_a >= 3 || count_b >= 3) {
    reference_is_b = along_b >= along_a;
    if (std::max(along_a, along_b) < kFaceAngleCosine) return false;
    m = reference_is_b ? face_b.normal : face_a.normal;
  } else {
    const Eigen::Vector3d d_a = (face_a.vertices[1] - face_a.vertices[0]).normalized();
    const Eigen::Vector3d d_b = (face_b.vertices[1] - face_b.vertices[0]).normalized();
    if (!(d_a.cross(d_b).norm() <= kFaceAngleSine)) return false;
  }
  const SupportFace& reference = reference_is_b ? face_b : face_a;
  const SupportFace& incident = reference_is_b ? face_a : face_b;
  thread_local std::vector<Eigen::Vector3d> clipped, scratch;
  clipped = incident.vertices;
  const bool closed = incident.vertices.size() >= 3;
  const std::vector<Eigen::Vector3d>& r = reference.vertices;
  double size = 0.0;  // the reference's largest extent from its first vertex
  for (const Eigen::Vector3d& v : r) size = std::max(size, (v - r[0]).norm());
  const double margin = kClipMargin * size;
  if (r.size() >= 3) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& v : r) centroid += v;
    centroid /= static_cast<double>(r.size());
    // The side planes contain n (not the face's normal m): each point kept is then one whose shadow along n
    // on the reference plane, where its partner lies, falls inside the reference face.
    for (std::size_t e = 0; e < r.size() && !clipped.empty(); ++e) {
      const Eigen::Vector3d& v0 = r[e];
      Eigen::Vector3d side = (r[(e + 1) % r.size()] - v0).cross(n);
      if (side.dot(centroid - v0) > 0.0) side = -side;  // outward from the face's interior
      clipAgainstPlane(clipped, scratch, side, side.dot(v0), margin * side.norm(), closed);
      std::swap(clipped, scratch);
    }
  } else {  // a segment: the slab between the planes across it at its ends (containing n, as above)
    const Eigen::Vector3d along = (r[1] - r[0]) - (r[1] - r[0]).dot(n) * n;
    clipAgainstPlane(clipped, scratch, -along, -along.dot(r[0]), margin * along.norm(), closed);
    clipAgainstPlane(scratch, clipped, along, along.dot(r[1]), margin * along.norm(), closed);
  }
  const std::size_t first = points.size();
  const Eigen::Vector3d along = (r[1] - r[0]).normalized();  // a reference segment's direction
  for (const Eigen::Vector3d& p : clipped) {
    if (r.size() >= 3) {  // the partner: p moved along n onto the reference plane (through r[0], normal m)
      const double t = (p - r[0]).dot(m) / n.dot(m);
      addClippedPoint(p, p - t * n, reference_is_b ? t : -t, n, reference_is_b, max_distance, pair, points);
    } else {  // two segments (the reference is b's): the partner is the reference segment's point across
      const Eigen::Vector3d q = r[0] + (p - r[0]).dot(along) * along;
      addClippedPoint(p, q, (p - q).dot(n), n, true, max_distance, pair, points);
    }
  }
  if (points.size() == first) return false;
  keepFourPoints(points, first);
  return true;
}

void keepFourPoints(std::vector<ContactPoint>& points, std::size_t first) {
  const std::size_t count = points.size() - first;
  if (count <= 4) return;
  auto at = [&](std::size_t i) -> const Eigen::Vector3d& { return points[first + i].on_b; };
  // Each choice goes to a later point only if it is better by more than rounding: a face resting flat has
  // its points at one depth to rounding, and a twisted square on a square an octagon of nearly equal
  // diagonals, and a choice that rounding flips from step to step changes the face's points and loses
  // their warm starts (a twisted tower at h = 10 ms rocked by 60 mm).
  double spread = 0.0;
  for (std::size_t i = 1; i < count; ++i) spread = std::max(spread, (at(i) - at(0)).norm());
  const double length_tolerance = kChoiceTolerance * spread;
  std::array<std::size_t, 4> kept{};
  // The deepest.
  kept[0] = 0;
  for (std::size_t i = 1; i < count; ++i) {
    if (points[first + i].distance < points[first + kept[0]].distance - length_tolerance) kept[0] = i;
  }
  // The farthest from it.
  kept[1] = kept[0];
  for (std::size_t i = 0; i < count; ++i) {
    if ((at(i) - at(kept[0])).norm() > (at(kept[1]) - at(kept[0])).norm() + length_tolerance) kept[1] = i;
  }
  // The largest triangle with those two.
  const Eigen::Vector3d edge = at(kept[1]) - at(kept[0]);
  const double area_tolerance = length_tolerance * edge.norm();
  kept[2] = kept[0];
  double largest = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double area = edge.cross(at(i) - at(kept[0])).norm();
    if (area > largest + area_tolerance) largest = area, kept[2] = i;
  }
  std::size_t kept_count = largest > 0.0 ? 3 : (kept[1] != kept[0] ? 2 : 1);  // 1: the points coincide
  // The most area added beyond the triangle: outside one of its edges, the triangle that edge makes with it.
  if (kept_count == 3) {
    const Eigen::Vector3d normal = edge.cross(at(kept[2]) - at(kept[0])).normalized();
    double gain = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      for (int e = 0; e < 3; ++e) {
        const Eigen::Vector3d& from = at(kept[e]);
        const Eigen::Vector3d& to = at(kept[(e + 1) % 3]);
        const double outside = -(to - from).cross(at(i) - from).dot(normal);
        if (outside > gain + area_tolerance) gain = outside, kept[3] = i;
      }
    }
    if (gain > 0.0) kept_count = 4;
  }
  std::array<ContactPoint, 4> chosen;
  for (std::size_t k = 0; k < kept_count; ++k) chosen[k] = points[first + kept[k]];
  points.resize(first);
  for (std::size_t k = 0; k < kept_count; ++k) points.push_back(chosen[k]);
}

}  // namespace contact
}  // namespace rigid_body
