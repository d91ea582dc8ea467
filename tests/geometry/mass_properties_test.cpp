#include "geometry/mass_properties.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::MakeBoxMesh;
using testing::MakePrismMesh;
using testing::MakeUnitTetrahedron;
using ::testing::ThrowsMessage;

constexpr double kPi = 3.14159265358979323846;

// relative error of sums of ~10² terms of size ~1 in double precision: a few hundred ulps
constexpr double kRoundOff = 1e-12;

// relative, for closed forms of boxes and prisms: vertices up to 2e3 sizes from the origin keep
// ~12 digits after the shift to the bounding-box centre, and the moments sum ~10² such terms
constexpr double kClosedFormRel = 1e-9;

// m: a few ulps of the 0.3 m prism's coordinates
constexpr double kCoordinateRoundOff = 1e-15;

TEST(MassPropertiesTest, UnitTetrahedronMatchesClosedForm) {
  // volume 1/6, CM (1/4, 1/4, 1/4); about the CM: ∫x² = 1/60 − (1/6)(1/16) = 1/160 and
  // ∫xy = 1/120 − 1/96 = −1/480, so I_xx = 2/160 = 1/80 and I_xy = +1/480 (density 1)
  const MassProperties p = ComputeMassProperties(MakeUnitTetrahedron(), 1.0);
  EXPECT_NEAR(p.volume, 1.0 / 6.0, kRoundOff);
  EXPECT_NEAR(p.mass, 1.0 / 6.0, kRoundOff);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(p.center_of_mass[a], 0.25, kRoundOff);
    for (int b = 0; b < 3; ++b) {
      EXPECT_NEAR(p.inertia(a, b), a == b ? 1.0 / 80.0 : 1.0 / 480.0, kRoundOff) << a << b;
    }
  }
  // the principal moments of that matrix: 1/80 + 2/480 = 1/60 along (1, 1, 1) and, twice,
  // 1/80 − 1/480 = 1/96 across it
  EXPECT_NEAR(p.principal_moments[0], 1.0 / 96.0, kRoundOff);
  EXPECT_NEAR(p.principal_moments[1], 1.0 / 96.0, kRoundOff);
  EXPECT_NEAR(p.principal_moments[2], 1.0 / 60.0, kRoundOff);
  EXPECT_NEAR(std::abs(p.principal_axes.col(2).dot(Eigen::Vector3d::Ones().normalized())), 1.0,
              kRoundOff);
}

TEST(MassPropertiesTest, BoxMatchesClosedFormFarFromOrigin) {
  // a 1 × 2 × 3 box centred at (1e3, −2e3, 5e2): integrating about the bounding-box centre keeps
  // the error at round-off, where integrating about the origin would lose ~6 digits
  const Eigen::Vector3d size(1.0, 2.0, 3.0);
  const Eigen::Vector3d centre(1e3, -2e3, 5e2);
  const double density = 7800.0;
  const MassProperties p =
      ComputeMassProperties(MakeBoxMesh(centre - size / 2, centre + size / 2), density);
  const double mass = density * 6.0;
  // box inertia about its centre: m/12 (b² + c², a² + c², a² + b²)
  const Eigen::Vector3d expected(mass / 12 * (4 + 9), mass / 12 * (1 + 9), mass / 12 * (1 + 4));
  EXPECT_LE(std::abs(p.volume - 6.0) / 6.0, kClosedFormRel);
  EXPECT_LE(std::abs(p.mass - mass) / mass, kClosedFormRel);
  EXPECT_LE((p.center_of_mass - centre).norm() / centre.norm(), kRoundOff);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(std::abs(p.inertia(a, a) - expected[a]) / expected[a], kClosedFormRel) << a;
    for (int b = 0; b < 3; ++b) {
      if (a != b) {
        EXPECT_LE(std::abs(p.inertia(a, b)) / expected.minCoeff(), kClosedFormRel);
      }
    }
  }
  // ascending principal moments: z (a² + b² = 5), y (10), x (13)
  EXPECT_LE(std::abs(p.principal_moments[0] - expected[2]) / expected[2], kClosedFormRel);
  EXPECT_LE(std::abs(p.principal_moments[1] - expected[1]) / expected[1], kClosedFormRel);
  EXPECT_LE(std::abs(p.principal_moments[2] - expected[0]) / expected[0], kClosedFormRel);
}

TEST(MassPropertiesTest, PrismMatchesPolygonAndBoundsCylinder) {
  // inscribed regular n-gon prism, α = 2π/n: area A = (n/2) R² sin α (the cylinder's πR² times
  // n sin α / (2π)), polar moment J = n R⁴ sin α (2 + cos α) / 12 (n triangles from the centre,
  // each (area/6)(|a|² + a·b + |b|²)); a regular polygon's second moment is isotropic, so
  // I_axis = ρ L J and I_transverse = ρ L (J/2 + A L²/12)
  const int n = 64;
  const double radius = 0.1;
  const double length = 0.3;
  const double density = 1000.0;
  const double alpha = 2.0 * kPi / n;
  const double area = 0.5 * n * radius * radius * std::sin(alpha);
  const double polar = n * std::pow(radius, 4) * std::sin(alpha) * (2.0 + std::cos(alpha)) / 12.0;
  const double volume = area * length;
  const double axial = density * length * polar;
  const double transverse = density * length * (polar / 2 + area * length * length / 12);

  const MassProperties p = ComputeMassProperties(MakePrismMesh(n, radius, length), density);
  EXPECT_LE(std::abs(p.volume - volume) / volume, kClosedFormRel);
  EXPECT_LE(std::abs(p.inertia(2, 2) - axial) / axial, kClosedFormRel);
  EXPECT_LE(std::abs(p.inertia(0, 0) - transverse) / transverse, kClosedFormRel);
  EXPECT_LE(std::abs(p.inertia(1, 1) - transverse) / transverse, kClosedFormRel);
  EXPECT_NEAR(p.center_of_mass.z(), length / 2, kCoordinateRoundOff);
  EXPECT_NEAR(p.center_of_mass.head<2>().norm(), 0.0, kCoordinateRoundOff);

  // against the true cylinder: the polygon misses the fractions 1 − n sin α/(2π) of the volume
  // (1.6e-3 at n = 64) and 1 − n sin α (2 + cos α)/(6π) of J (3.2e-3), both from below
  const double cylinder_volume = kPi * radius * radius * length;
  const double cylinder_mass = density * cylinder_volume;
  const double cylinder_axial = cylinder_mass * radius * radius / 2;
  const double volume_deficit = 1.0 - n * std::sin(alpha) / (2 * kPi);
  const double polar_deficit = 1.0 - n * std::sin(alpha) * (2 + std::cos(alpha)) / (6 * kPi);
  EXPECT_LT(p.volume, cylinder_volume);
  EXPECT_LE((cylinder_volume - p.volume) / cylinder_volume, volume_deficit * (1 + kClosedFormRel));
  EXPECT_LT(p.inertia(2, 2), cylinder_axial);
  EXPECT_LE((cylinder_axial - p.inertia(2, 2)) / cylinder_axial,
            polar_deficit * (1 + kClosedFormRel));
  EXPECT_LT(volume_deficit, 2e-3);
  EXPECT_LT(polar_deficit, 4e-3);
}

TEST(MassPropertiesTest, RigidMotionMovesCentreAndRotatesInertia) {
  const TriangleMesh mesh = MakePrismMesh(12, 0.2, 0.7);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d translation(0.3, -1.2, 2.5);
  TriangleMesh moved = mesh;
  for (Eigen::Vector3d& v : moved.vertices) v = rotation * v + translation;

  const MassProperties a = ComputeMassProperties(mesh, 500.0);
  const MassProperties b = ComputeMassProperties(moved, 500.0);
  // sizes ~1 m and ~1 kg·m²: differences are round-off
  EXPECT_NEAR(b.volume, a.volume, kRoundOff);
  EXPECT_LE((b.center_of_mass - (rotation * a.center_of_mass + translation)).norm(), kRoundOff);
  EXPECT_LE((b.inertia - rotation * a.inertia * rotation.transpose()).norm(),
            kRoundOff * a.inertia.norm());
  EXPECT_LE((b.principal_moments - a.principal_moments).norm(),
            kRoundOff * a.principal_moments.norm());
}

TEST(MassPropertiesTest, PrincipalAxesAreARightHandedEigenbasis) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 2.0, 3.0));
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, 0.4, -0.8).normalized()).toRotationMatrix();
  for (Eigen::Vector3d& v : mesh.vertices) v = rotation * v;
  const MassProperties p = ComputeMassProperties(mesh, 1.0);
  const Eigen::Matrix3d& axes = p.principal_axes;
  EXPECT_NEAR(axes.determinant(), 1.0, kRoundOff);
  EXPECT_LE((axes.transpose() * axes - Eigen::Matrix3d::Identity()).norm(), kRoundOff);
  EXPECT_LE((p.inertia * axes - axes * p.principal_moments.asDiagonal()).norm(),
            kRoundOff * p.inertia.norm());
  EXPECT_LT(p.principal_moments[0], p.principal_moments[1]);
  EXPECT_LT(p.principal_moments[1], p.principal_moments[2]);
}

TEST(MassPropertiesTest, InwardWoundMeshGivesTheSameSolid) {
  const TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 2.0, 3.0));
  TriangleMesh inward = mesh;
  for (Eigen::Vector3i& t : inward.triangles) std::swap(t[1], t[2]);
  const MassProperties a = ComputeMassProperties(mesh, 2.0);
  const MassProperties b = ComputeMassProperties(inward, 2.0);
  EXPECT_NEAR(b.volume, 6.0, kRoundOff);
  EXPECT_LE((b.center_of_mass - a.center_of_mass).norm(), kRoundOff);
  EXPECT_LE((b.inertia - a.inertia).norm(), kRoundOff * a.inertia.norm());
}

TEST(MassPropertiesTest, ForMassScalesDensity) {
  const TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 2.0, 3.0));
  const MassProperties by_density = ComputeMassProperties(mesh, 2.5);
  const MassProperties by_mass = ComputeMassPropertiesForMass(mesh, 15.0);
  EXPECT_DOUBLE_EQ(by_mass.mass, 15.0);
  EXPECT_NEAR(by_mass.volume, 6.0, kRoundOff);
  // 15 kg over 6 m³ is density 2.5
  EXPECT_LE((by_mass.inertia - by_density.inertia).norm(), kRoundOff * by_density.inertia.norm());
  EXPECT_LE((by_mass.principal_moments - by_density.principal_moments).norm(),
            kRoundOff * by_density.principal_moments.norm());
}

TEST(MassPropertiesTest, RejectsOpenMeshNamingSource) {
  TriangleMesh open = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  open.triangles.pop_back();
  EXPECT_THAT([&] { ComputeMassProperties(open, 1.0, "parts/lid.stl"); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr("parts/lid.stl"), HasSubstr("open"), HasSubstr("3 boundary"))));
}

TEST(MassPropertiesTest, RejectsInconsistentWinding) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);
  std::swap(mesh.triangles[1][1], mesh.triangles[1][2]);
  EXPECT_THAT([&] { ComputeMassProperties(mesh, 1.0, "box"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("box"), HasSubstr("inconsistently"))));
}

TEST(MassPropertiesTest, RejectsFlatMeshes) {
  // a closed, consistently wound tetrahedron with all vertices in z = 0
  TriangleMesh flat = MakeUnitTetrahedron();
  flat.vertices[3] = Eigen::Vector3d(1.0, 1.0, 0.0);
  EXPECT_THAT([&] { ComputeMassProperties(flat, 1.0, "flat.obj"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("flat.obj"), HasSubstr("flat"))));
  // a sheet 1e-13 m thick over 1 m: 1.7e-14 m³, below 1e-12 × diagonal³ (2.8e-12 m³), is
  // round-off, not a solid
  flat.vertices[3] = Eigen::Vector3d(1.0, 1.0, 1e-13);
  EXPECT_THAT([&] { ComputeMassProperties(flat, 1.0, "sheet.obj"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("sheet.obj"), HasSubstr("flat"))));
}

TEST(MassPropertiesTest, ScaleFreeFromBelowAMicrometreToAboveALightYear) {
  // the unit cube scaled by L: volume L³, inertia L⁵/6 at density 1, whatever L in the range
  // (the old absolute 1e-12 m³ threshold rejected everything below a 0.1 mm cube); L is a
  // power of 2 here, so the scaled coordinates are exact and only the summation rounds
  constexpr double kRelativeRoundOff = 1e-14;  // relative; 12 triangles of exact coordinates
  for (int exponent : {-60, -20, -13, 0, 10, 60}) {
    const double l = std::ldexp(1.0, exponent);
    const MassProperties p = ComputeMassProperties(
        MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(l)), 1.0);
    EXPECT_NEAR(p.volume / std::pow(l, 3), 1.0, kRelativeRoundOff) << l;
    EXPECT_NEAR(p.principal_moments.minCoeff() / (std::pow(l, 5) / 6), 1.0, kRelativeRoundOff) << l;
    EXPECT_NEAR(p.principal_moments.maxCoeff() / (std::pow(l, 5) / 6), 1.0, kRelativeRoundOff) << l;
  }
}

TEST(MassPropertiesTest, RejectsSizesOutsideTheSupportedRange) {
  for (double l : {1e-21, 1e21}) {
    const TriangleMesh cube = MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(l));
    EXPECT_THAT([&] { ComputeMassProperties(cube, 1.0, "cube"); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("cube: the mesh is"),
                                                HasSubstr("expected a bounding-box diagonal"))))
        << l;
  }
  // a 1000 km cube 1e21 m from the origin (a smaller one would round away at that distance)
  const TriangleMesh far =
      MakeBoxMesh(Eigen::Vector3d::Constant(1e21), Eigen::Vector3d::Constant(1e21 + 1e6));
  EXPECT_THAT([&] { ComputeMassProperties(far, 1.0, "far"); },
              ThrowsMessage<InputError>(HasSubstr("every coordinate within")));
}

TEST(MassPropertiesTest, RejectsADensityOrMassBeyondDoublePrecision) {
  // a 1e10 m cube is in range, but at density 1e300 its mass (1e330 kg) is not
  const TriangleMesh big = MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e10));
  EXPECT_THAT([&] { ComputeMassProperties(big, 1e300, "big"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("big"), HasSubstr("beyond the range"))));
  // 1e-300 kg over a 1e-15 m cube: the inertia (1e-330 kg·m²) underflows
  const TriangleMesh small = MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-15));
  EXPECT_THAT([&] { ComputeMassPropertiesForMass(small, 1e-300, "small"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("small"), HasSubstr("beyond the range"))));
}

TEST(MassPropertiesTest, RejectsPartsWoundAgainstEachOther) {
  // an outward 2 m cube and, 8 m away, an inward 1 m cube: closed and consistently oriented part
  // by part, with a positive total volume (7 m³), but the inside-out part is negative mass; the
  // "centre of mass" then lies outside every vertex and the moments are not a solid's
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(2.0));
  const TriangleMesh inward = MakeBoxMesh(Eigen::Vector3d(10, 0, 0), Eigen::Vector3d(11, 1, 1));
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), inward.vertices.begin(), inward.vertices.end());
  for (const Eigen::Vector3i& t : inward.triangles) {
    mesh.triangles.emplace_back(base + t[0], base + t[2], base + t[1]);
  }
  EXPECT_THAT([&] { ComputeMassProperties(mesh, 1.0, "parts.fbx"); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr("parts.fbx"), HasSubstr("wound in opposite senses"))));
}

TEST(MassPropertiesTest, ChecksAcceptThinPlatesAndNeedles) {
  // box a × b × c, mass m: I = m/12 (b² + c², a² + c², a² + b²). A plate 1 × 1 × 1e-3 exceeds
  // the triangle inequality by only 2 m c²/12 (1e-6 of I3), a needle 1e-3 × 1e-3 × 1 has a
  // smallest moment 2e-6 of the others: both must pass the checks, with their exact values
  constexpr double kRelative = 1e-9;  // of the largest moment: ≤ 10⁶ ulps, 12 triangles
  const MassProperties plate =
      ComputeMassProperties(MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 1e-3)), 1.0);
  const double plate_mass = 1e-3;
  EXPECT_NEAR(plate.principal_moments[0] + plate.principal_moments[1] - plate.principal_moments[2],
              2 * plate_mass * 1e-6 / 12, kRelative * plate.principal_moments[2]);
  const MassProperties needle = ComputeMassProperties(
      MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1e-3, 1e-3, 1)), 1.0);
  EXPECT_NEAR(needle.principal_moments[0] / needle.principal_moments[2], 2e-6 / (1 + 1e-6),
              kRelative);
}

TEST(MassPropertiesTest, RejectsBadDensityAndMass) {
  const TriangleMesh mesh = MakeUnitTetrahedron();
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THAT([&] { ComputeMassProperties(mesh, bad, "tet"); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("tet"), HasSubstr("density"))));
    EXPECT_THAT([&] { ComputeMassPropertiesForMass(mesh, bad, "tet"); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("tet"), HasSubstr("mass"))));
  }
}

}  // namespace
}  // namespace ecpsim::geometry
