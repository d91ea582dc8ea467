#include "geometry/paper_bodies.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::geometry {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kPi = 3.14159265358979323846;

// sums of ~10² terms of size ≤ 1: a few hundred ulps
constexpr double kRoundOff = 1e-12;

void ExpectSolid(const TriangleMesh& mesh) {
  const MeshTopology t = AnalyzeTopology(mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.consistently_oriented);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
}

double MinCoordinate(const TriangleMesh& mesh, int axis) {
  double lowest = HUGE_VAL;
  for (const Eigen::Vector3d& v : mesh.vertices) lowest = std::min(lowest, v[axis]);
  return lowest;
}

double MaxCoordinate(const TriangleMesh& mesh, int axis) {
  double highest = -HUGE_VAL;
  for (const Eigen::Vector3d& v : mesh.vertices) highest = std::max(highest, v[axis]);
  return highest;
}

// total area of the triangles lying in the plane z = 0 (the contact patch with the ground)
double AreaOnGround(const TriangleMesh& mesh) {
  double area = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    if (a.z() == 0 && b.z() == 0 && c.z() == 0) {
      const Eigen::Vector3d n = (b - a).cross(c - a);
      EXPECT_LT(n.z(), 0.0);  // the ground faces point down, out of the body
      area += 0.5 * n.norm();
    }
  }
  return area;
}

TEST(PaperBodiesTest, DeskIsASolidWithItsCentreOfMassAtTheGivenHeight) {
  const TriangleMesh desk = MakeDeskMesh();
  ExpectSolid(desk);
  const MassProperties p = ComputeMassPropertiesForMass(desk, 15.0, "desk");
  EXPECT_NEAR(p.center_of_mass.z(), 0.45, kRoundOff);
  EXPECT_NEAR(p.center_of_mass.x(), 0.0, kRoundOff);
  EXPECT_NEAR(p.center_of_mass.y(), 0.0, kRoundOff);
  EXPECT_DOUBLE_EQ(p.mass, 15.0);

  // footprint: the 0.5 m square top; feet on z = 0 with four 0.06 m squares of contact
  EXPECT_DOUBLE_EQ(MinCoordinate(desk, 0), -0.25);
  EXPECT_DOUBLE_EQ(MaxCoordinate(desk, 1), 0.25);
  EXPECT_EQ(MinCoordinate(desk, 2), 0.0);
  EXPECT_NEAR(AreaOnGround(desk), 4 * 0.06 * 0.06, kRoundOff);

  // volume: the top A t plus four feet f² (H − t), with H the solved height
  const double height = MaxCoordinate(desk, 2);
  EXPECT_NEAR(p.volume, 0.25 * 0.05 + 4 * 0.0036 * (height - 0.05), kRoundOff);
}

TEST(PaperBodiesTest, DeskHeightFollowsOtherCentreHeights) {
  for (double com_height : {0.1, 0.3, 0.8}) {
    DeskParams params;
    params.com_height = com_height;
    const TriangleMesh desk = MakeDeskMesh(params);
    ExpectSolid(desk);
    EXPECT_NEAR(ComputeMassProperties(desk, 1.0).center_of_mass.z(), com_height, kRoundOff);
  }
}

TEST(PaperBodiesTest, MassScalesInertiaLinearly) {
  const TriangleMesh desk = MakeDeskMesh();
  const MassProperties light = ComputeMassPropertiesForMass(desk, 15.0);
  const MassProperties heavy = ComputeMassPropertiesForMass(desk, 30.0);
  EXPECT_DOUBLE_EQ(heavy.mass, 2 * light.mass);
  EXPECT_LE((heavy.inertia - 2 * light.inertia).norm(), kRoundOff * heavy.inertia.norm());
  EXPECT_NEAR(heavy.volume, light.volume, kRoundOff);
}

TEST(PaperBodiesTest, TBarLiesFlatWithCentreAboveTheOrigin) {
  const TriangleMesh tbar = MakeTBarMesh();
  ExpectSolid(tbar);
  const MassProperties p = ComputeMassPropertiesForMass(tbar, 2.0, "T-bar");
  // bar 0.4 × 0.1 plus stem 0.1 × 0.3, 0.05 thick
  EXPECT_NEAR(p.volume, (0.4 * 0.1 + 0.1 * 0.3) * 0.05, kRoundOff);
  EXPECT_NEAR(p.center_of_mass.z(), 0.025, kRoundOff);
  EXPECT_NEAR(p.center_of_mass.x(), 0.0, kRoundOff);
  EXPECT_NEAR(p.center_of_mass.y(), 0.0, kRoundOff);
  EXPECT_EQ(MinCoordinate(tbar, 2), 0.0);
  EXPECT_DOUBLE_EQ(MaxCoordinate(tbar, 2), 0.05);
  EXPECT_NEAR(MaxCoordinate(tbar, 0) - MinCoordinate(tbar, 0), 0.4, kRoundOff);
  EXPECT_NEAR(MaxCoordinate(tbar, 1) - MinCoordinate(tbar, 1), 0.4, kRoundOff);
  EXPECT_NEAR(AreaOnGround(tbar), 0.07, kRoundOff);
  // the stem hangs along −y: the bar's edge is further from the centre than the stem's end
  EXPECT_GT(MaxCoordinate(tbar, 1), 0.0);
  EXPECT_LT(MaxCoordinate(tbar, 1), -MinCoordinate(tbar, 1));
}

TEST(PaperBodiesTest, DumbbellMatchesItsPolygonalClosedForm) {
  const DumbbellParams params;
  const TriangleMesh dumbbell = MakeDumbbellMesh(params);
  ExpectSolid(dumbbell);
  const MassProperties p = ComputeMassProperties(dumbbell, 1.0, "dumbbell");

  // inscribed 96-gons: area (n/2) r² sin α, polar moment n r⁴ sin α (2 + cos α) / 12, α = 2π/n
  const int n = params.segments;
  const double alpha = 2 * kPi / n;
  auto area = [&](double r) { return 0.5 * n * r * r * std::sin(alpha); };
  auto polar = [&](double r) {
    return n * std::pow(r, 4) * std::sin(alpha) * (2 + std::cos(alpha)) / 12;
  };
  const double discs = params.length - params.bar_length;
  EXPECT_NEAR(p.volume, area(params.radius) * discs + area(params.bar_radius) * params.bar_length,
              kRoundOff);
  EXPECT_NEAR(p.inertia(0, 0),
              polar(params.radius) * discs + polar(params.bar_radius) * params.bar_length,
              kRoundOff);
  EXPECT_LE(p.center_of_mass.norm(), kRoundOff);
}

TEST(PaperBodiesTest, DumbbellStaysInsideItsCylinderAndTouchesWithTwoSegments) {
  const DumbbellParams params;
  const TriangleMesh dumbbell = MakeDumbbellMesh(params);
  // every vertex within the hull cylinder (R, L), up to the round-off of r cos θ, r sin θ and
  // their norm: relative, two ulps
  constexpr double kRimRoundOff = 4e-16;
  for (const Eigen::Vector3d& v : dumbbell.vertices) {
    EXPECT_LE(v.tail<2>().norm(), params.radius * (1 + kRimRoundOff));
    EXPECT_LE(std::abs(v.x()), 0.5 * params.length);
  }
  // lying on its side the lowest points are the k = 72 ring vertices (angle −π/2) of the four
  // disc rims, at x = ±L/2 and ±L_b/2: an edge of each disc, so two contact segments
  const double lowest = MinCoordinate(dumbbell, 2);
  EXPECT_EQ(lowest, -params.radius);
  std::vector<double> xs;
  for (const Eigen::Vector3d& v : dumbbell.vertices) {
    if (v.z() == lowest) xs.push_back(v.x());
  }
  std::sort(xs.begin(), xs.end());
  EXPECT_THAT(xs, ::testing::ElementsAre(-0.15, -0.09, 0.09, 0.15));
}

TEST(PaperBodiesTest, CommittedMeshesMatchTheGenerators) {
  // scenes/meshes/*.obj come from `ecpsim meshes`; the files hold single precision, so the
  // centre of mass moves by up to ~1e-7 relative (float rounding of each coordinate, 6e-8)
  constexpr double kFloatCentreShift = 1e-7;  // m, for bodies of size ≤ 0.5 m
  // relative: the volume sums products of three such coordinates over many triangles
  constexpr double kFloatVolumeRel = 1e-6;
  struct Body {
    const char* file;
    TriangleMesh mesh;
  };
  const Body bodies[] = {{"desk.obj", MakeDeskMesh()},
                         {"tbar.obj", MakeTBarMesh()},
                         {"dumbbell.obj", MakeDumbbellMesh()}};
  for (const Body& body : bodies) {
    const std::string path = std::string(ECPSIM_SOURCE_DIR) + "/scenes/meshes/" + body.file;
    const TriangleMesh loaded = LoadMesh(path);
    ExpectSolid(loaded);
    EXPECT_EQ(loaded.vertices.size(), body.mesh.vertices.size()) << path;
    EXPECT_EQ(loaded.triangles.size(), body.mesh.triangles.size()) << path;
    const MassProperties a = ComputeMassProperties(body.mesh, 1.0);
    const MassProperties b = ComputeMassProperties(loaded, 1.0, path);
    EXPECT_NEAR(b.volume / a.volume, 1.0, kFloatVolumeRel) << path;
    EXPECT_LE((b.center_of_mass - a.center_of_mass).norm(), kFloatCentreShift) << path;
  }
}

TEST(PaperBodiesTest, RejectsImpossibleParameters) {
  DeskParams desk;
  desk.foot_size = 0.3;
  EXPECT_THAT([&] { MakeDeskMesh(desk); }, ThrowsMessage<InputError>(HasSubstr("foot_size")));
  desk = DeskParams{};
  desk.com_height = 0.02;
  EXPECT_THAT([&] { MakeDeskMesh(desk); }, ThrowsMessage<InputError>(HasSubstr("com_height")));
  TBarParams tbar;
  tbar.thickness = std::nan("");
  EXPECT_THAT([&] { MakeTBarMesh(tbar); }, ThrowsMessage<InputError>(HasSubstr("thickness")));
  DumbbellParams dumbbell;
  dumbbell.bar_radius = 0.2;
  EXPECT_THAT([&] { MakeDumbbellMesh(dumbbell); },
              ThrowsMessage<InputError>(HasSubstr("bar_radius")));
  dumbbell = DumbbellParams{};
  dumbbell.segments = 2;
  EXPECT_THAT([&] { MakeDumbbellMesh(dumbbell); },
              ThrowsMessage<InputError>(HasSubstr("segments")));
}

}  // namespace
}  // namespace ecpsim::geometry
