#include "geometry/contact_patch.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "geometry/paper_bodies.h"
#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using testing::MakeBoxMesh;

const Plane kGround;  // z = 0, normal +z

// m or m²: a few dozen ulps of sub-metre lengths and areas that take a few operations each
constexpr double kRoundOff = 1e-15;

// m or m²: lengths and areas that pass through a rotation, trigonometric facets or the hull's
// construction; still 10⁶ below the patch tolerance (1e-6 of the mesh's size)
constexpr double kRotatedRoundOff = 1e-12;

// m: the containment tolerance around a patch's hull; test points lie 0.5× (inside) or 2×
// (outside) it off the hull
constexpr double kHullTolerance = 1e-6;

// m: a containment tolerance far below every length here, for points well inside a hull
constexpr double kInsideTolerance = 1e-9;

// area of a planar polygon in 3-D, positive when counter-clockwise about +z
double AreaAboutZ(const std::vector<Eigen::Vector3d>& polygon) {
  Eigen::Vector3d twice = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    twice += polygon[k].cross(polygon[(k + 1) % polygon.size()]);
  }
  return twice.z() / 2;
}

// the pose that puts the mesh's lowest vertex (after `R`) on z = 0
Eigen::Isometry3d RestOnGround(const TriangleMesh& mesh, const Eigen::Matrix3d& R) {
  double lowest = 1e300;
  for (const Eigen::Vector3d& v : mesh.vertices) lowest = std::min(lowest, (R * v).z());
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = Eigen::Vector3d(0, 0, -lowest);
  return X;
}

// The desk on its four feet: four 0.06 m squares, their hull the 0.5 m top outline.
TEST(ContactPatchTest, DeskFlatIsFourSquaresInASquareHull) {
  const ContactPatch patch =
      ExtractContactPatch(MakeDeskMesh(), Eigen::Isometry3d::Identity(), kGround);
  ASSERT_EQ(patch.polygons.size(), 4u);
  for (const auto& foot : patch.polygons) {
    EXPECT_EQ(foot.size(), 4u);
    EXPECT_NEAR(AreaAboutZ(foot), 0.0036, kRoundOff);
  }
  EXPECT_TRUE(patch.segments.empty());
  EXPECT_TRUE(patch.points.empty());
  ASSERT_EQ(patch.hull.size(), 4u);
  for (const Eigen::Vector3d& corner : patch.hull) {
    EXPECT_NEAR(std::abs(corner.x()), 0.25, kRotatedRoundOff);
    EXPECT_NEAR(std::abs(corner.y()), 0.25, kRotatedRoundOff);
    EXPECT_EQ(corner.z(), 0.0);
  }
  EXPECT_GT(AreaAboutZ(patch.hull), 0.0);
  EXPECT_NEAR(patch.area, 0.25, kRotatedRoundOff);
  EXPECT_NEAR(patch.feature_area, 4 * 0.0036, kRoundOff);
  EXPECT_EQ(patch.mode, ContactMode::kNonConvexPatch);
  EXPECT_STREQ(ContactModeName(patch.mode), "non-convex patch");
}

// The dumbbell on its side (axis along x, centre at height R): each end disc touches along a
// 0.06 m line; together they span the 0.3 m length with a 0.18 m gap.
TEST(ContactPatchTest, DumbbellOnItsSideIsTwoCollinearSegments) {
  const DumbbellParams params;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(0, 0, params.radius);
  const ContactPatch patch = ExtractContactPatch(MakeDumbbellMesh(params), X, kGround);
  EXPECT_TRUE(patch.polygons.empty());
  EXPECT_TRUE(patch.points.empty());
  ASSERT_EQ(patch.segments.size(), 2u);
  for (const auto& segment : patch.segments) {
    EXPECT_NEAR((segment[1] - segment[0]).norm(), 0.06, kRotatedRoundOff);
  }
  ASSERT_EQ(patch.hull.size(), 2u);
  EXPECT_NEAR((patch.hull[1] - patch.hull[0]).norm(), 0.3, kRotatedRoundOff);
  EXPECT_EQ(patch.area, 0.0);
  EXPECT_EQ(patch.mode, ContactMode::kNonConvexLine);
  // the middle of the gap is in the hull, a point beside the line is not
  EXPECT_TRUE(PatchHullContains(patch, kGround, {0, 0, 0}, kInsideTolerance));
  EXPECT_FALSE(PatchHullContains(patch, kGround, {0, 2 * kHullTolerance, 0}, kHullTolerance));
  EXPECT_FALSE(
      PatchHullContains(patch, kGround, {0.15 + 2 * kHullTolerance, 0, 0}, kHullTolerance));
  EXPECT_TRUE(
      PatchHullContains(patch, kGround, {0.15 + 0.5 * kHullTolerance, 0, 0}, kHullTolerance));
}

TEST(ContactPatchTest, BoxFlatOnEdgeAndOnCorner) {
  const TriangleMesh box = MakeBoxMesh({-0.1, -0.2, 0}, {0.1, 0.2, 0.3});
  const ContactPatch flat = ExtractContactPatch(box, Eigen::Isometry3d::Identity(), kGround);
  ASSERT_EQ(flat.polygons.size(), 1u);
  EXPECT_EQ(flat.polygons[0].size(), 4u);
  EXPECT_NEAR(flat.area, 0.08, kRoundOff);
  EXPECT_NEAR(flat.feature_area, 0.08, kRoundOff);
  EXPECT_EQ(flat.mode, ContactMode::kConvexPatch);

  // on the edge x ∈ [−0.1, 0.1] after a 45° roll about x
  const Eigen::Matrix3d roll =
      Eigen::AngleAxisd(0.25 * EIGEN_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const ContactPatch edge = ExtractContactPatch(box, RestOnGround(box, roll), kGround);
  EXPECT_TRUE(edge.polygons.empty());
  ASSERT_EQ(edge.segments.size(), 1u);
  EXPECT_NEAR((edge.segments[0][1] - edge.segments[0][0]).norm(), 0.2, kRotatedRoundOff);
  EXPECT_EQ(edge.hull.size(), 2u);
  EXPECT_EQ(edge.mode, ContactMode::kLine);

  // on a corner after a generic rotation
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  const Eigen::Isometry3d X_corner = RestOnGround(box, tilt);
  const ContactPatch corner = ExtractContactPatch(box, X_corner, kGround);
  ASSERT_EQ(corner.points.size(), 1u);
  EXPECT_EQ(corner.hull.size(), 1u);
  EXPECT_EQ(corner.mode, ContactMode::kPoint);
  EXPECT_TRUE(PatchHullContains(corner, kGround, corner.points[0], kInsideTolerance));
  EXPECT_FALSE(PatchHullContains(corner, kGround,
                                 corner.points[0] + Eigen::Vector3d(2 * kHullTolerance, 0, 0),
                                 kHullTolerance));
  EXPECT_FALSE(PatchHullContains(corner, kGround,
                                 corner.points[0] + Eigen::Vector3d(0, 0, 2 * kHullTolerance),
                                 kHullTolerance));
}

// The T-bar flat is its T outline (area 0.4 × 0.1 + 0.3 × 0.1 = 0.07) in a hexagonal hull
// (bar 0.04 + trapezoid (0.4 + 0.1)/2 × 0.3 = 0.075, total 0.115); tilted about the hull edge
// from a bar corner to a stem-tip corner it rests on those two corners only.
TEST(ContactPatchTest, TBarFlatAndOnTwoCorners) {
  const TriangleMesh tbar = MakeTBarMesh();
  const ContactPatch flat = ExtractContactPatch(tbar, Eigen::Isometry3d::Identity(), kGround);
  ASSERT_EQ(flat.polygons.size(), 1u);
  EXPECT_EQ(flat.polygons[0].size(), 8u);
  EXPECT_NEAR(AreaAboutZ(flat.polygons[0]), 0.07, kRoundOff);
  EXPECT_NEAR(flat.feature_area, 0.07, kRoundOff);
  EXPECT_EQ(flat.hull.size(), 6u);
  EXPECT_NEAR(flat.area, 0.115, kRoundOff);
  EXPECT_EQ(flat.mode, ContactMode::kNonConvexPatch);

  // the bar's bottom-right corner and the stem tip's right corner (lowest y, largest x)
  Eigen::Vector3d bar_corner(-1e300, 1e300, 0);
  Eigen::Vector3d stem_corner(-1e300, 1e300, 0);
  double y_min = 1e300;
  for (const Eigen::Vector3d& v : tbar.vertices) y_min = std::min(y_min, v.y());
  for (const Eigen::Vector3d& v : tbar.vertices) {
    if (v.z() != 0) continue;
    if (v.x() == 0.2 && v.y() < bar_corner.y()) bar_corner = v;
    if (v.y() == y_min && v.x() > stem_corner.x()) stem_corner = v;
  }
  ASSERT_EQ(bar_corner.x(), 0.2);
  const Eigen::Vector3d axis = (stem_corner - bar_corner).normalized();
  for (double angle : {0.1, -0.1}) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translate(bar_corner).rotate(Eigen::AngleAxisd(angle, axis)).translate(-bar_corner);
    // the sense of rotation that lifts the rest of the bar
    // m: the two corners are copies of mesh vertices, at distance 0 from themselves
    constexpr double kSameVertex = 1e-12;
    double lowest = 1e300;
    for (const Eigen::Vector3d& v : tbar.vertices) {
      if ((v - bar_corner).norm() > kSameVertex && (v - stem_corner).norm() > kSameVertex) {
        lowest = std::min(lowest, (X * v).z());
      }
    }
    if (lowest < 0) continue;
    const ContactPatch two = ExtractContactPatch(tbar, X, kGround);
    EXPECT_EQ(two.points.size(), 2u);
    EXPECT_TRUE(two.segments.empty());
    ASSERT_EQ(two.hull.size(), 2u);
    EXPECT_NEAR((two.hull[1] - two.hull[0]).norm(), (stem_corner - bar_corner).norm(),
                kRotatedRoundOff);
    EXPECT_EQ(two.mode, ContactMode::kTwoPoint);
    EXPECT_TRUE(PatchHullContains(two, kGround, 0.5 * (X * bar_corner + X * stem_corner),
                                  kInsideTolerance));
    return;
  }
  FAIL() << "no rotation about the hull edge lifts the T-bar";
}

// A box tilted about its near bottom edge: the far edge 0.5 × tolerance up still touches (a
// convex patch), 2 × tolerance up it does not (a line).
TEST(ContactPatchTest, ToleranceDecidesWhatTouches) {
  const TriangleMesh box = MakeBoxMesh({-0.1, -0.2, 0}, {0.1, 0.2, 0.3});
  const double tolerance = ContactPatchTolerance(box);
  // the default is relative: 1e-6 of the box's diagonal √(0.2² + 0.4² + 0.3²) m
  constexpr double kToleranceRoundOff = 1e-20;  // m: ~100 ulps of the 5.4e-7 m tolerance
  EXPECT_NEAR(tolerance, kContactPatchRelTolerance * std::sqrt(0.29), kToleranceRoundOff);
  // m²: tilted by ~1e-6 rad, the face's area in the plane is 0.08 cos(angle), ~1e-13 below 0.08
  constexpr double kTiltedAreaTolerance = 1e-9;
  for (const double rise : {0.5, 2.0}) {
    const double angle = std::asin(rise * tolerance / 0.4);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translate(Eigen::Vector3d(0, -0.2, 0))
        .rotate(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()))
        .translate(Eigen::Vector3d(0, 0.2, 0));
    const ContactPatch patch = ExtractContactPatch(box, X, kGround);
    if (rise < 1) {
      EXPECT_EQ(patch.mode, ContactMode::kConvexPatch);
      EXPECT_NEAR(patch.area, 0.08, kTiltedAreaTolerance);
    } else {
      EXPECT_EQ(patch.mode, ContactMode::kLine);
      EXPECT_EQ(patch.area, 0.0);
    }
  }
  // lifted clear of the plane: nothing
  Eigen::Isometry3d above = Eigen::Isometry3d::Identity();
  above.translation().z() = 2 * tolerance;
  const ContactPatch none = ExtractContactPatch(box, above, kGround);
  EXPECT_EQ(none.mode, ContactMode::kNone);
  EXPECT_TRUE(none.hull.empty());
  EXPECT_FALSE(PatchHullContains(none, kGround, Eigen::Vector3d::Zero(), 1.0));
}

// The same poses of a box scaled by L from 0.1 mm to 1 km give the same modes, and areas ∝ L²:
// the default tolerance scales with the mesh (an absolute 1 µm would be a twentieth of the
// L = 1e-4 box's smallest side)
TEST(ContactPatchTest, ScaledBoxGivesTheSamePatches) {
  // flat on its face, tilted onto an edge by an angle far above the tolerance, and on a corner
  const std::vector<Eigen::AngleAxisd> tilts = {
      Eigen::AngleAxisd(0, Eigen::Vector3d::UnitX()),
      Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()),
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized())};
  const std::vector<ContactMode> expected = {ContactMode::kConvexPatch, ContactMode::kLine,
                                             ContactMode::kPoint};
  // relative: the patch's area from a few products of coordinates scaled by L
  constexpr double kAreaRoundOff = 1e-12;
  for (const double L : {1e-4, 1e-2, 1.0, 1e2, 1e3}) {
    const TriangleMesh box =
        MakeBoxMesh(Eigen::Vector3d(-0.1, -0.2, -0.15) * L, Eigen::Vector3d(0.1, 0.2, 0.15) * L);
    for (size_t k = 0; k < tilts.size(); ++k) {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.rotate(tilts[k]);
      // lowest vertex exactly on the plane
      double lowest = INFINITY;
      for (const Eigen::Vector3d& v : box.vertices) lowest = std::min(lowest, (X * v).z());
      X.pretranslate(Eigen::Vector3d(0, 0, -lowest));
      const ContactPatch patch = ExtractContactPatch(box, X, kGround);
      EXPECT_EQ(patch.mode, expected[k]) << "L = " << L << ", tilt " << k;
      // the flat face's area 0.2 × 0.4 L², to round-off
      if (k == 0) {
        EXPECT_NEAR(patch.area / (L * L), 0.08, kAreaRoundOff) << "L = " << L;
      }
    }
  }
}

// Tetrahedra standing on their tips: isolated points, classified by number and layout.
TEST(ContactPatchTest, IsolatedTipsArePointContacts) {
  const auto tip_mesh = [](const std::vector<Eigen::Vector2d>& where) {
    TriangleMesh mesh;
    for (const Eigen::Vector2d& p : where) {
      const int base = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(p.x(), p.y(), 0);
      mesh.vertices.emplace_back(p.x() + 0.05, p.y(), 0.1);
      mesh.vertices.emplace_back(p.x(), p.y() + 0.05, 0.1);
      mesh.vertices.emplace_back(p.x() - 0.05, p.y() - 0.05, 0.1);
      mesh.triangles.emplace_back(base, base + 2, base + 1);
      mesh.triangles.emplace_back(base, base + 3, base + 2);
      mesh.triangles.emplace_back(base, base + 1, base + 3);
      mesh.triangles.emplace_back(base + 1, base + 2, base + 3);
    }
    return mesh;
  };
  const auto tips = [&](const std::vector<Eigen::Vector2d>& where) {
    return ExtractContactPatch(tip_mesh(where), Eigen::Isometry3d::Identity(), kGround);
  };
  EXPECT_EQ(tips({{0, 0}}).mode, ContactMode::kPoint);
  EXPECT_EQ(tips({{0, 0}, {1, 0}}).mode, ContactMode::kTwoPoint);
  const ContactPatch three = tips({{0, 0}, {1, 0}, {0, 1}});
  EXPECT_EQ(three.mode, ContactMode::kMultiPoint);
  EXPECT_NEAR(three.area, 0.5, kRoundOff);
  EXPECT_TRUE(PatchHullContains(three, kGround, {0.25, 0.25, 0}, kInsideTolerance));
  EXPECT_TRUE(
      PatchHullContains(three, kGround, {0.5, 0.5 + 0.5 * kHullTolerance, 0}, kHullTolerance));
  EXPECT_FALSE(
      PatchHullContains(three, kGround, {0.5, 0.5 + 2 * kHullTolerance, 0}, kHullTolerance));
  EXPECT_EQ(tips({{0, 0}, {1, 0}, {2, 0}}).mode, ContactMode::kNonConvexLine);
  // two tips closer than the tolerance are one point (half the tolerance apart changes the
  // mesh's diagonal, hence the tolerance, by a negligible 1e-6 of itself)
  const double gap = 0.5 * ContactPatchTolerance(tip_mesh({{0, 0}}));
  const ContactPatch close = tips({{0, 0}, {gap, 0}});
  EXPECT_EQ(close.points.size(), 1u);
  EXPECT_EQ(close.mode, ContactMode::kPoint);
}

// A triangle soup (every triangle with its own corners, as STL stores them) welds into the same
// single square.
TEST(ContactPatchTest, UnweldedSoupGivesTheSamePatch) {
  const TriangleMesh box = MakeBoxMesh({-0.1, -0.2, 0}, {0.1, 0.2, 0.3});
  TriangleMesh soup;
  for (const Eigen::Vector3i& t : box.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(box.vertices[t[k]]);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  const ContactPatch patch = ExtractContactPatch(soup, Eigen::Isometry3d::Identity(), kGround);
  ASSERT_EQ(patch.polygons.size(), 1u);
  EXPECT_EQ(patch.polygons[0].size(), 4u);
  EXPECT_EQ(patch.mode, ContactMode::kConvexPatch);
}

// A tilted plane: the box resting on x + z = 0.1 (normal (1, 0, 1)/√2) gives its face there.
TEST(ContactPatchTest, TiltedPlaneUsesItsOwnFrame) {
  const TriangleMesh box = MakeBoxMesh({-0.1, -0.2, 0}, {0.1, 0.2, 0.3});
  Plane plane;
  plane.normal = Eigen::Vector3d(-1, 0, 1).normalized();
  plane.offset = 0.0;
  // the box's bottom face (normal −z in B) turned onto −n: rotate −45° about y
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(-0.25 * EIGEN_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const ContactPatch patch = ExtractContactPatch(box, X, plane);
  EXPECT_EQ(patch.mode, ContactMode::kConvexPatch);
  EXPECT_NEAR(patch.area, 0.08, kRotatedRoundOff);
  for (const Eigen::Vector3d& corner : patch.hull) {
    EXPECT_NEAR(plane.normal.dot(corner) - plane.offset, 0.0, kRoundOff);
  }
  // the face's centre lies on the tilted plane to round-off, so a round-off tolerance holds it
  EXPECT_TRUE(PatchHullContains(patch, plane, X * Eigen::Vector3d(0, 0, 0), kRotatedRoundOff));
  EXPECT_FALSE(PatchHullContains(patch, plane, X * Eigen::Vector3d(0.1 + 2 * kHullTolerance, 0, 0),
                                 kHullTolerance));
}

// Where two bodies touch: a 0.2 m box's bottom on a 0.3 m box's top is the whole bottom, the
// 0.3 m box's bottom on the 0.2 m box's top the 0.2 m square, the bottom of a box shifted by half
// its width over the top's edge half of it, and one shifted to the edge that edge (both patches
// extracted on the contact plane, the lower body's with the plane's normal reversed)
TEST(ContactPatchTest, BoxOnBoxIsTheOverlapOfTheirFaces) {
  const TriangleMesh small = MakeBoxMesh({-0.1, -0.1, 0}, {0.1, 0.1, 0.1});
  const TriangleMesh large = MakeBoxMesh({-0.15, -0.15, -0.1}, {0.15, 0.15, 0});
  const Plane below{-Eigen::Vector3d::UnitZ(), 0};  // the lower body's side of z = 0
  const double tolerance = 1e-9;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const ContactPatch small_bottom = ExtractContactPatch(small, I, kGround, tolerance);
  const ContactPatch large_top = ExtractContactPatch(large, I, below, tolerance);
  ASSERT_EQ(large_top.mode, ContactMode::kConvexPatch);
  const ContactPatch on_large =
      IntersectContactPatches(small_bottom, large_top, kGround, tolerance);
  EXPECT_EQ(on_large.mode, ContactMode::kConvexPatch);
  EXPECT_NEAR(on_large.area, 0.04, kRoundOff);
  EXPECT_NEAR(on_large.feature_area, 0.04, kRoundOff);

  // the large box above the small one: its bottom cut to the small top
  const TriangleMesh large_above = MakeBoxMesh({-0.15, -0.15, 0}, {0.15, 0.15, 0.1});
  const TriangleMesh small_below = MakeBoxMesh({-0.1, -0.1, -0.1}, {0.1, 0.1, 0});
  const ContactPatch cut = IntersectContactPatches(
      ExtractContactPatch(large_above, I, kGround, tolerance),
      ExtractContactPatch(small_below, I, below, tolerance), kGround, tolerance);
  EXPECT_EQ(cut.mode, ContactMode::kConvexPatch);
  EXPECT_NEAR(cut.area, 0.04, kRoundOff);
  for (const Eigen::Vector3d& corner : cut.hull) {
    EXPECT_NEAR(std::abs(corner.x()), 0.1, kRoundOff);
    EXPECT_NEAR(std::abs(corner.y()), 0.1, kRoundOff);
  }

  // shifted by 0.15 m in x: half its 0.2 m width over the large top; by 0.25 m, only its edge
  Eigen::Isometry3d shifted = I;
  shifted.translation() = Eigen::Vector3d(0.15, 0, 0);
  const ContactPatch half = IntersectContactPatches(
      ExtractContactPatch(small, shifted, kGround, tolerance), large_top, kGround, tolerance);
  EXPECT_EQ(half.mode, ContactMode::kConvexPatch);
  EXPECT_NEAR(half.area, 0.1 * 0.2, kRoundOff);
  shifted.translation() = Eigen::Vector3d(0.25, 0, 0);
  const ContactPatch edge = IntersectContactPatches(
      ExtractContactPatch(small, shifted, kGround, tolerance), large_top, kGround, tolerance);
  EXPECT_EQ(edge.mode, ContactMode::kLine);
  EXPECT_EQ(edge.area, 0);
}

// The desk's four feet on a support that only reaches under two of them: a non-convex patch of
// two squares; on a beam under its middle, nothing; along a line under two feet (a cylinder's
// top), that line across the two feet
TEST(ContactPatchTest, TheDesksFeetOnANarrowerSupportKeepTheFeetItReaches) {
  const ContactPatch feet =
      ExtractContactPatch(MakeDeskMesh(), Eigen::Isometry3d::Identity(), kGround);
  const double tolerance = 1e-9;
  ContactPatch support;  // a 0.3 × 0.6 m top under x ∈ [0, 0.3] (ccw about −z, as extracted)
  support.hull = {{0, -0.3, 0}, {0, 0.3, 0}, {0.3, 0.3, 0}, {0.3, -0.3, 0}};
  const ContactPatch two = IntersectContactPatches(feet, support, kGround, tolerance);
  EXPECT_EQ(two.polygons.size(), 2u);
  EXPECT_NEAR(two.feature_area, 2 * 0.0036, kRoundOff);
  EXPECT_EQ(two.mode, ContactMode::kNonConvexPatch);

  ContactPatch beam;  // under the desk's middle, between the feet
  beam.hull = {{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0.1, 0.1, 0}, {-0.1, 0.1, 0}};
  EXPECT_EQ(IntersectContactPatches(feet, beam, kGround, tolerance).mode, ContactMode::kNone);

  ContactPatch line;  // along x = 0.22, through the two feet at x ∈ [0.19, 0.25]
  line.hull = {{0.22, -0.4, 0}, {0.22, 0.4, 0}};
  const ContactPatch across = IntersectContactPatches(feet, line, kGround, tolerance);
  EXPECT_EQ(across.segments.size(), 2u);
  double length = 0;
  for (const auto& segment : across.segments) length += (segment[1] - segment[0]).norm();
  EXPECT_NEAR(length, 2 * 0.06, kRoundOff);
  EXPECT_EQ(across.mode, ContactMode::kNonConvexLine);
}

TEST(ContactPatchTest, ModeNames) {
  const std::vector<std::pair<ContactMode, std::string>> names = {
      {ContactMode::kNone, "none"},
      {ContactMode::kPoint, "point"},
      {ContactMode::kTwoPoint, "two-point"},
      {ContactMode::kMultiPoint, "multi-point"},
      {ContactMode::kLine, "line"},
      {ContactMode::kNonConvexLine, "non-convex line"},
      {ContactMode::kConvexPatch, "convex patch"},
      {ContactMode::kNonConvexPatch, "non-convex patch"}};
  for (const auto& [mode, name] : names) EXPECT_EQ(ContactModeName(mode), name);
}

}  // namespace
}  // namespace ecpsim::geometry
