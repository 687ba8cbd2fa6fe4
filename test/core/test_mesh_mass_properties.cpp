// Mass properties from meshes: the exact method against closed forms, sampling's 1/√N convergence, the
// bounding box's known ratio on a sphere, and every way a mesh can be unusable.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <utility>
#include <vector>

#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/mesh_mass_properties.hpp"
#include "rigid_body_sim/mesh_primitives.hpp"
#include "rigid_body_sim/references.hpp"

using namespace rigid_body;

namespace {

const std::string kMeshes = TEST_MESH_DIR;

MeshMassProperties exactOf(const TriangleMesh& mesh, double mass = 2.0) {
  MeshMassOptions options;
  options.mass = mass;
  return meshMassProperties(mesh, options);
}

double relativeError(const Eigen::Matrix3d& actual, const Eigen::Matrix3d& expected) {
  return (actual - expected).norm() / expected.norm();
}

}  // namespace

TEST(MeshMassProperties, ExactBoxEqualsTheClosedFormInEveryFormat) {
  const Eigen::Vector3d size(0.4, 0.2, 0.1);
  const Eigen::Matrix3d expected = MassProperties::box(2.0, size).inertia();
  for (const TriangleMesh& mesh : {primitives::box(size), loadMesh(kMeshes + "/box.obj"), loadMesh(kMeshes + "/box_ascii.stl")}) {
    const MeshMassProperties p = exactOf(mesh);
    EXPECT_NEAR(p.volume, 0.008, 1e-15);
    EXPECT_LT(p.p_MBcm.norm(), 1e-15);
    EXPECT_LT(relativeError(p.I_Bcm_M, expected), 1e-12);
  }
  // A binary STL stores float32 corners: exact for that polyhedron, 1e-7 from the double box.
  EXPECT_LT(relativeError(exactOf(loadMesh(kMeshes + "/box_binary.stl")).I_Bcm_M, expected), 1e-6);
}

TEST(MeshMassProperties, ExactTetrahedronEqualsTheCovarianceFormula) {
  // ∫ r rᵀ dV = V/20 (Σ vᵢvᵢᵀ + s sᵀ), s = Σ vᵢ: an independent closed form (Tonon 2004).
  const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  const double volume = 1.0, density = 3.0;  // |det[v1 v2 v3]|/6 = 6/6
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const auto& p : v) s += p, sum += p * p.transpose();
  const Eigen::Matrix3d C = density * volume / 20.0 * (sum + s * s.transpose());
  const Eigen::Matrix3d I_origin = C.trace() * Eigen::Matrix3d::Identity() - C;
  const double mass = density * volume;
  const Eigen::Vector3d c = s / 4.0;
  const Eigen::Matrix3d expected = I_origin - mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  MeshMassOptions options;
  options.density = density;
  const MeshMassProperties p = meshMassProperties(loadMesh(kMeshes + "/tetrahedron.obj"), options);
  EXPECT_NEAR(p.mass, mass, 1e-14);
  EXPECT_LT((p.p_MBcm - c).norm(), 1e-15);
  EXPECT_LT(relativeError(p.I_Bcm_M, expected), 1e-12);
}

TEST(MeshMassProperties, MovingTheMeshMovesTheCentreAndTurnsTheTensor) {
  const TriangleMesh bracket = primitives::lBracket(0.1, 0.02, 0.005);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(Eigen::Vector3d(1.0, -2.0, 0.5));
  X.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const MeshMassProperties here = exactOf(bracket), there = exactOf(transformed(bracket, 1.0, X));
  EXPECT_LT((there.p_MBcm - X * here.p_MBcm).norm(), 1e-12);
  EXPECT_LT(relativeError(there.I_Bcm_M, X.linear() * here.I_Bcm_M * X.linear().transpose()), 1e-12);
  // Scaling by s: I ∝ m s² at equal mass.
  EXPECT_LT(relativeError(exactOf(transformed(bracket, 3.0)).I_Bcm_M, 9.0 * here.I_Bcm_M), 1e-12);
}

TEST(MeshMassProperties, LBracketEqualsTwoBoxesByTheParallelAxisTheorem) {
  const double density = 2700.0;
  const reference::SolidMassProperties expected = reference::lBracket(density, 0.1, 0.02, 0.005);
  MeshMassOptions options;
  options.density = density;
  const MeshMassProperties p = meshMassProperties(loadMesh(kMeshes + "/l_bracket.obj"), options);
  EXPECT_NEAR(p.mass, expected.mass, 1e-12 * expected.mass);
  EXPECT_LT((p.p_MBcm - expected.centre).norm(), 1e-15);
  EXPECT_LT(relativeError(p.I_Bcm_M, expected.inertia), 1e-12);
  EXPECT_GT(std::abs(p.I_Bcm_M(0, 1)), 1e-3 * p.I_Bcm_M(0, 0));  // a real product of inertia
}

TEST(MeshMassProperties, IcosphereConvergesToTheSphere) {
  const Eigen::Matrix3d sphere = MassProperties::sphere(2.0, 0.5).inertia();
  double previous = 1.0;
  for (int level = 1; level <= 4; ++level) {
    const double error = relativeError(exactOf(primitives::icosphere(0.5, level)).I_Bcm_M, sphere);
    EXPECT_LT(error, previous / 3.0) << level;  // the polyhedron closes in on the sphere (~4× per level)
    previous = error;
  }
  EXPECT_LT(previous, 1e-2);
}

TEST(MeshMassProperties, CylinderPrismConvergesAsOneOverNSquared) {
  const Eigen::Matrix3d cylinder = MassProperties::cylinder(2.0, 0.1, 0.4).inertia();
  const double e16 = relativeError(exactOf(primitives::cylinder(0.1, 0.4, 16)).I_Bcm_M, cylinder);
  const double e64 = relativeError(exactOf(primitives::cylinder(0.1, 0.4, 64)).I_Bcm_M, cylinder);
  EXPECT_NEAR(e16 / e64, 16.0, 1.0);  // (64/16)²
  EXPECT_LT(e64, 1e-3);
}

TEST(MeshMassProperties, SamplingConvergesAsOneOverSqrtN) {
  const TriangleMesh bracket = loadMesh(kMeshes + "/l_bracket.obj");
  const Eigen::Matrix3d exact = exactOf(bracket).I_Bcm_M;
  MeshMassOptions options;
  options.method = InertiaMethod::kSampling;
  options.mass = 2.0;
  options.seed = 7;
  double previous_se = 0.0;
  for (std::uint64_t n : {2000u, 20000u, 200000u}) {
    options.samples = n;
    const MeshMassProperties p = meshMassProperties(bracket, options);
    const double error = (p.I_Bcm_M - exact).norm();
    EXPECT_LT(error, 4.0 * p.inertia_standard_error) << n;  // the reported standard error is honest
    if (previous_se > 0.0) {
      EXPECT_NEAR(previous_se / p.inertia_standard_error, std::sqrt(10.0), 0.6) << n;
    }
    previous_se = p.inertia_standard_error;
  }
  // Same seed, same result.
  options.samples = 2000;
  EXPECT_EQ(meshMassProperties(bracket, options).I_Bcm_M, meshMassProperties(bracket, options).I_Bcm_M);
}

TEST(MeshMassProperties, BoundingBoxOfASphereIsFiveThirdsOfIt) {
  // A sphere of radius r in its bounding cube of side 2r: (M/12)(8r²) / ((2/5) M r²) = 5/3.
  MeshMassOptions options;
  options.method = InertiaMethod::kBoundingBox;
  options.mass = 2.0;
  const MeshMassProperties box = meshMassProperties(primitives::icosphere(0.5, 4), options);
  const Eigen::Matrix3d sphere = MassProperties::sphere(2.0, 0.5).inertia();
  EXPECT_NEAR(box.I_Bcm_M(0, 0) / sphere(0, 0), 5.0 / 3.0, 0.02);
  EXPECT_NEAR(box.I_Bcm_M(2, 2) / sphere(2, 2), 5.0 / 3.0, 0.02);
  // The oriented box of a long, turned box is the box itself; the axis-aligned one overestimates.
  Eigen::Isometry3d turn = Eigen::Isometry3d(Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()));
  const TriangleMesh turned = transformed(primitives::box(Eigen::Vector3d(0.4, 0.1, 0.05)), 1.0, turn);
  options.method = InertiaMethod::kOrientedBoundingBox;
  const Eigen::Matrix3d exact = exactOf(turned).I_Bcm_M;
  EXPECT_LT(relativeError(meshMassProperties(turned, options).I_Bcm_M, exact), 1e-9);
  options.method = InertiaMethod::kBoundingBox;
  EXPECT_GT(relativeError(meshMassProperties(turned, options).I_Bcm_M, exact), 0.1);
}

TEST(MeshMassProperties, PrincipalAxesGiveADiagonalTensorAndTheFrameToFindIt) {
  const MeshMassProperties p = exactOf(loadMesh(kMeshes + "/l_bracket.obj"));
  const MeshBody body = meshBody(p, true);
  const Eigen::Matrix3d& I_B = body.mass.inertia();
  EXPECT_LT(std::abs(I_B(0, 1)) + std::abs(I_B(0, 2)) + std::abs(I_B(1, 2)), 1e-12 * I_B.norm());
  const Eigen::Matrix3d R_MB = body.X_MB.linear();
  EXPECT_NEAR(R_MB.determinant(), 1.0, 1e-12);
  EXPECT_LT(relativeError(R_MB * I_B * R_MB.transpose(), p.I_Bcm_M), 1e-12);
  EXPECT_EQ(body.X_MB.translation(), p.p_MBcm);
  // Without principal axes: the mesh's own axes, the same tensor.
  EXPECT_LT(relativeError(meshBody(p, false).mass.inertia(), p.I_Bcm_M), 1e-15);
}

TEST(MeshMassProperties, EveryMethodGivesAPhysicalTensor) {
  for (InertiaMethod method : {InertiaMethod::kExact, InertiaMethod::kSampling, InertiaMethod::kBoundingBox,
                               InertiaMethod::kOrientedBoundingBox}) {
    MeshMassOptions options;
    options.method = method;
    options.mass = 1.0;
    options.samples = 5000;
    for (const char* name : {"/l_bracket.obj", "/ring.obj", "/sphere.stl"}) {
      EXPECT_NO_THROW(meshBody(meshMassProperties(loadMesh(kMeshes + name), options), true))
          << inertiaMethodName(method) << name;
    }
  }
}

TEST(MeshErrors, BrokenMeshesGiveClearErrors) {
  const auto message = [](const std::string& file) -> std::string {
    try {
      exactOf(loadMesh(kMeshes + file));
    } catch (const MeshError& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(message("/open_box.obj").find("mesh is not closed: 3 edges belong to one triangle only"), std::string::npos)
      << message("/open_box.obj");
  EXPECT_NE(message("/one_flipped_box.obj").find("not consistently oriented"), std::string::npos)
      << message("/one_flipped_box.obj");
  EXPECT_NE(message("/broken.stl").find("too short to be an STL"), std::string::npos) << message("/broken.stl");
  EXPECT_NE(message("/no_such_file.stl").find("cannot open mesh file"), std::string::npos);
  TriangleMesh flat = primitives::box(Eigen::Vector3d(1, 1, 1));
  for (auto& p : flat.vertices) p.z() = 0.0;  // closed, but encloses nothing
  try {
    exactOf(flat);
    FAIL() << "expected MeshError";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("encloses no volume"), std::string::npos) << error.what();
  }
}

// Every class of malformed input the readers can meet, written to a temporary file: each must give a
// MeshError that says what is wrong, never a crash, an out-of-range read or a hang.
TEST(MeshErrors, SamplingBeyondItsTestBudgetIsRefusedBeforeItStarts) {
  // sphere.stl has 1 280 triangles: 1 562 500 samples are 2e9 ray-triangle tests, the limit; one more is over.
  const TriangleMesh sphere = loadMesh(kMeshes + "/sphere.stl");
  ASSERT_EQ(sphere.triangles.size(), 1280u);
  MeshMassOptions options;
  options.method = InertiaMethod::kSampling;
  options.mass = 1.0;
  options.samples = kMaxSamplingTests / 1280;
  EXPECT_EQ(samplingTests(1280, options), kMaxSamplingTests);
  options.samples += 1;
  EXPECT_GT(samplingTests(1280, options), kMaxSamplingTests);
  try {
    meshMassProperties(sphere, options);
    ADD_FAILURE() << "sampling over its budget ran";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("1562501 samples on 1280 triangles"), std::string::npos) << error.what();
  }
  options.samples = std::numeric_limits<std::uint64_t>::max();  // saturates, no overflow
  EXPECT_EQ(samplingTests(1280, options), std::numeric_limits<std::uint64_t>::max());
  options.stratified = true;
  options.samples = 1000;  // a 10³ grid
  EXPECT_EQ(samplingTests(1280, options), 1280000u);
}

TEST(MeshErrors, MalformedFilesOfEveryClassAreRefusedWithAMessage) {
  const std::string directory = ::testing::TempDir();
  const auto message = [&](const std::string& name, const std::string& content) -> std::string {
    const std::string path = directory + "/" + name;
    std::ofstream(path, std::ios::binary) << content;
    try {
      loadMesh(path);
    } catch (const MeshError& error) {
      return error.what();
    }
    return "(no error)";
  };
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  const std::vector<std::pair<std::string, std::string>> objs = {
      {vertices + "f 1 2 x\n", "is not a vertex index"},
      {vertices + "f 1 2 3.5\n", "is not a vertex index"},
      {vertices + "f 1 2 99999999999999999999\n", "is not a vertex index"},  // beyond int64
      {vertices + "f 1 2 2147483648\n", "names no vertex"},                  // beyond int, and past the end
      {vertices + "f 0 1 2\n", "names no vertex"},                           // OBJ counts from 1
      {vertices + "f 1 2 5\n", "names no vertex"},                           // one past the last
      {vertices + "f -5 1 2\n", "names no vertex"},                          // relative, before the first
      {vertices + "f -9223372036854775808 1 2\n", "names no vertex"},
      {"f 1 2 3\n" + vertices, "names no vertex"},                           // before any vertex
      {vertices + "f /1 2 3\n", "is not a vertex index"},
      {vertices + "f 1 2\n", "a face with < 3 vertices"},
      {"v 0 0\n", "bad vertex"},
      {"v 0 0 nan\n", "bad vertex"},
      {vertices, "has no faces"},
  };
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const std::string got = message("case" + std::to_string(i) + ".obj", objs[i].first);
    EXPECT_NE(got.find(objs[i].second), std::string::npos) << "case " << i << ": " << got;
  }
  // Relative indices that do name vertices are fine: the last three.
  EXPECT_EQ(message("relative.obj", vertices + "f -1 -2 -3\nf 1 2 3\nf 1 2 4\nf 1 3 4\n").find("names no vertex"),
            std::string::npos);
  // A binary STL whose count does not match its size, one with a NaN corner, an ASCII STL cut short.
  std::string binary(84, '\0');
  binary[80] = 5;  // says 5 triangles, has none
  EXPECT_NE(message("count.stl", binary).find("is not a valid binary STL"), std::string::npos);
  std::string nan_corner(84 + 50, '\0');
  nan_corner[80] = 1;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan_corner[84 + 12], &nan, sizeof nan);
  EXPECT_NE(message("nan.stl", nan_corner).find("not a finite number"), std::string::npos);
  EXPECT_NE(message("cut.stl", "solid x\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0\n")
                .find("a vertex line without three numbers"),
            std::string::npos);
  EXPECT_NE(message("unknown.ply", "ply\n").find("unknown mesh format"), std::string::npos);
  // Not regular files (a directory, an endless device behind a mesh's name), and a file over the size limit.
  const std::string folder = directory + "/folder.stl", zero = directory + "/zero.stl";
  std::filesystem::create_directory(folder);
  std::filesystem::remove(zero);
  std::filesystem::create_symlink("/dev/zero", zero);
  for (const std::string& path : {folder, zero}) {
    try {
      loadMesh(path);
      FAIL() << "expected MeshError for " << path;
    } catch (const MeshError& error) {
      EXPECT_NE(std::string(error.what()).find("is not a regular file"), std::string::npos) << error.what();
    }
  }
  try {
    loadMesh(kMeshes + "/sphere.stl", 1000);
    FAIL() << "expected MeshError";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("more than the limit of 1000"), std::string::npos) << error.what();
  }
}

TEST(MeshErrors, AnInsideOutMeshIsFlippedWithAWarning) {
  const MeshMassProperties p = exactOf(loadMesh(kMeshes + "/inside_out_box.obj"));
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_NE(p.warnings[0].find("inside out"), std::string::npos);
  EXPECT_GT(p.volume, 0.0);
  EXPECT_LT(relativeError(p.I_Bcm_M, MassProperties::box(2.0, Eigen::Vector3d(0.4, 0.2, 0.1)).inertia()), 1e-12);
}
