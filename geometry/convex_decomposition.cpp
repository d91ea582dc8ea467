#include "geometry/convex_decomposition.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <queue>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/parallel_for.h"
#include "geometry/hull_reach.h"
#include "geometry/mesh_bounds.h"
#include "geometry/part_seams.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// the part of convex polygon `subject` inside convex polygon `clip`, both counter-clockwise
// (Sutherland–Hodgman: left of each of its edges)
std::vector<Vector2d> Clip(std::vector<Vector2d> subject, const std::vector<Vector2d>& clip) {
  for (size_t e = 0; e < clip.size() && !subject.empty(); ++e)
    subject = ClipToSide(subject, clip[e], clip[(e + 1) % clip.size()], true);
  return subject;
}

// whether face f of parts[i] is a seam covered by the faces of other parts that lie on it,
// facing it, each of those parts reaching `depth` behind its share of f: the prism f × [0,
// depth] along f's normal is then inside those parts
bool SeamCovered(const std::vector<ConvexHull>& parts, size_t i, int f, double depth,
                 double tolerance, double size) {
  const ConvexHull& a = parts[i];
  const Vector3d& n = a.normals[f];
  const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const std::vector<Vector2d> face = FaceInPlane(a, f, u, v);
  double covered = 0;
  for (size_t j = 0; j < parts.size(); ++j) {
    if (j == i) continue;
    const ConvexHull& b = parts[j];
    for (size_t g = 0; g < b.faces.size(); ++g) {
      if (!FacesMeet(a, f, b, static_cast<int>(g), tolerance, size)) continue;
      const std::vector<Vector2d> share = Clip(face, FaceInPlane(b, static_cast<int>(g), u, v));
      const double area = std::abs(SignedArea(share));
      if (area <= tolerance * size) continue;
      for (const Vector2d& corner : share) {
        const Vector3d x = (a.offsets[f] + depth) * n + corner.x() * u + corner.y() * v;
        for (size_t c = 0; c < b.normals.size(); ++c)
          if (b.normals[c].dot(x) - b.offsets[c] > tolerance) return false;
      }
      covered += area;
    }
  }
  return covered > 0 && covered >= SignedArea(face) - tolerance * size;
}

// whether corner k of face f is no corner of the part grown across f: every other face at it
// faces no way against f's normal, so the grown copy of the corner lies as far out as it in
// every direction the corner is extreme in (on a prism's side edge, as a bar's end corners)
bool PassedByGrowth(const ConvexHull& part, int f, int k) {
  for (size_t g = 0; g < part.faces.size(); ++g) {
    if (static_cast<int>(g) == f || part.normals[g].dot(part.normals[f]) >= -kCoplanarTolerance)
      continue;
    const std::vector<int>& face = part.faces[g];
    if (std::find(face.begin(), face.end(), k) != face.end()) return false;
  }
  return true;
}

std::vector<Vector3d> Joined(const ConvexHull& a, const ConvexHull& b) {
  std::vector<Vector3d> points = a.vertices;
  points.insert(points.end(), b.vertices.begin(), b.vertices.end());
  return points;
}

// Points of the hull of two parts, cheap to find: the midpoints of their support points in 26
// directions (the axes and the diagonals). One that lies in neither part, or out of the solid, is
// there without the hull, which on a finely tessellated part (an 840-gon face) costs a second.
std::vector<Vector3d> SupportMidpoints(const ConvexHull& a, const ConvexHull& b) {
  const auto support = [](const ConvexHull& hull, const Vector3d& direction) {
    return *std::max_element(
        hull.vertices.begin(), hull.vertices.end(),
        [&](const Vector3d& p, const Vector3d& q) { return direction.dot(p) < direction.dot(q); });
  };
  std::vector<Vector3d> midpoints;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        const Vector3d direction(x, y, z);
        if (direction.isZero()) continue;
        midpoints.push_back((support(a, direction) + support(b, direction)) / 2);
      }
    }
  }
  return midpoints;
}

// m: how far `p` lies beyond the hull's face planes (≤ 0 inside)
double Beyond(const ConvexHull& hull, const Vector3d& p) {
  double beyond = -INFINITY;
  for (size_t f = 0; f < hull.normals.size(); ++f)
    beyond = std::max(beyond, hull.normals[f].dot(p) - hull.offsets[f]);
  return beyond;
}

// two parts to merge, and the volume their hull adds to theirs (m³), or where not `evaluated` its
// last known value for either part before it changed; stale once either changes again
struct Candidate {
  double cost = 0;
  std::size_t i = 0, j = 0;  // i < j
  int version_i = 0, version_j = 0;
  bool evaluated = false;
  // the queue's top is the cheapest, ties to the lowest indices (a fixed order)
  bool operator<(const Candidate& other) const {
    return std::tie(cost, i, j) > std::tie(other.cost, other.i, other.j);
  }
};

// `parts` merged in pairs that meet face to face, cheapest first, wherever the hull of the two
// reaches no farther than `bound` m out of the solid, until no pair does. A pair whose part grew
// is queued at its last cost and costed again when it comes up (a hull each), so that a part
// gathering many neighbours costs one hull per pair it merges or is refused, not one per
// neighbour at every merge
std::vector<ConvexHull> MergeWithinBound(std::vector<ConvexHull> parts, const TriangleMesh& mesh,
                                         double bound, double touch, const std::string& source) {
  const SolidDistance solid(mesh, source);
  const std::size_t n = parts.size();
  std::vector<Eigen::AlignedBox3d> boxes(n);
  std::vector<double> volumes(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (const Vector3d& v : parts[i].vertices) boxes[i].extend(v);
    volumes[i] = HullVolume(parts[i]);
  }
  // neighbours: parts that meet face to face (a merged part keeps the neighbours of both)
  std::vector<std::vector<std::size_t>> neighbours(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (boxes[i].exteriorDistance(boxes[j]) > touch || !FindSeam(parts[i], parts[j], touch))
        continue;
      neighbours[i].push_back(j);
      neighbours[j].push_back(i);
    }
  }
  std::vector<int> version(n, 0);
  std::vector<bool> alive(n, true);
  std::map<std::pair<std::size_t, std::size_t>, double> last_cost;
  // pairs refused: a part that grows only reaches farther with the other, so stays refused
  std::set<std::pair<std::size_t, std::size_t>> refused;
  const auto was_refused = [&](std::size_t a, std::size_t b) {
    return refused.count({std::min(a, b), std::max(a, b)}) > 0;
  };
  std::priority_queue<Candidate> queue;
  const auto propose = [&](std::size_t a, std::size_t b, double cost, bool evaluated) {
    const std::size_t i = std::min(a, b), j = std::max(a, b);
    queue.push({cost, i, j, version[i], version[j], evaluated});
  };
  const auto cost_of = [&](std::size_t i, std::size_t j, const ConvexHull& joined) {
    const double cost = HullVolume(joined) - volumes[i] - volumes[j];
    last_cost[{std::min(i, j), std::max(i, j)}] = cost;
    return cost;
  };
  // a pair whose hull has a point out of reach is refused before its hull is taken (as
  // ReachesWithin would refuse it after)
  const auto out_of_reach = [&](std::size_t i, std::size_t j) {
    for (const Vector3d& p : SupportMidpoints(parts[i], parts[j]))
      if (!solid.Inside(p) && solid.ToSurface(p) > bound + touch) return true;
    return false;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j : neighbours[i]) {
      if (i > j) continue;
      if (out_of_reach(i, j)) {
        refused.insert({i, j});
        continue;
      }
      propose(i, j, cost_of(i, j, ComputeConvexHull(Joined(parts[i], parts[j]), source)), true);
    }
  }
  while (!queue.empty()) {
    const Candidate c = queue.top();
    queue.pop();
    if (!alive[c.i] || !alive[c.j] || version[c.i] != c.version_i || version[c.j] != c.version_j)
      continue;
    if (out_of_reach(c.i, c.j)) {
      refused.insert({c.i, c.j});
      continue;
    }
    ConvexHull joined = ComputeConvexHull(Joined(parts[c.i], parts[c.j]), source);
    // costed again: tried now while still the cheapest, else queued at its cost
    if (!c.evaluated) {
      const double cost = cost_of(c.i, c.j, joined);
      if (!queue.empty() &&
          std::tie(queue.top().cost, queue.top().i, queue.top().j) < std::tie(cost, c.i, c.j)) {
        propose(c.i, c.j, cost, true);
        continue;
      }
    }
    if (!ReachesWithin(joined, {&parts[c.i], &parts[c.j]}, mesh, solid, bound)) {
      refused.insert({c.i, c.j});
      continue;
    }
    // j joins i: i takes its neighbours, which now neighbour i
    parts[c.i] = std::move(joined);
    volumes[c.i] = HullVolume(parts[c.i]);
    ++version[c.i];
    alive[c.j] = false;
    std::vector<std::size_t> joined_neighbours;
    for (std::size_t k : neighbours[c.i])
      if (k != c.j && alive[k]) joined_neighbours.push_back(k);
    for (std::size_t k : neighbours[c.j]) {
      if (k == c.i || !alive[k]) continue;
      std::replace(neighbours[k].begin(), neighbours[k].end(), c.j, c.i);
      joined_neighbours.push_back(k);
    }
    std::sort(joined_neighbours.begin(), joined_neighbours.end());
    joined_neighbours.erase(std::unique(joined_neighbours.begin(), joined_neighbours.end()),
                            joined_neighbours.end());
    neighbours[c.i] = joined_neighbours;
    neighbours[c.j].clear();
    for (std::size_t k : joined_neighbours) {
      if (was_refused(c.i, k) || was_refused(c.j, k)) {
        refused.insert({std::min(c.i, k), std::max(c.i, k)});
        continue;
      }
      const auto last = [&](std::size_t a) {
        const auto it = last_cost.find({std::min(a, k), std::max(a, k)});
        return it == last_cost.end() ? INFINITY : it->second;
      };
      propose(c.i, k, std::min(last(c.i), last(c.j)), false);
    }
  }
  std::vector<ConvexHull> merged;
  for (std::size_t i = 0; i < n; ++i)
    if (alive[i]) merged.push_back(std::move(parts[i]));
  return merged;
}

}  // namespace

double HullVolume(const ConvexHull& hull) {
  // the divergence theorem over the fanned faces, about the first vertex (exact for a convex
  // polyhedron; the origin's choice only rounds)
  if (hull.vertices.empty()) return 0;
  const Vector3d& o = hull.vertices.front();
  double six_volume = 0;
  for (const std::vector<int>& face : hull.faces) {
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      six_volume += (hull.vertices[face[0]] - o)
                        .dot((hull.vertices[face[k]] - o).cross(hull.vertices[face[k + 1]] - o));
    }
  }
  return six_volume / 6;
}

std::vector<ConvexHull> DecomposeSolid(const TriangleMesh& mesh, const std::string& source,
                                       std::size_t max_parts, double tolerance_rel) {
  if (!(tolerance_rel >= 0 && tolerance_rel < 1)) {
    throw InputError(fmt::format(
        "convex decomposition of {}: tolerance = {}: expected a finite value >= 0 and < 1 "
        "(a fraction of the mesh's bounding-box diagonal)",
        source, tolerance_rel));
  }
  const double size = ComputeMeshBounds(mesh.vertices).diagonal;
  const double tolerance = kCoplanarTolerance * size;
  std::vector<ConvexHull> parts;
  const std::vector<std::vector<Vector3d>> pieces = ExactConvexPieces(mesh, source);
  parts.resize(pieces.size());
  ParallelFor(pieces.size(),
              [&](std::size_t i) { parts[i] = ComputeConvexHull(pieces[i], source); });
  // merge two pieces meeting face to face where their union is convex (within a tolerance,
  // such a merge is one whose hull stays in the solid, and comes first there, costing nothing)
  for (bool merged = tolerance_rel == 0; merged;) {
    merged = false;
    for (size_t i = 0; i < parts.size() && !merged; ++i) {
      for (size_t j = i + 1; j < parts.size() && !merged; ++j) {
        if (!FindSeam(parts[i], parts[j], tolerance)) continue;
        const std::vector<Vector3d> midpoints = SupportMidpoints(parts[i], parts[j]);
        if (std::any_of(midpoints.begin(), midpoints.end(), [&](const Vector3d& p) {
              return std::min(Beyond(parts[i], p), Beyond(parts[j], p)) > tolerance;
            })) {
          continue;  // a point of their hull in neither: their union is not convex
        }
        ConvexHull joined = ComputeConvexHull(Joined(parts[i], parts[j]), source);
        const double sum = HullVolume(parts[i]) + HullVolume(parts[j]);
        if (HullVolume(joined) > sum + tolerance * size * size) continue;
        parts[i] = std::move(joined);
        parts.erase(parts.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
  // or where the hull of two reaches no farther than the tolerance out of the solid
  if (tolerance_rel > 0 && parts.size() > 1)
    parts = MergeWithinBound(std::move(parts), mesh, tolerance_rel * size, tolerance, source);
  if (parts.size() > max_parts) {
    throw InputError(fmt::format(
        "convex decomposition of {}: {} convex parts within a tolerance of {} of its "
        "bounding-box diagonal ({:.3g} m), more than {}; raise the tolerance "
        "(`decomposition_tolerance`: a coarser, approximate decomposition), list the body's "
        "`parts` yourself, or keep its hull "
        "(decomposition: none)",
        source, parts.size(), tolerance_rel, tolerance_rel * size, max_parts));
  }
  // move each seam inside the part that covers it (all against the parts as they were)
  const double depth = kSeamOverlapRel * size;
  std::vector<std::vector<Vector3d>> grown(parts.size());
  std::vector<std::vector<bool>> passed(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    passed[i].assign(parts[i].vertices.size(), false);
    for (size_t f = 0; f < parts[i].faces.size(); ++f) {
      if (!SeamCovered(parts, i, static_cast<int>(f), depth, tolerance, size)) continue;
      for (int k : parts[i].faces[f]) {
        grown[i].push_back(parts[i].vertices[k] + depth * parts[i].normals[f]);
        passed[i][k] = passed[i][k] || PassedByGrowth(parts[i], static_cast<int>(f), k);
      }
    }
  }
  ParallelFor(parts.size(), [&](std::size_t i) {
    if (grown[i].empty()) return;
    for (size_t k = 0; k < parts[i].vertices.size(); ++k)
      if (!passed[i][k]) grown[i].push_back(parts[i].vertices[k]);
    parts[i] = ComputeConvexHull(grown[i], source);
  });
  return parts;
}

}  // namespace ecpsim::geometry
