#pragma once
// Convex hulls with CGAL (the only CGAL translation unit): 3-D hull as merged polygonal faces and
// half-spaces, and the 2-D hull of planar point sets.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// A convex polyhedron as both vertex/face lists and the half-space system n_i · y ≤ d_i.
struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;           // m
  std::vector<std::vector<int>> faces;             // polygons, counter-clockwise seen from outside
  std::vector<Eigen::Vector3d> normals;            // unit outward normal of each face
  std::vector<double> offsets;                     // d_i: n_i · y ≤ d_i inside, m
  std::vector<std::vector<int>> vertex_faces;      // faces incident to each vertex (≥ 3 each)
  std::vector<std::vector<int>> vertex_neighbors;  // vertices joined to each vertex by a hull edge
};

/// Relative tolerance for merging coplanar hull triangles, as a fraction of the bounding-box
/// diagonal: float-exported meshes carry ~6e-8 relative rounding per coordinate (up to ~2e-7 in a
/// vertex's distance to a plane through others), so 1e-6 merges that noise with margin while
/// staying far below any modelled feature (1 µm on a 1 m body). A merged face's plane is the
/// normal of its corner polygon at the outermost extreme point, so its corners may lie up to a
/// few tolerances inside it; exactly coplanar input keeps exact planes.
inline constexpr double kCoplanarTolerance = 1e-6;  // dimensionless, × bounding-box diagonal

/// CPU times of ComputeConvexHull's stages (the calling thread's), s: a diagnostic for benchmarks
/// (issue 11's comparison with qhull), filled only when asked for.
struct ConvexHullStageTimes {
  double exact_hull = 0;  // CGAL's convex_hull_3 alone (into its Surface_mesh)
  double arrays = 0;      // that mesh as plain arrays in canonical order
  double merge = 0;       // coplanar merge, corners, normals, offsets, adjacency
};

/// Convex hull of `points` with exact predicates. Triangles whose planes agree within
/// kCoplanarTolerance × (bounding-box diagonal) are merged into one polygonal face, so a cube read
/// from a file with float noise has exactly 6 faces. Offsets are taken as max_v n_i · v over the
/// hull vertices, so every input point satisfies every inequality up to round-off.
/// Every output is a function of the set of points alone, bit for bit, whatever their order and
/// whatever CGAL's triangulation of exactly coplanar points: vertices in lexicographic order of
/// their coordinates; each face from its smallest vertex; faces in order of the area of the
/// largest exact face they hold; normals from the corner polygons (Σ (v_k − v_0) × (v_{k+1} −
/// v_0), exact for a face in a coordinate plane); offsets over the extreme points.
/// @throws InputError naming `source` for fewer than 4 points, non-finite coordinates, or a
///         degenerate (collinear or coplanar, zero-volume) point set.
/// `stage_times`, when given, receives the durations of the stages of this call.
ConvexHull ComputeConvexHull(const std::vector<Eigen::Vector3d>& points,
                             const std::string& source = "point set",
                             ConvexHullStageTimes* stage_times = nullptr);

/// The hull shifted by `offset` (e.g. −centre of mass, to move it into the body frame).
ConvexHull TranslateHull(const ConvexHull& hull, const Eigen::Vector3d& offset);

/// The hull's faces fanned into triangles (outward winding), e.g. for rendering or mass properties.
TriangleMesh TriangulateHull(const ConvexHull& hull);

/// The convex pieces of the solid a closed, consistently oriented triangle mesh bounds, exactly:
/// the mesh in CGAL's exact kernel, each piece with a reflex edge (the solid wrapping more than
/// half a turn round it) cut in two by CGAL's clip along the plane of a face beside that edge,
/// the plane holding the most reflex edges first, until no piece has one. Each piece comes as
/// its corners (rounded to doubles). The pieces fill the solid and meet face to face. Here
/// rather than in a file of its own so that CGAL stays in one translation unit.
/// @throws InputError naming `source` if the mesh is not a closed 2-manifold, has a triangle of
///         no area, intersects itself, or CGAL refuses a cut.
std::vector<std::vector<Eigen::Vector3d>> ExactConvexPieces(const TriangleMesh& mesh,
                                                            const std::string& source);

/// Distances to the solid a closed, consistently oriented triangle mesh bounds (mesh frame): CGAL's
/// AABB tree over its triangles, and its ray-crossing inside test. Here rather than in a file of
/// its own so that CGAL stays in one translation unit.
class SolidDistance {
 public:
  /// @throws InputError naming `source` if the mesh has no triangles or they do not form an
  ///         oriented 2-manifold surface.
  SolidDistance(const TriangleMesh& mesh, const std::string& source);
  ~SolidDistance();
  SolidDistance(const SolidDistance&) = delete;
  SolidDistance& operator=(const SolidDistance&) = delete;

  /// m: the distance from `p` to the mesh's surface.
  double ToSurface(const Eigen::Vector3d& p) const;
  /// Whether `p` lies in the solid (on its surface counts as in).
  bool Inside(const Eigen::Vector3d& p) const;

 private:
  struct Trees;
  std::unique_ptr<Trees> trees_;
};

/// 2-D convex hull, counter-clockwise, without collinear points; fewer than 3 output points for
/// degenerate input (one point, or a segment given by its two ends).
std::vector<Eigen::Vector2d> ComputeConvexHull2D(const std::vector<Eigen::Vector2d>& points);

}  // namespace ecpsim::geometry
