#pragma once
// Everything one rendered frame shows, as plain data: posed bodies and hulls, contact patches with
// their ECPs, ground planes, camera, text and display toggles.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/contact_patch.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::render {

/// An edge of a convex hull (body frame, m) with the outward normals of its two faces, so that
/// edges behind the hull (both faces turned away from the camera) can be drawn fainter.
struct HullEdge {
  Eigen::Vector3d a, b;
  Eigen::Vector3d n_left, n_right;
};

/// A body's convex hull for display: its boundary as triangles and its feature edges.
struct HullGeometry {
  geometry::TriangleMesh mesh;  // body frame, outward winding
  std::vector<HullEdge> edges;  // body frame; empty for smooth primitives
};

/// The display geometry of a polyhedral hull: its polygon faces cut into triangles (ears cut
/// round by round, not fans, so that no long slivers cross a many-cornered face) and the edges
/// between faces.
HullGeometry MakeHullGeometry(const geometry::ConvexHull& hull);

/// The display geometry of any convex shape: a polyhedron's faces and edges, or a smooth
/// primitive's tessellation (with `segments` around) without edges.
HullGeometry MakeHullGeometry(const geometry::ConvexShape& shape, int segments = 48);

/// A body to draw. The meshes are shared and treated as immutable while the renderer keeps them:
/// their GPU buffers are made once per mesh object and reused while it is alive.
struct BodyVisual {
  std::shared_ptr<const geometry::TriangleMesh> mesh;      // body frame, m
  std::shared_ptr<const HullGeometry> hull;                // body frame; null: no hull overlay
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // body → world
  Eigen::Vector3f colour = Eigen::Vector3f(0.80f, 0.62f, 0.42f);  // RGB in [0, 1], as displayed
  bool fixed = false;  // an obstacle: drawn, but not followed by automatic framing
};

/// A fixed plane obstacle drawn as a ground sheet with a metric grid, centred under the camera
/// target and sized to the camera's distance (camera.h, GroundHalfExtent).
struct PlaneVisual {
  geometry::Plane plane;  // world; the sheet is the plane n · x = offset
};

/// One contact between a body and an obstacle: the actual patch and the solver's points.
struct ContactVisual {
  geometry::Plane plane;                         // world; the patch lies on it
  geometry::ContactPatch patch;                  // world (geometry::ExtractContactPatch)
  std::optional<Eigen::Vector3d> a1;             // ECP on the body's hull, world, m
  std::optional<Eigen::Vector3d> cm_projection;  // centre of mass projected on the plane, m
  std::optional<Eigen::Vector3d> force;          // contact force p/h on the body, world, N
};

/// Where the camera is. `automatic` frames every body from a fixed direction, following their
/// bounding sphere (centre moves with the bodies, size is constant).
struct CameraSpec {
  bool automatic = true;
  Eigen::Vector3d position = Eigen::Vector3d(1.2, -1.8, 1.1);  // m, world
  Eigen::Vector3d target = Eigen::Vector3d::Zero();            // m, world
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_y_deg = 35;  // vertical field of view
};

/// What to show besides the bodies.
struct DisplayToggles {
  bool hull = true;         // translucent convex hulls with edges
  bool force_arrow = true;  // contact forces (needs ContactVisual::force and force_scale > 0)
  bool inset = true;        // top-down contact inset, top-right corner
  bool text = true;         // time, contact mode and solver iterations, top-left
};

struct FrameInput {
  std::vector<BodyVisual> bodies;
  std::vector<PlaneVisual> planes;
  std::vector<ContactVisual> contacts;
  CameraSpec camera;
  DisplayToggles show;
  double force_scale = 0;  // m of arrow per N of contact force; 0 hides the arrows
  double time = 0;         // s, shown in the text overlay
  int iterations = -1;     // solver iterations of the last step; < 0: not shown
  std::string model;       // what solved the last step ("planar", "hull 2, free 1"); "": none
  std::string title;       // first text line (e.g. the scene name); empty: none
};

}  // namespace ecpsim::render
