#pragma once
// A triangle mesh: the plain data every geometry step passes along.

#include <vector>

#include <Eigen/Core>

namespace ecpsim::geometry {

/// Vertices in metres in one frame (the file's frame after scaling, or a body frame), and
/// triangles as index triples into `vertices`, counter-clockwise seen from outside when the
/// mesh is consistently oriented.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

}  // namespace ecpsim::geometry
