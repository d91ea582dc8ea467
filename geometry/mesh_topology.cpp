#include "geometry/mesh_topology.h"

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "common/errors.h"

namespace ecpsim::geometry {

MeshTopology AnalyzeTopology(const TriangleMesh& mesh) {
  const int n = static_cast<int>(mesh.vertices.size());

  // bucket every triangle edge by its smaller vertex (counting sort: linear time, no hashing)
  std::vector<int> start(n + 1, 0);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const int u = t[c];
      const int v = t[(c + 1) % 3];
      ECPSIM_DEMAND(u >= 0 && u < n && v >= 0 && v < n);
      if (u != v) ++start[std::min(u, v) + 1];
    }
  }
  for (int i = 0; i < n; ++i) start[i + 1] += start[i];

  // each entry: the larger vertex, and +1 if traversed from smaller to larger, −1 otherwise
  struct HalfEdge {
    int other;
    int direction;
  };
  std::vector<HalfEdge> edges(start[n]);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const int u = t[c];
      const int v = t[(c + 1) % 3];
      if (u == v) continue;
      edges[fill[std::min(u, v)]++] = HalfEdge{std::max(u, v), u < v ? 1 : -1};
    }
  }

  // within a bucket (a handful of entries), group equal edges and count their uses and directions
  MeshTopology topology;
  bool oriented = true;
  for (int i = 0; i < n; ++i) {
    auto first = edges.begin() + start[i];
    auto last = edges.begin() + start[i + 1];
    std::sort(first, last, [](const HalfEdge& a, const HalfEdge& b) { return a.other < b.other; });
    for (auto group = first; group != last;) {
      int uses = 0;
      int net_direction = 0;
      auto it = group;
      for (; it != last && it->other == group->other; ++it) {
        ++uses;
        net_direction += it->direction;
      }
      if (uses == 1) ++topology.boundary_edges;
      if (uses >= 3) ++topology.non_manifold_edges;
      // consistent winding: the uses of an edge alternate in direction (exactly opposite for two)
      if (std::abs(net_direction) > 1) oriented = false;
      group = it;
    }
  }
  topology.closed =
      !mesh.triangles.empty() && topology.boundary_edges == 0 && topology.non_manifold_edges == 0;
  topology.consistently_oriented = oriented;
  return topology;
}

}  // namespace ecpsim::geometry
