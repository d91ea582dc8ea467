#include "geometry/mesh_bounds.h"

#include <algorithm>

#include <fmt/format.h>

namespace ecpsim::geometry {

MeshBounds ComputeMeshBounds(const std::vector<Eigen::Vector3d>& vertices) {
  MeshBounds bounds;
  if (vertices.empty()) return bounds;
  bounds.lo = bounds.hi = vertices.front();
  for (const Eigen::Vector3d& v : vertices) {
    bounds.lo = bounds.lo.cwiseMin(v);
    bounds.hi = bounds.hi.cwiseMax(v);
  }
  bounds.max_abs = std::max(bounds.lo.cwiseAbs().maxCoeff(), bounds.hi.cwiseAbs().maxCoeff());
  // Eigen's stableNorm rescales, so a 1e200 m box does not overflow in the squares
  bounds.diagonal = (bounds.hi - bounds.lo).stableNorm();
  return bounds;
}

bool IsInSupportedSizeRange(const MeshBounds& bounds) {
  return bounds.diagonal >= kMinMeshSize && bounds.diagonal <= kMaxMeshSize &&
         bounds.max_abs <= kMaxMeshSize;
}

std::string SupportedSizeRangeText() {
  return fmt::format(
      "a bounding-box diagonal between {:g} m and {:g} m and every coordinate within ±{:g} m",
      kMinMeshSize, kMaxMeshSize, kMaxMeshSize);
}

}  // namespace ecpsim::geometry
