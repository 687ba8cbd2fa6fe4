#include "rigid_body_sim/ros/markers.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {

// A plane is drawn as a square this wide [m] and this thin [m], centred below the world origin.
constexpr double kPlaneExtent = 20.0;
constexpr double kPlaneThickness = 0.01;
// A contact normal is drawn this long [m]; a contact point this wide [m].
constexpr double kNormalLength = 0.1;
constexpr double kPointSize = 0.02;

std_msgs::ColorRGBA colour(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r, c.g = g, c.b = b, c.a = a;
  return c;
}

// Distinct colours for the bodies, in turn.
std_msgs::ColorRGBA bodyColour(std::size_t body) {
  static const float palette[][3] = {{0.90f, 0.45f, 0.10f}, {0.20f, 0.55f, 0.85f}, {0.30f, 0.70f, 0.30f},
                                     {0.80f, 0.25f, 0.55f}, {0.95f, 0.80f, 0.20f}, {0.50f, 0.35f, 0.80f}};
  const float* c = palette[body % 6];
  return colour(c[0], c[1], c[2]);
}

void setPose(const Eigen::Isometry3d& X, geometry_msgs::Pose& pose) { pose = tf2::toMsg(X); }

// A box with the principal moments of `mass` (the equivalent box of a body given by its inertia alone):
// I₁ = M (b² + c²)/12 …, so a² = 6 (I₂ + I₃ − I₁)/M.
Eigen::Vector3d equivalentBox(const rigid_body::MassProperties& mass) {
  const Eigen::Vector3d& I = mass.principalMoments();
  const double k = 6.0 / mass.mass();
  return Eigen::Vector3d(std::sqrt(std::max(0.0, k * (I.y() + I.z() - I.x()))),
                         std::sqrt(std::max(0.0, k * (I.x() + I.z() - I.y()))),
                         std::sqrt(std::max(0.0, k * (I.x() + I.y() - I.z()))));
}

// A shape's marker type and scale; false for a shape rviz has no primitive for (a mesh without a file).
bool primitive(rigid_body::ShapeType type, const Eigen::Vector3d& size, visualization_msgs::Marker& marker) {
  switch (type) {
    case rigid_body::ShapeType::kBox:
      marker.type = visualization_msgs::Marker::CUBE;
      marker.scale.x = size.x(), marker.scale.y = size.y(), marker.scale.z = size.z();
      return true;
    case rigid_body::ShapeType::kSphere:
      marker.type = visualization_msgs::Marker::SPHERE;
      marker.scale.x = marker.scale.y = marker.scale.z = 2.0 * size.x();
      return true;
    case rigid_body::ShapeType::kCylinder:
      marker.type = visualization_msgs::Marker::CYLINDER;  // rviz's cylinder has its axis along z too
      marker.scale.x = marker.scale.y = 2.0 * size.x(), marker.scale.z = size.y();
      return true;
    case rigid_body::ShapeType::kCapsule:  // drawn as the cylinder that holds it
      marker.type = visualization_msgs::Marker::CYLINDER;
      marker.scale.x = marker.scale.y = 2.0 * size.x(), marker.scale.z = size.y() + 2.0 * size.x();
      return true;
    case rigid_body::ShapeType::kPlane:
    case rigid_body::ShapeType::kMesh:
      return false;
  }
  return false;
}

}  // namespace

Markers::Markers(ros::NodeHandle& nh, const NodeConfig& config) : config_(config) {
  publisher_ = nh.advertise<visualization_msgs::MarkerArray>(
      "markers", 1, [this](const ros::SingleSubscriberPublisher&) { ++subscribers_; },
      [this](const ros::SingleSubscriberPublisher&) { --subscribers_; });
  rebuild();
}

void Markers::bodiesChanged(std::size_t bodies_before) {
  // An id a spawn takes again is drawn, not deleted, by the next publication.
  const int bodies = static_cast<int>(config_.bodies.size());
  removed_ids_.erase(std::remove_if(removed_ids_.begin(), removed_ids_.end(), [bodies](int id) { return id < bodies; }),
                     removed_ids_.end());
  if (config_.bodies.size() == bodies_before + 1) {
    // A spawn appends: its marker goes after the other bodies' (a spawn costs the same in any scene).
    array_.markers.insert(array_.markers.begin() + static_cast<std::ptrdiff_t>(bodies_before),
                          bodyMarker(bodies_before));
    ++contact_points_;
    return;
  }
  // Ids are body indices: after a removal the last ones are free, and rviz keeps a marker until told.
  for (std::size_t id = config_.bodies.size(); id < bodies_before; ++id) removed_ids_.push_back(static_cast<int>(id));
  rebuild();
}

void Markers::rebuild() {
  array_.markers.clear();
  addBodies();
  addEnvironment();
  const NodeConfig& config = config_;
  // Contact points and normals, in the world frame, refilled each time (empty without contact).
  visualization_msgs::Marker points;
  points.header.frame_id = config.world_frame;
  points.ns = "contacts";
  points.id = 0;
  points.type = visualization_msgs::Marker::SPHERE_LIST;
  points.scale.x = points.scale.y = points.scale.z = kPointSize;
  points.color = colour(0.9f, 0.1f, 0.1f);
  points.pose.orientation.w = 1.0;
  visualization_msgs::Marker normals = points;
  normals.id = 1;
  normals.type = visualization_msgs::Marker::LINE_LIST;
  normals.scale.x = 0.2 * kPointSize;
  normals.color = colour(1.0f, 1.0f, 0.1f);
  contact_points_ = array_.markers.size();
  array_.markers.push_back(points);
  array_.markers.push_back(normals);
}

void Markers::addBodies() {
  for (std::size_t body = 0; body < config_.bodies.size(); ++body) array_.markers.push_back(bodyMarker(body));
}

visualization_msgs::Marker Markers::bodyMarker(std::size_t body) const {
  const BodyConfig& b = config_.bodies[body];
  visualization_msgs::Marker marker;
  marker.header.frame_id = b.body_frame;  // it moves with tf: no per-tick pose
  marker.ns = "bodies";
  marker.id = static_cast<int>(body);
  marker.color = bodyColour(body);
  marker.pose.orientation.w = 1.0;
  marker.frame_locked = true;
  if (b.hasShape(rigid_body::ShapeType::kMesh)) {
    // The mesh as its file has it: its own frame sits at X_BM in the body frame, scaled to metres.
    marker.type = visualization_msgs::Marker::MESH_RESOURCE;
    marker.mesh_resource = b.mesh_uri.rfind("package://", 0) == 0 ? b.mesh_uri : "file://" + b.mesh_path;
    marker.scale.x = marker.scale.y = marker.scale.z = b.mesh_scale;
    setPose(b.X_MB.inverse(), marker.pose);
  } else if (b.mass_source == MassSource::kUrdf && (b.visual || !b.visual_mesh.empty())) {
    // The link's <visual>, posed in the link frame, which is the published frame.
    if (b.visual) {
      primitive(b.visual->type, b.visual->size, marker);
      setPose(b.visual->pose, marker.pose);
    } else {
      marker.type = visualization_msgs::Marker::MESH_RESOURCE;
      marker.mesh_resource = b.visual_mesh;
      marker.scale.x = marker.scale.y = marker.scale.z = b.visual_mesh_scale;
      setPose(b.X_PV, marker.pose);
    }
  } else if (b.mass_source != MassSource::kShape) {
    // No shape to draw: the box with the same principal moments, at the centre of mass along the principal
    // axes (in the published frame: X_P,principal = X_BP⁻¹ X_B,principal).
    marker.type = visualization_msgs::Marker::CUBE;
    const Eigen::Vector3d size = equivalentBox(b.model.mass);
    marker.scale.x = size.x(), marker.scale.y = size.y(), marker.scale.z = size.z();
    Eigen::Isometry3d X_B_principal = Eigen::Isometry3d::Identity();
    X_B_principal.linear() = b.model.mass.principalAxes();
    setPose(b.X_BP.inverse() * X_B_principal, marker.pose);
  } else {
    Eigen::Vector3d size = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < b.size.size() && i < 3; ++i) size[static_cast<int>(i)] = b.size[i];
    primitive(b.shape, size, marker);
  }
  return marker;
}

void Markers::addEnvironment() {
  for (std::size_t i = 0; i < config_.environment.size(); ++i) {
    const rigid_body::CollisionShape& shape = config_.environment[i];
    visualization_msgs::Marker marker;
    marker.header.frame_id = config_.world_frame;
    marker.ns = "environment";
    marker.id = static_cast<int>(i);
    marker.color = colour(0.6f, 0.6f, 0.6f, shape.type == rigid_body::ShapeType::kPlane ? 0.6f : 0.8f);
    if (shape.type == rigid_body::ShapeType::kPlane) {
      // A thin square whose top face is the plane n·x = offset.
      marker.type = visualization_msgs::Marker::CUBE;
      marker.scale.x = marker.scale.y = kPlaneExtent, marker.scale.z = kPlaneThickness;
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), shape.normal).toRotationMatrix();
      X.translation() = (shape.offset - 0.5 * kPlaneThickness) * shape.normal;
      setPose(X, marker.pose);
    } else if (shape.type == rigid_body::ShapeType::kMesh) {
      marker.type = visualization_msgs::Marker::TRIANGLE_LIST;  // the triangles as read (no file to point to)
      marker.scale.x = marker.scale.y = marker.scale.z = 1.0;
      for (const auto& t : shape.mesh.triangles) {
        for (int v : t) marker.points.push_back(tf2::toMsg(shape.mesh.vertices[static_cast<std::size_t>(v)]));
      }
      setPose(shape.pose, marker.pose);
    } else {
      primitive(shape.type, shape.size, marker);
      setPose(shape.pose, marker.pose);
    }
    array_.markers.push_back(marker);
  }
}

const visualization_msgs::MarkerArray& Markers::build(const rigid_body::World& world, const ros::Time& stamp) {
  for (visualization_msgs::Marker& marker : array_.markers) marker.header.stamp = stamp;
  visualization_msgs::Marker& points = array_.markers[contact_points_];
  visualization_msgs::Marker& normals = array_.markers[contact_points_ + 1];
  points.points.clear();
  normals.points.clear();
  const rigid_body::Scene& scene = world.scene();
  for (std::size_t body = 0; scene.hasContact() && body < scene.bodyCount(); ++body) {
    for (const rigid_body::Contact& contact : scene.contacts(body)) {
      points.points.push_back(tf2::toMsg(contact.position_W));
      normals.points.push_back(tf2::toMsg(contact.position_W));
      normals.points.push_back(tf2::toMsg(Eigen::Vector3d(contact.position_W + kNormalLength * contact.normal_W)));
    }
  }
  // rviz refuses an empty list: an empty one is deleted (same id) until contacts come back.
  points.action = points.points.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
  normals.action = points.action;
  // The removed bodies' markers, deleted once, after the others.
  array_.markers.resize(contact_points_ + 2);
  for (int id : removed_ids_) {
    visualization_msgs::Marker gone;
    gone.header.frame_id = config_.world_frame;
    gone.header.stamp = stamp;
    gone.ns = "bodies";
    gone.id = id;
    gone.action = visualization_msgs::Marker::DELETE;
    array_.markers.push_back(gone);
  }
  return array_;
}

void Markers::publish(const rigid_body::World& world) {
  if (subscribers_ <= 0) return;
  // On a grid of the marker period in simulated time (OutputSchedule says how a late tick and a rewind go).
  if (!schedule_.due(world.stamp(), rigid_body::toNanoseconds(1.0 / config_.marker_rate))) return;
  publisher_.publish(build(world, toRosTime(world.stamp())));
  removed_ids_.clear();
}

}  // namespace rigid_body_ros
