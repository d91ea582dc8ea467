#pragma once
// Test meshes generated from a seed for the drop sweep: random convex polytopes, L, T and U
// shapes, tori, thin plates, needles, nearly coplanar facets, low-relief terrain slabs and
// disconnected parts. Each is a closed, consistently outward-wound triangle mesh.

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace ecpsim::evaluation {

enum class MeshKind {
  kConvex,        // hull of 4–2,000 random points on or in a sphere or an ellipsoid (CGAL)
  kLShape,        // two boxes joined at a corner, as one closed non-convex mesh
  kTShape,        // a bar on a stem
  kUShape,        // a base and two uprights
  kTorus,         // major radius 1, minor 0.1–0.6, 8–96 × 6–32 segments
  kPlate,         // a prism over a convex 3–32-gon, 100 times wider than thick
  kNeedle,        // a prism over a convex 3–16-gon, 100 times longer than wide
  kCoplanar,      // a box, faces cut into up to 24 × 24 quads, vertices jittered 1e-9–1e-5
  kTerrain,       // a slab whose top is a grid of up to 48 × 48 heights with 1e-6–1e-2 relief
  kDisconnected,  // two or three separate boxes or convex polytopes in one mesh
};
constexpr int kMeshKindCount = 10;

/// convex, l_shape, t_shape, u_shape, torus, plate, needle, coplanar, terrain, disconnected
const char* MeshKindName(MeshKind kind);
/// Every kind, in the order above.
std::vector<MeshKind> AllMeshKinds();

struct GeneratedMesh {
  geometry::TriangleMesh mesh;  // closed, outward-wound; bounding box centred at 0, diagonal 1
  std::string description;      // the drawn parameters, e.g. "612 points on an ellipsoid ..."
};

/// The mesh of `kind` for `seed`: the same on every platform and every call (SeededRandom).
/// Sizes are dimensionless (bounding-box diagonal 1): the caller scales to metres.
GeneratedMesh GenerateMesh(MeshKind kind, std::uint64_t seed);

}  // namespace ecpsim::evaluation
