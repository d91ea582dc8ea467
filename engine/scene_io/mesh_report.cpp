#include "engine/scene_io/mesh_report.h"

#include <utility>

#include <fmt/format.h>

namespace ecpsim::engine {

MeshReport ReportMesh(ScaledMesh scaled, const std::string& path, const std::optional<double>& mass,
                      const std::optional<double>& density) {
  MeshReport report;
  report.scaled = std::move(scaled);
  const geometry::TriangleMesh& mesh = report.scaled.mesh;
  report.topology = geometry::AnalyzeTopology(mesh);
  const geometry::MeshTopology& topology = report.topology;
  // the hull first: a flat mesh fails here with the hull's "coplanar" message
  const geometry::ConvexHull hull = geometry::ComputeConvexHull(mesh.vertices, path);

  const bool solid = topology.closed && topology.consistently_oriented;
  report.mass_source = "mesh";
  if (!solid) {
    report.mass_source = topology.closed ? "convex hull (mesh is inconsistently oriented)"
                                         : "convex hull (mesh is open)";
    report.warning = (fmt::format(
        "{}: the mesh is not a closed, consistently oriented surface ({} boundary edges, {} "
        "non-manifold edges); using the mass properties of its convex hull",
        path, topology.boundary_edges, topology.non_manifold_edges));
  }
  const geometry::TriangleMesh hull_mesh =
      solid ? geometry::TriangleMesh{} : geometry::TriangulateHull(hull);
  const geometry::TriangleMesh& source = solid ? mesh : hull_mesh;
  report.props =
      mass ? geometry::ComputeMassPropertiesForMass(source, *mass, path)
           : geometry::ComputeMassProperties(source, density.value_or(kDefaultMeshDensity), path);
  report.body_hull = geometry::TranslateHull(hull, -report.props.center_of_mass);
  return report;
}

}  // namespace ecpsim::engine
