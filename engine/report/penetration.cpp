#include "engine/report/penetration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

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

double PenetrationProbe::BodyDepth(const Scene& scene, const State& state, int a, int b,
                                   const Eigen::Vector3d* normal) const {
  const auto world_vertices = [&](int body) {
    const BodyState& s = state.bodies[body];
    const Eigen::Matrix3d R = s.Q_WB.toRotationMatrix();
    std::vector<Eigen::Vector3d> world;
    for (int i : half_space_vertices_[body])
      world.push_back(R * scene.bodies[body].mesh.vertices[i] + s.p_WB);
    return world;
  };
  const std::vector<Eigen::Vector3d> va = world_vertices(a), vb = world_vertices(b);
  const auto extent = [](const std::vector<Eigen::Vector3d>& v, const Eigen::Vector3d& u) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Eigen::Vector3d& x : v) {
      const double d = u.dot(x);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return std::pair(lo, hi);
  };
  // the overlap of the two projections on u: how far one must move along ±u to clear the other
  double depth = INFINITY;
  const auto axis = [&](const Eigen::Vector3d& u) {
    if (!(u.squaredNorm() > 0) || depth <= 0) return;
    const auto [lo_a, hi_a] = extent(va, u);
    const auto [lo_b, hi_b] = extent(vb, u);
    depth = std::min(depth, std::min(hi_a - lo_b, hi_b - lo_a) / u.norm());
  };
  axis(state.bodies[b].p_WB - state.bodies[a].p_WB);
  // the world axes: candidates too, and some axis even for two primitives at one centre
  for (int i = 0; i < 3; ++i) axis(Eigen::Vector3d::Unit(i));
  if (normal != nullptr) axis(*normal);
  for (int body : {a, b}) {
    const auto* polyhedron = scene.bodies[body].hull->AsPolyhedron();
    if (polyhedron == nullptr) continue;
    const Eigen::Matrix3d R = state.bodies[body].Q_WB.toRotationMatrix();
    for (const Eigen::Vector3d& n : polyhedron->hull().normals) axis(R * n);
  }
  return std::max(depth, 0.0);
}

double PenetrationProbe::MaxDepth(const Scene& scene, const State& state) const {
  double deepest = 0;
  // the solved contact normal is a separating axis of a pair that touches edge to edge
  const bool solved = state.contacts.size() == scene.contacts.size();
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody()) continue;
    deepest = std::max(deepest, BodyDepth(scene, state, pair.body, pair.other_body,
                                          solved ? &state.contacts[k].n : nullptr));
  }
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
