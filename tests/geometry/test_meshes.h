#pragma once
// Small closed meshes with known mass properties, shared by the geometry tests.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry::testing {

/// The axis-aligned box [lo, hi] (metres), 8 vertices, 12 outward-wound triangles.
inline TriangleMesh MakeBoxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  // corner i + 2 j + 4 k takes hi along the axes whose bit is set
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        mesh.vertices.emplace_back(i ? hi.x() : lo.x(), j ? hi.y() : lo.y(), k ? hi.z() : lo.z());
      }
    }
  }
  // quads counter-clockwise seen from outside: −x, +x, −y, +y, −z, +z
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

/// The tetrahedron (0, e_x, e_y, e_z), outward-wound.
inline TriangleMesh MakeUnitTetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                   Eigen::Vector3d::UnitZ()};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

/// A right prism along z over the regular n-gon inscribed in the circle of `radius` (vertices at
/// angles 2πk/n), z ∈ [0, length]: the tessellated cylinder.
inline TriangleMesh MakePrismMesh(int n, double radius, double length) {
  const double pi = 3.14159265358979323846;
  TriangleMesh mesh;
  for (int layer = 0; layer < 2; ++layer) {
    for (int k = 0; k < n; ++k) {
      const double angle = 2.0 * pi * k / n;
      mesh.vertices.emplace_back(radius * std::cos(angle), radius * std::sin(angle),
                                 layer * length);
    }
  }
  const int bottom_centre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0.0, 0.0, 0.0);
  const int top_centre = bottom_centre + 1;
  mesh.vertices.emplace_back(0.0, 0.0, length);
  for (int k = 0; k < n; ++k) {
    const int a = k;
    const int b = (k + 1) % n;
    mesh.triangles.emplace_back(a, b, b + n);  // side, outward
    mesh.triangles.emplace_back(a, b + n, a + n);
    mesh.triangles.emplace_back(bottom_centre, b, a);       // bottom cap, −z
    mesh.triangles.emplace_back(top_centre, a + n, b + n);  // top cap, +z
  }
  return mesh;
}

/// The signed volume (divergence theorem about the origin) of each connected part of `mesh`
/// (triangles sharing vertices), in order of each part's first triangle: positive for a part
/// wound outward.
inline std::vector<double> ComponentVolumes(const TriangleMesh& mesh) {
  // union-find over vertices joined by triangle edges
  std::vector<int> parent(mesh.vertices.size());
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<int>(v);
  auto root = [&parent](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    parent[root(t[1])] = root(t[0]);
    parent[root(t[2])] = root(t[0]);
  }
  std::vector<int> part_of_root(mesh.vertices.size(), -1);
  std::vector<double> volumes;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    int& part = part_of_root[root(t[0])];
    if (part < 0) {
      part = static_cast<int>(volumes.size());
      volumes.push_back(0.0);
    }
    volumes[part] += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6;
  }
  return volumes;
}

/// The fixtures folder written by tests/fixtures/make_fixtures.py.
inline std::string FixturePath(const std::string& name) {
  return std::string(ECPSIM_SOURCE_DIR) + "/tests/fixtures/meshes/" + name;
}

}  // namespace ecpsim::geometry::testing
