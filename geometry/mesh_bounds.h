#pragma once
// The axis-aligned bounds of a mesh and the range of sizes the geometry computes without overflow.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ecpsim::geometry {

/// m: the smallest and largest bounding-box diagonal (and largest |coordinate|) a mesh may have.
/// The highest power of length the geometry forms is the inertia, density × L⁵, and its products
/// downstream (norms, the engine's I·ω terms) reach L¹⁰; keeping L¹⁰ within 1e±200 leaves a
/// factor 1e±100 of double's 1e±308 range for densities, masses, g, h and velocities, and no
/// intermediate result underflows to a subnormal (where relative precision is lost).
inline constexpr double kMinMeshSize = 1e-20;  // m
inline constexpr double kMaxMeshSize = 1e20;   // m

/// Axis-aligned bounding box of a vertex set (metres, the vertices' frame).
struct MeshBounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();  // componentwise minimum
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();  // componentwise maximum
  double diagonal = 0;                           // |hi − lo|, never overflowing for finite input
  double max_abs = 0;                            // largest |coordinate|
};

/// Bounds of `vertices` (all finite; an empty set gives all zeros). The diagonal is computed
/// without overflow or underflow for any finite coordinates (it may be +inf only when hi − lo
/// itself exceeds the double range).
MeshBounds ComputeMeshBounds(const std::vector<Eigen::Vector3d>& vertices);

/// True if the diagonal lies in [kMinMeshSize, kMaxMeshSize] and every |coordinate| is at most
/// kMaxMeshSize: the mesh's welding, topology, hull and mass properties then stay finite.
bool IsInSupportedSizeRange(const MeshBounds& bounds);

/// The range in words, for messages: "a bounding-box diagonal between 1e-20 m and 1e+20 m and
/// every coordinate within ±1e+20 m".
std::string SupportedSizeRangeText();

}  // namespace ecpsim::geometry
