#pragma once
// What the engine adapters read from a scene beyond the bodies: each obstacle as a plane, each
// contact pair's friction, the parts the pairs touch and a kinematic body's pose and twist per
// step; and the check of the state they report (header-only: each adapter is its own optional TU).

#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Core>

#include "common/errors.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"

namespace ecpsim::baselines {

/// The plane n · y = d bounding a half-space obstacle n · y ≤ d (world frame, n unit, d in m).
struct HalfSpacePlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0;
};

/// Obstacle `o` of `scene` as a plane.
/// @throws InputError naming the scene, the obstacle and `engine` if the obstacle is not a
///         polyhedral shape with exactly one constraint (the adapters model half-spaces only).
inline HalfSpacePlane HalfSpaceOf(const engine::Scene& scene, int o, const char* engine) {
  const engine::Obstacle& obstacle = scene.obstacles[static_cast<std::size_t>(o)];
  const auto* polyhedron = obstacle.shape->AsPolyhedron();
  if (polyhedron == nullptr || polyhedron->NumConstraints() != 1) {
    throw InputError(fmt::format(
        "{}: obstacles[{}] '{}': the {} adapter models half-spaces only (one plane n·y ≤ d); "
        "expected a half-space obstacle",
        scene.source, o, obstacle.name, engine));
  }
  HalfSpacePlane plane;
  plane.normal = polyhedron->hull().normals[0].normalized();
  plane.offset = polyhedron->hull().offsets[0];
  return plane;
}

/// Whether a peer models contact pair `pair`: of a pair that lists its hulls' contacts and its
/// parts' (decomposition: auto, engine/auto_sides.h) the parts', exact wherever the bodies are.
inline bool PeerModels(const engine::ContactPair& pair) {
  return pair.sides != engine::SideChoice::kHulls;
}

/// The friction of every contact pair the scene lists; a pair it does not list (or excludes
/// under `pairs:`) never touches. Bodies touch through pieces (ContactPair::part, other_part: −1
/// the body's hull, else one of its parts): the body-level lookups answer for any of their
/// pieces, the piece-level ones for the pieces a ContactPair names only.
class PairFrictionTable {
 public:
  explicit PairFrictionTable(const engine::Scene& scene)
      : obstacle_(scene.bodies.size(),
                  std::vector<std::optional<engine::Friction>>(scene.obstacles.size())),
        body_(scene.bodies.size(),
              std::vector<std::optional<engine::Friction>>(scene.bodies.size())) {
    for (const engine::ContactPair& pair : scene.contacts) {
      if (!PeerModels(pair)) continue;
      const auto b = static_cast<std::size_t>(pair.body);
      if (pair.WithBody()) {
        const auto g = static_cast<std::size_t>(pair.other_body);
        body_[b][g] = body_[g][b] = pair.friction;
        pieces_[{pair.body, pair.part, pair.other_body, pair.other_part}] = pair.friction;
        pieces_[{pair.other_body, pair.other_part, pair.body, pair.part}] = pair.friction;
      } else {
        obstacle_[b][static_cast<std::size_t>(pair.obstacle)] = pair.friction;
        obstacle_pieces_[{pair.body, pair.part, pair.obstacle}] = pair.friction;
      }
    }
  }
  /// Body b against obstacle o; empty: they never touch.
  const std::optional<engine::Friction>& WithObstacle(int b, int o) const {
    return obstacle_[static_cast<std::size_t>(b)][static_cast<std::size_t>(o)];
  }
  /// Bodies a and b, in either order; empty: they never touch.
  const std::optional<engine::Friction>& WithBody(int a, int b) const {
    return body_[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
  }
  /// Piece `part` of body b (−1: its hull) against obstacle o; empty: they never touch.
  std::optional<engine::Friction> PieceWithObstacle(int b, int part, int o) const {
    const auto found = obstacle_pieces_.find({b, part, o});
    if (found == obstacle_pieces_.end()) return std::nullopt;
    return found->second;
  }
  /// Piece `part_a` of body a against piece `part_b` of body b (−1: a hull), in either order;
  /// empty: they never touch.
  std::optional<engine::Friction> PieceWithPiece(int a, int part_a, int b, int part_b) const {
    const auto found = pieces_.find({a, part_a, b, part_b});
    if (found == pieces_.end()) return std::nullopt;
    return found->second;
  }

 private:
  std::vector<std::vector<std::optional<engine::Friction>>> obstacle_, body_;
  std::map<std::array<int, 3>, engine::Friction> obstacle_pieces_;  // (body, part, obstacle)
  std::map<std::array<int, 4>, engine::Friction> pieces_;  // (body, part, other, other part)
};

/// The parts of each body that the scene's pairs touch (ContactPair::part, other_part ≥ 0),
/// ascending; empty for a body touched through its hull only.
inline std::vector<std::vector<int>> TouchedParts(const engine::Scene& scene) {
  std::vector<std::vector<int>> parts(scene.bodies.size());
  const auto add = [&](int b, int part) {
    std::vector<int>& list = parts[static_cast<std::size_t>(b)];
    if (part >= 0 && std::find(list.begin(), list.end(), part) == list.end()) list.push_back(part);
  };
  for (const engine::ContactPair& pair : scene.contacts) {
    if (!PeerModels(pair)) continue;
    add(pair.body, pair.part);
    if (pair.WithBody()) add(pair.other_body, pair.other_part);
  }
  for (std::vector<int>& list : parts) std::sort(list.begin(), list.end());
  return parts;
}

/// Body-frame hull of part `part` of body b: a polyhedral part's own, a smooth part's
/// tessellation's.
/// @throws InputError naming the scene, body and part if a smooth part's tessellation is flat.
inline geometry::ConvexHull PartHull(const engine::Scene& scene, int b, int part) {
  const engine::Body& body = scene.bodies[static_cast<std::size_t>(b)];
  const geometry::ConvexShape& shape = *body.parts[static_cast<std::size_t>(part)];
  if (const geometry::PolyhedralShape* polyhedron = shape.AsPolyhedron()) return polyhedron->hull();
  return geometry::ComputeConvexHull(
      shape.Tessellate().vertices,
      fmt::format("{}: bodies[{}] '{}' parts[{}]", scene.source, b, body.name, part));
}

/// A kinematic body's prescribed pose at the start of the step [t, t + h] and its twist over
/// the step (KinematicMotion::StepTwist: the engine update c + h v, Exp(h ω) R lands on the
/// pose at t + h), for the adapters to set before each engine step.
struct KinematicStep {
  engine::KinematicPose start;
  engine::KinematicPose end;
  engine::KinematicMotion::Twist twist;
};

inline KinematicStep KinematicStepOf(const engine::Body& body, double t, double h) {
  return {body.motion->PoseAt(t), body.motion->PoseAt(t + h), body.motion->StepTwist(t, h)};
}

/// @throws engine::SolverFailure "<engine>: the state of body '…' is not finite at t = … s"
///         for the first body whose state is not finite (never a NaN in an output);
///         `name_of(b)` gives body b's name.
template <typename NameOf>
void RequireFiniteState(const char* engine, const engine::State& state, NameOf name_of) {
  for (std::size_t b = 0; b < state.bodies.size(); ++b) {
    if (!engine::IsFinite(state.bodies[b])) {
      throw engine::SolverFailure(fmt::format(
          "{}: the state of body '{}' is not finite at t = {} s", engine, name_of(b), state.t));
    }
  }
}

}  // namespace ecpsim::baselines
