#include "engine/report/penetration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

#include "common/errors.h"
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

// a convex shape's vertices (a primitive's from its tessellation) and face normals (a
// polyhedron's; none for a primitive), body frame
// `side` with its centre set: the mean of its vertices
PenetrationProbe::ConvexSide Centred(PenetrationProbe::ConvexSide side) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : side.vertices) sum += v;
  side.centre = sum / static_cast<double>(std::max<size_t>(side.vertices.size(), 1));
  return side;
}

PenetrationProbe::ConvexSide SideOf(const geometry::ConvexShape& shape) {
  PenetrationProbe::ConvexSide side;
  const auto* polyhedron = shape.AsPolyhedron();
  side.vertices = polyhedron ? polyhedron->hull().vertices : shape.Tessellate().vertices;
  if (polyhedron) side.normals = polyhedron->hull().normals;
  return Centred(std::move(side));
}

}  // namespace

PenetrationProbe::PenetrationProbe(const Scene& scene) {
  for (const Body& body : scene.bodies) {
    std::vector<int> vertices = HullVerticesInMesh(body);
    if (vertices.empty()) {
      vertices.resize(body.mesh.vertices.size());
      std::iota(vertices.begin(), vertices.end(), 0);
    }
    // the hull's side: its half-space vertices of the mesh and the hull's normals
    ConvexSide hull;
    for (int i : vertices) hull.vertices.push_back(body.mesh.vertices[i]);
    if (const auto* polyhedron = body.hull->AsPolyhedron())
      hull.normals = polyhedron->hull().normals;
    sides_.emplace_back().push_back(Centred(std::move(hull)));
    for (const auto& part : body.parts) sides_.back().push_back(SideOf(*part));
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

namespace {

// a convex side posed in the world: its body-frame vertices and face normals under (R, p)
struct PosedSide {
  const PenetrationProbe::ConvexSide& side;
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
};

PosedSide Posed(const PenetrationProbe::ConvexSide& side, const BodyState& s) {
  return {side, s.Q_WB.toRotationMatrix(), s.p_WB};
}

// the overlap of two posed convex sides along the candidate axes: `line` (between their reference
// points), the world axes, `normal` if given and both sides' face normals
double SeparatingAxisDepth(const PosedSide& a, const PosedSide& b, const Eigen::Vector3d& line,
                           const Eigen::Vector3d* normal) {
  // the extent of R v + p over the vertices along u: u · p + (Rᵀ u) · v
  const auto extent = [](const PosedSide& side, const Eigen::Vector3d& u) {
    const Eigen::Vector3d u_B = side.R.transpose() * u;
    double lo = INFINITY, hi = -INFINITY;
    for (const Eigen::Vector3d& v : side.side.vertices) {
      const double d = u_B.dot(v);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    const double shift = u.dot(side.p);
    return std::pair(lo + shift, hi + shift);
  };
  // the overlap of the two projections on u: how far one must move along ±u to clear the other
  double depth = INFINITY;
  const auto axis = [&](const Eigen::Vector3d& u) {
    if (!(u.squaredNorm() > 0) || depth <= 0) return;
    const auto [lo_a, hi_a] = extent(a, u);
    const auto [lo_b, hi_b] = extent(b, u);
    depth = std::min(depth, std::min(hi_a - lo_b, hi_b - lo_a) / u.norm());
  };
  axis(line);
  // the world axes: candidates too, and some axis even for two primitives at one centre
  for (int i = 0; i < 3; ++i) axis(Eigen::Vector3d::Unit(i));
  if (normal != nullptr) axis(*normal);
  for (const PosedSide* side : {&a, &b})
    for (const Eigen::Vector3d& n : side->side.normals) axis(side->R * n);
  return std::max(depth, 0.0);
}

}  // namespace

// (the scene's bodies are the probe's: it keeps their sides)
double PenetrationProbe::BodyDepth(const Scene&, const State& state, int a, int b,
                                   const Eigen::Vector3d* normal) const {
  return SeparatingAxisDepth(Posed(sides_[a].front(), state.bodies[a]),
                             Posed(sides_[b].front(), state.bodies[b]),
                             state.bodies[b].p_WB - state.bodies[a].p_WB, normal);
}

double PenetrationProbe::ContactDepth(const Scene& scene, const State& state, int k,
                                      const Eigen::Vector3d* normal) const {
  const ContactPair& pair = scene.contacts[k];
  ECPSIM_DEMAND(pair.WithBody());
  const PosedSide F = Posed(sides_[pair.body][pair.part + 1], state.bodies[pair.body]);
  const PosedSide G =
      Posed(sides_[pair.other_body][pair.other_part + 1], state.bodies[pair.other_body]);
  // the line between the sides' reference points: the parts' centres of vertices
  const auto centre = [](const PosedSide& side) {
    return Eigen::Vector3d(side.R * side.side.centre + side.p);
  };
  const Eigen::Vector3d line = pair.part < 0 && pair.other_part < 0
                                   ? Eigen::Vector3d(G.p - F.p)
                                   : Eigen::Vector3d(centre(G) - centre(F));
  return SeparatingAxisDepth(F, G, line, normal);
}

double PenetrationProbe::MaxDepth(const Scene& scene, const State& state) const {
  double deepest = 0;
  // the solved contact normal is a separating axis of a pair that touches edge to edge
  const bool solved = state.contacts.size() == scene.contacts.size();
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    // a hull spans the body's cavities: its parts' contacts measure the body itself
    if (!pair.WithBody() || pair.sides == SideChoice::kHulls) continue;
    deepest = std::max(deepest, ContactDepth(scene, state, static_cast<int>(k),
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
