#pragma once
// The stages of ComputeConvexHull that need no CGAL (convex_hull.cpp, the one CGAL translation
// unit, computes the exact hull and its exact faces): the exact hull as plain arrays, the exact
// faces ordered and merged into planar faces within the coplanar tolerance, and the ConvexHull
// built from them. Internal to geometry/: ComputeConvexHull is the interface.

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geometry/convex_hull.h"

namespace ecpsim::geometry {

/// The exact hull as plain arrays: triangles (outward), the triangle across each edge (k, k + 1)
/// and its vertex off that edge (its apex), and per vertex the triangles around it and the
/// vertices joined to it (compressed rows).
struct TriangulatedHull {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> across;
  std::vector<std::array<int, 3>> apex;
  std::vector<int> fan_start;
  std::vector<int> fan;
  std::vector<int> ring_start;
  std::vector<int> ring;
};

/// The exact hull's faces: its triangles joined across every edge whose two triangles are exactly
/// coplanar (exact predicate), i.e. the true faces of the polytope of the input points, whatever
/// way CGAL triangulated them. Their corners (vertices on three exact faces or more: the extreme
/// points) and planes depend on the point set alone.
struct ExactFaces {
  std::vector<int> face_of;         // exact face of each triangle
  std::vector<int> triangle_start;  // the triangles of each exact face (compressed rows)
  std::vector<int> triangles;
  std::vector<int> corner_start;      // the corners of each exact face, counter-clockwise seen
  std::vector<int> corners;           // from outside, starting at its smallest label
  std::vector<Eigen::Vector3d> area;  // fan over the corners from the first: 2 × area × normal
  std::vector<char> extreme;          // per vertex: on three exact faces or more
  int size() const { return static_cast<int>(area.size()); }
};

/// Far below the merge tolerance and far above the round-off of n · v (a few 1e-16 of the largest
/// coordinate): a merged face's outermost vertex is searched for among the vertices this close to
/// the best one found by climbing, so that near-ties in double precision cannot make the offset
/// depend on the path the climb took; and a quick test that rejects a neighbour by one point
/// allows this much beyond the merge tolerance, so that round-off cannot make it stricter than the
/// full test.
inline constexpr double kSupportSlack = 1e-12;  // dimensionless, × largest |coordinate|

/// the error for a point set whose thickness is below the merge tolerance somewhere
[[noreturn]] void ThrowFlatWithinTolerance(const std::string& source, double tolerance,
                                           double diagonal);

/// compressed rows of the indices 0 … n − 1 by their row `row_of[i]`, each row in increasing order
void FillRows(int rows, const std::vector<int>& row_of, std::vector<int>& start,
              std::vector<int>& values);

/// CGAL's convex_hull_3 orders part of its work by vertex handles (a std::map keyed on them, that
/// is on heap addresses), so the labels of the same hull can differ from call to call (and a
/// body's trajectory with the process's history).
/// Relabels vertices in lexicographic order of their coordinates (hull vertices are distinct),
/// starts each triangle at its smallest label (keeping its winding) and sorts the triangles, so
/// the hull of a point set is the same arrays in every run.
void CanonicalOrder(std::vector<Eigen::Vector3d>& points,
                    std::vector<std::array<int, 3>>& triangles);

/// The boundary of a group of triangles as one loop, counter-clockwise seen from outside, appended
/// to `loop`; false if the group is not a disk (several loops or a pinched vertex).
bool AppendBoundaryLoop(const TriangulatedHull& hull, const std::vector<int>& group_of,
                        const int* first, const int* last, std::vector<std::pair<int, int>>& edges,
                        std::vector<int>& loop);

/// how many distinct values (at most 3, the count stops there) `label` takes on the triangles
/// around vertex v
int DistinctAround(const TriangulatedHull& hull, const std::vector<int>& label, int v);

/// Σ (p_k − p_0) × (p_{k+1} − p_0) over a convex polygon given as `count` labels: twice its area
/// times its normal. Differences to the first corner keep a face in a coordinate plane exactly
/// normal to its axis (its in-plane differences have an exact zero component).
Eigen::Vector3d FanAreaVector(const std::vector<Eigen::Vector3d>& points, const int* polygon,
                              int count);

/// appends the labels of `loop` that `keep` marks, rotated to start at the smallest of them
void AppendCornersFromSmallest(const std::vector<int>& loop, const std::vector<char>& keep,
                               std::vector<int>& corners);

/// Grows planar groups of exact faces from the largest first (their normals are the most
/// accurate): a neighbour joins when all its corners lie within `tolerance` of the seed's plane,
/// so a group is a union of whole exact faces. Testing distances to the group's plane, not
/// normals of neighbours pairwise, keeps a finely tessellated curved surface from drifting into
/// one face. Returns the group of each exact face; `seed_rank` receives the place in `order` of
/// each group's seed (its largest exact face).
std::vector<int> GrowCoplanarGroups(const TriangulatedHull& hull, const ExactFaces& faces,
                                    const std::vector<int>& order, double tolerance, double slack,
                                    std::vector<int>& seed_rank);

/// Largest n · v over the extreme points of the hull: climbing the (exactly convex) triangulated
/// hull from `start` finds the largest n · v up to round-off (on a convex polytope a local maximum
/// of a linear function is the global one); the extreme points within kSupportSlack of it are then
/// visited (a cap of a convex polytope is connected), so the result does not depend on the path.
/// `visited` (one entry per vertex, never equal to `stamp` before) marks the cap's vertices.
double MaxOverExtremePoints(const TriangulatedHull& hull, const std::vector<char>& extreme,
                            const Eigen::Vector3d& n, int start, double slack,
                            std::vector<int>& visited, int stamp, std::vector<int>& queue);

/// The exact faces in their canonical order, largest first (`order`), and each face's place in
/// it (`rank`).
struct FaceOrder {
  std::vector<int> order;
  std::vector<int> rank;
};

/// Exact faces largest first; equal areas by their first two corners (a directed hull edge, so
/// unique; labels order as coordinates do), so the order depends on the points alone.
FaceOrder OrderFacesByArea(const ExactFaces& faces);

/// Throws ThrowFlatWithinTolerance where the points are flat within `tolerance` (m) across the
/// normal of one of the largest exact faces: a set flat within the tolerance has its largest faces
/// on the flat sides.
void CheckNotFlat(const TriangulatedHull& exact, const ExactFaces& faces,
                  const std::vector<int>& order, double tolerance, double diagonal,
                  const std::string& source);

/// The hull's faces as groups of the exact hull's triangles, each a disk with three corners or
/// more.
struct MergedFaces {
  int num_groups = 0;
  std::vector<int> group_of;     // per triangle: its group
  std::vector<int> key;          // per group: the rank of its largest exact face
  std::vector<int> group_start;  // the triangles of each group (compressed rows)
  std::vector<int> group_triangles;
  std::vector<int> loop_start;  // the boundary loop of each group (compressed rows),
  std::vector<int> loops;       // counter-clockwise seen from outside
  std::vector<char> corner;     // per vertex: around three groups or more
};

/// Merges coplanar exact faces (GrowCoplanarGroups within `tolerance`, m), then checks that every
/// merged face keeps three corners (vertices on three or more faces; the others sit inside a
/// face or on a straight edge between two). Where the tolerance merged a sliver between two
/// nearly parallel faces that check fails: the offending groups and their neighbours fall back
/// to single exact faces until it holds, which it does at the latest for the exact faces
/// themselves.
MergedFaces MergeFaces(const TriangulatedHull& exact, const ExactFaces& faces, FaceOrder face_order,
                       double tolerance, double slack);

/// The ConvexHull of the merged faces: its corners in label order (lexicographic order of
/// coordinates), its faces in the order of their largest exact faces, each a corner polygon from
/// its smallest corner with the normal of that polygon and as offset the largest n · v over the
/// extreme points, and the adjacency of its vertices.
ConvexHull BuildHull(const TriangulatedHull& exact, const ExactFaces& faces,
                     const MergedFaces& merged, double slack);

}  // namespace ecpsim::geometry
