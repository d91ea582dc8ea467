#pragma once
// What the engine adapters read from a scene beyond the bodies: each obstacle as a plane and each
// body–obstacle pair's friction; and the check of the state they report (header-only: each
// adapter is its own optional TU).

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <fmt/format.h>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "geometry/convex_shape.h"
#include "common/errors.h"

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

/// friction[b][o]: the friction of body b's contacts with obstacle o, empty where the scene lists
/// no such contact pair (then the two never touch).
using PairFrictionTable = std::vector<std::vector<std::optional<engine::Friction>>>;

inline PairFrictionTable MakePairFrictionTable(const engine::Scene& scene) {
  PairFrictionTable table(scene.bodies.size(),
                          std::vector<std::optional<engine::Friction>>(scene.obstacles.size()));
  for (const engine::ContactPair& pair : scene.contacts) {
    table[static_cast<std::size_t>(pair.body)][static_cast<std::size_t>(pair.obstacle)] =
        pair.friction;
  }
  return table;
}

/// @throws engine::SolverFailure "<engine>: the state of body '…' is not finite at t = … s"
///         for the first body whose state is not finite (never a NaN in an output);
///         `name_of(b)` gives body b's name.
template <typename NameOf>
void RequireFiniteState(const char* engine, const engine::State& state, NameOf name_of) {
  for (std::size_t b = 0; b < state.bodies.size(); ++b) {
    if (!engine::IsFinite(state.bodies[b])) {
      throw engine::SolverFailure(fmt::format("{}: the state of body '{}' is not finite at t = {} s",
                                              engine, name_of(b), state.t));
    }
  }
}

}  // namespace ecpsim::baselines
