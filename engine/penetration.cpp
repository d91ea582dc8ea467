#include "engine/penetration.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <tuple>

#include "geometry/convex_shape.h"

namespace ecpsim::engine {
namespace {

// the mesh vertices that are (bit for bit) the vertices of a polyhedral hull computed from the
// mesh; empty when the hull is a primitive or any hull vertex is not a mesh vertex
std::vector<int> HullVerticesInMesh(const Body& body) {
  const auto* polyhedron = body.hull->AsPolyhedron();
  if (polyhedron == nullptr || polyhedron->hull().vertices.empty()) {
    return {};
  }
  using Key = std::tuple<double, double, double>;
  std::map<Key, int> index;
  for (size_t i = 0; i < body.mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = body.mesh.vertices[i];
    index.emplace(Key(v.x(), v.y(), v.z()), static_cast<int>(i));
  }
  std::vector<int> found;
  for (const Eigen::Vector3d& v : polyhedron->hull().vertices) {
    const auto it = index.find(Key(v.x(), v.y(), v.z()));
    if (it == index.end()) {
      return {};
    }
    found.push_back(it->second);
  }
  return found;
}

}  // namespace

PenetrationProbe::PenetrationProbe(const Scene& scene) {
  for (const Body& body : scene.bodies) {
    std::vector<int> vertices = HullVerticesInMesh(body);
    if (vertices.empty()) {
      vertices.resize(body.mesh.vertices.size());
      std::iota(vertices.begin(), vertices.end(), 0);
    }
    half_space_vertices_.push_back(std::move(vertices));
  }
}

double PenetrationProbe::Depth(const Scene& scene, const State& state, int b, int o) const {
  const Body& body = scene.bodies[b];
  const Eigen::Matrix3d R_WB = state.bodies[b].Q_WB.toRotationMatrix();
  const Eigen::Vector3d& p_WB = state.bodies[b].p_WB;
  const geometry::ConvexShape& shape = *scene.obstacles[o].shape;
  // depth = −max_j g_j(x); a vertex outside any one constraint is outside G
  const auto depth = [&](const Eigen::Vector3d& v_B) {
    const Eigen::Vector3d x = R_WB * v_B + p_WB;
    double largest = shape.Value(0, x);
    for (int j = 1; j < shape.NumConstraints() && largest < 0; ++j) {
      largest = std::max(largest, shape.Value(j, x));
    }
    return -largest;
  };
  double deepest = 0;
  if (shape.IsHalfSpace()) {
    for (int i : half_space_vertices_[b]) {
      deepest = std::max(deepest, depth(body.mesh.vertices[i]));
    }
  } else {
    for (const Eigen::Vector3d& v : body.mesh.vertices) {
      deepest = std::max(deepest, depth(v));
    }
  }
  return deepest;
}

double PenetrationProbe::MaxDepth(const Scene& scene, const State& state) const {
  double deepest = 0;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    // a kinematic body goes where its motion says, through the ground too
    if (scene.bodies[b].IsKinematic()) continue;
    for (size_t o = 0; o < scene.obstacles.size(); ++o) {
      deepest = std::max(deepest, Depth(scene, state, static_cast<int>(b), static_cast<int>(o)));
    }
  }
  return deepest;
}

}  // namespace ecpsim::engine
