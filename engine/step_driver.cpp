#include "engine/step_driver.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "engine/loads.h"

namespace ecpsim::engine {
namespace {

// the sub-step ladder: the step at h, then in 2, 4 and 16 equal parts (engine/README.md: hard
// impacts and bodies far smaller than g h² need the last rung)
constexpr int kSubsteps[] = {1, 2, 4, 16};

IslandState Gather(const Island& island, const State& state) {
  IslandState local;
  for (int b : island.bodies) local.bodies.push_back(state.bodies[b]);
  for (int k : island.contacts) local.contacts.push_back(state.contacts[k]);
  return local;
}

// a sphere about a body's centre of mass that holds everything of it that can be touched within
// the step
struct BoundingSphere {
  Eigen::Vector3d centre;
  double radius;
};

// the broad phase's margin beyond a body's reach in the step, as a fraction of its radius: the
// reach is a bound already (speed, applied impulse and gravity over h); the margin covers the
// contact impulses of the step itself, which can speed a body up by what another brings in
constexpr double kBroadPhaseMargin = 0.25;

double HullRadius(const Body& body) {
  double radius = 0;
  for (const Eigen::Vector3d& v : body.mesh.vertices) radius = std::max(radius, v.norm());
  return radius;
}

std::vector<BoundingSphere> StepSpheres(const Scene& scene, const State& state) {
  std::vector<BoundingSphere> spheres;
  const double h = scene.h;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const BodyState& s = state.bodies[b];
    const double radius = HullRadius(body);
    if (body.IsKinematic()) {
      // its hull at the step's start and end: the sphere about the midpoint of the two centres
      const Eigen::Vector3d end = body.motion->PoseAt(state.t + h).p;
      spheres.push_back({0.5 * (s.p_WB + end), radius * (1 + kBroadPhaseMargin) +
                                                  0.5 * (end - s.p_WB).norm()});
      continue;
    }
    const Eigen::Matrix<double, 6, 1> applied = AppliedImpulse(
        scene.loads, scene.impulses, static_cast<int>(b), state.t, h, s.Q_WB.toRotationMatrix());
    const double reach = h * (s.v_WB.norm() + applied.head<3>().norm() / body.mass +
                              h * scene.gravity.norm());
    spheres.push_back({s.p_WB, radius * (1 + kBroadPhaseMargin) + reach});
  }
  return spheres;
}

std::string BodyNames(const Scene& scene, const Island& island) {
  std::string names;
  for (int b : island.bodies)
    names += fmt::format("{}'{}'", names.empty() ? "" : ", ", scene.bodies[b].name);
  return names;
}

}  // namespace

std::vector<Island> FormIslands(const Scene& scene, const State& state) {
  const int n = static_cast<int>(scene.bodies.size());
  // union–find over the dynamic bodies joined by a contact in the step
  std::vector<int> root(n);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int b) {
    while (root[b] != b) b = root[b] = root[root[b]];
    return b;
  };
  std::vector<bool> in_step(scene.contacts.size(), true);
  std::vector<BoundingSphere> spheres;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody()) continue;
    if (spheres.empty()) spheres = StepSpheres(scene, state);
    const BoundingSphere& a = spheres[pair.body];
    const BoundingSphere& b = spheres[pair.other_body];
    in_step[k] = (a.centre - b.centre).norm() <= a.radius + b.radius;
    if (in_step[k] && !scene.bodies[pair.other_body].IsKinematic())
      root[find(pair.body)] = find(pair.other_body);
  }
  std::vector<Island> islands;
  std::vector<int> island_of(n, -1);
  for (int b = 0; b < n; ++b) {
    if (scene.bodies[b].IsKinematic()) continue;
    const int r = find(b);
    if (island_of[r] < 0) {
      island_of[r] = static_cast<int>(islands.size());
      islands.emplace_back();
    }
    islands[island_of[r]].bodies.push_back(b);
  }
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (in_step[k]) islands[island_of[find(scene.contacts[k].body)]].contacts.push_back(static_cast<int>(k));
  return islands;
}

StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model) {
  StepReport report;
  report.converged = true;
  State next = state;

  const std::vector<Island> islands = FormIslands(scene, state);
  // contacts in no island: their bodies are apart for the whole step
  std::vector<bool> in_island(scene.contacts.size(), false);
  for (const Island& island : islands)
    for (int k : island.contacts) in_island[k] = true;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    if (in_island[k]) continue;
    ContactState& c = next.contacts[k];
    c.p_n = c.p_t = c.p_o = c.p_r = c.sigma = 0;
    c.warm_start = std::monostate();
  }

  for (const Island& island : islands) {
    std::string tried;
    double residual = 0;
    bool solved = false;
    for (int substeps : kSubsteps) {
      IslandState local = Gather(island, state);
      const double h = scene.h / substeps;
      double island_residual = 0;
      bool ok = true;
      for (int i = 0; i < substeps && ok; ++i) {
        AdvanceResult result = model.Advance(island, state.t + i * h, h, local);
        report.iterations += result.iterations;
        report.retries += result.retries;
        residual = result.residual;
        island_residual = std::max(island_residual, result.residual);
        if (!result.tried.empty())
          tried += fmt::format("{}{}", tried.empty() ? "" : "; ", result.tried);
        ok = result.solved;
        // a solved step can still overflow (e.g. the explicit gyroscopic term feeding a fast
        // spin, engine/README.md): such a state is never committed
        if (ok && !std::all_of(local.bodies.begin(), local.bodies.end(),
                               [](const BodyState& b) { return IsFinite(b); })) {
          ok = false;
          residual = INFINITY;
          tried += fmt::format("{}a non-finite state (h = {:g} s)", tried.empty() ? "" : "; ", h);
        }
      }
      if (!ok) continue;
      for (size_t i = 0; i < island.bodies.size(); ++i)
        next.bodies[island.bodies[i]] = local.bodies[i];
      for (size_t i = 0; i < island.contacts.size(); ++i)
        next.contacts[island.contacts[i]] = local.contacts[i];
      report.substeps = std::max(report.substeps, substeps);
      report.residual = std::max(report.residual, island_residual);
      solved = true;
      break;
    }
    if (!solved) {
      throw SolverFailure(fmt::format(
          "{}solver failed at t = {:.6g} s on body {}: residual {:.3g} > tolerance {:.3g}; "
          "tried {}",
          model.MessagePrefix(), state.t, BodyNames(scene, island), residual,
          scene.solver.tolerance, tried));
    }
  }

  // kinematic bodies: the prescribed pose at the step's end (never a sum of c + h v, which
  // drifts) and the step's twist
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    if (!body.IsKinematic()) continue;
    const KinematicMotion::Twist twist = body.motion->StepTwist(state.t, scene.h);
    const KinematicPose end =
        body.motion->PoseAt(static_cast<double>(state.steps + 1) * scene.h);
    next.bodies[b] = {end.p, end.q, twist.v, twist.w};
  }

  state.bodies = std::move(next.bodies);
  state.contacts = std::move(next.contacts);
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
