#pragma once
// Mesh units: `units: mm|cm|m|in` (scenes) and `--units` (hull, drop) as the readable form of a
// scale factor, and the warning about meshes of implausible size (a file in the wrong unit).

#include <optional>
#include <string>

#include "geometry/triangle_mesh.h"

namespace ecpsim::engine {

/// How the scale of a mesh was given, for messages: the spellings of the two keys, e.g.
/// {"--scale", "--units"} on the command line or {"bodies[0].scale", "bodies[0].units"} in a scene.
struct MeshScaleKeys {
  std::string scale;
  std::string units;
};

/// Metres per mesh unit for `units` ∈ {mm, cm, m, in}; nullopt for anything else.
std::optional<double> MetresPerUnit(const std::string& units);

/// The unit names MetresPerUnit knows, for messages: "mm, cm, m, in".
const char* KnownUnits();

/// Whether a `scale` and the factor of a unit (`metres` per unit) are the same up to the
/// round-off of a typed decimal (0.0254 and 25.4e-3 agree).
bool ScalesAgree(double scale, double metres);

/// The factor mesh units → m from an optional `scale` and optional `units` (1 when neither is
/// given).
/// @throws InputError naming keys.units for an unknown unit, keys.scale for a scale outside
///         kMeshScaleRange, and both when both are given and disagree (0.001 and `in`).
double ResolveMeshScale(const std::optional<double>& scale, const std::optional<std::string>& units,
                        const MeshScaleKeys& keys);

/// m: the diagonal of the axis-aligned bounding box of `mesh`'s vertices (0 for no vertices):
/// the size "across" that the size warning and the scene's relative tolerances use.
double MeshAcross(const geometry::TriangleMesh& mesh);

/// "" when a mesh `across` m wide (after `scale`) lies in [kMinPlausibleMeshSize,
/// kMaxPlausibleMeshSize], else a one-line warning naming `mesh`, its size and the unit that
/// would make it plausible, e.g. "meshes/part.stl is 254 m across; if it is in millimetres use
/// --units mm (--scale 0.001)".
std::string MeshSizeWarning(const std::string& mesh, double across, double scale,
                            const MeshScaleKeys& keys);

/// A mesh file at its resolved scale: the mesh in m, its size and its size warning.
struct ScaledMesh {
  geometry::TriangleMesh mesh;  // m, the file's frame
  double scale = 1;             // mesh units → m, as resolved
  double across = 0;            // m, MeshAcross(mesh)
  std::string warning;          // MeshSizeWarning, "" for a plausible size
};

/// Loads `path` (geometry::LoadMesh) at the scale ResolveMeshScale makes of `scale` and `units`.
/// @throws InputError as ResolveMeshScale and LoadMesh, and naming `path` and keys.scale when
///         the mesh's size is outside kLengthRange (its mass properties would overflow).
ScaledMesh LoadScaledMesh(const std::string& path, const std::optional<double>& scale,
                          const std::optional<std::string>& units, const MeshScaleKeys& keys);

}  // namespace ecpsim::engine
