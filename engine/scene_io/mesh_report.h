#pragma once
// What `ecpsim hull` and the Python module's hull() tell about a mesh file: its size, topology,
// mass properties and convex hull in the body frame.

#include <optional>
#include <string>

#include "engine/scene_io/mesh_scale.h"
#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::engine {

/// kg/m³, water: the density when neither a mass nor a density is given.
inline constexpr double kDefaultMeshDensity = 1000.0;

struct MeshReport {
  ScaledMesh scaled;  // the mesh in metres and its scale
  geometry::MeshTopology topology;
  // "mesh" when it bounds a solid (closed and consistently oriented); otherwise "convex hull
  // (mesh is open)" or "convex hull (mesh is inconsistently oriented)": an open scan or surface
  // patch still gets a usable, documented estimate
  std::string mass_source;
  geometry::MassProperties props;
  geometry::ConvexHull body_hull;  // the convex hull with the origin at the centre of mass
  std::string warning;             // the hull's mass stands in for the mesh's, or ""
};

/// The report of mesh file `path`, loaded as `scaled` (LoadScaledMesh; its size warning is the
/// caller's to show first), from `mass` (kg) or else `density` (kg/m³, default
/// kDefaultMeshDensity).
/// @throws InputError as geometry::ComputeConvexHull (a flat mesh: the "coplanar" message) and
///         the mass-properties functions, naming `path`.
MeshReport ReportMesh(ScaledMesh scaled, const std::string& path, const std::optional<double>& mass,
                      const std::optional<double>& density);

}  // namespace ecpsim::engine
