#include "engine/step_driver.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "engine/loads.h"

namespace ecpsim::engine {
namespace {

// the sub-step ladder: the step at h, then in 2, 4 and 16 equal parts (engine/README.md: hard
// impacts and bodies far smaller than g h² need the last rung)
constexpr int kSubsteps[] = {1, 2, 4, 16};
constexpr int kLadderLength = static_cast<int>(std::size(kSubsteps));

// The step's working storage, kept on the thread from step to step: a step in a steady state then
// allocates nothing of its own (vectors keep their capacity, and a contact copied over the last
// step's copy reuses its warm start's buffers)
struct StepScratch {
  // FormIslands: the union–find's roots, each contact's presence in the step, each root's island
  std::vector<int> root, island_of;
  std::vector<char> in_step;
  std::vector<Island> islands;
  // StepIslands: per island its state at the step's end, its contacts' impulses summed over the
  // sub-steps; the bodies at the step's end; the contacts in an island
  std::vector<IslandState> solved;
  std::vector<Eigen::Vector4d> impulse;
  std::vector<BodyState> next_bodies;
  std::vector<char> in_island;
};
thread_local StepScratch scratch;

// the island's part of `state` copied into `local` (over its last contents, reusing them)
void Gather(const Island& island, const State& state, IslandState& local) {
  local.bodies.resize(island.bodies.size());
  local.contacts.resize(island.contacts.size());
  for (size_t i = 0; i < island.bodies.size(); ++i) local.bodies[i] = state.bodies[island.bodies[i]];
  for (size_t i = 0; i < island.contacts.size(); ++i)
    local.contacts[i] = state.contacts[island.contacts[i]];
}

// an axis-aligned box (world) that holds everything of a body that can be touched within the step
using Box = Eigen::AlignedBox3d;

// the broad phase's margin beyond a body's reach in the step, relative to its hull's size: the
// reach is a bound already; the margin only keeps round-off of the support queries out
constexpr double kBroadPhaseRelMargin = 1e-6;

// the world box of `hull` at pose (c, R): six support queries (hill climbing on a polyhedron)
Box HullBox(const geometry::ConvexShape& hull, const Eigen::Vector3d& c, const Eigen::Matrix3d& R) {
  Box box;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(i);
    box.extend(c + R * hull.Support(R.transpose() * axis));
    box.extend(c + R * hull.Support(R.transpose() * -axis));
  }
  return box;
}

// How far a jaw can move within the step: its gripper holds it on the frame across the axis and
// in orientation (to the frame's pose at the step's end: the displacement and turn over the
// step), and along the axis it moves at its own speed plus the actuator's push h F / m — a
// motion along the axis only (the jaws hang 2.5 cm over the table in scenes/gripper.yaml: an
// isotropic 1 cm of closing would bring the table into the island)
struct JawReach {
  double speed = 0;                                    // m/s, in any direction
  Eigen::Vector3d closing = Eigen::Vector3d::Zero();   // m/s, along the axis (world)
};

JawReach JawReachOf(const Scene& scene, int b, const State& state, double radius,
                    const Eigen::Matrix<double, 6, 1>& applied) {
  const Gripper& gripper = scene.grippers[scene.bodies[b].gripper];
  const int j = gripper.jaws[0] == b ? 0 : 1;
  const double h = scene.h;
  const Body& body = scene.bodies[b];
  const BodyState& s = state.bodies[b];
  const KinematicPose frame = gripper.motion->PoseAt(state.t + h);
  const Eigen::Vector3d axis = ClosingAxis(gripper, frame);
  // across the axis to its place on the frame; along it, with the jaws' midpoint to the frame's
  // centre (island_gripper.h), the jaw's own opening being free
  const KinematicPose target = JawOnFrame(gripper, j, frame);
  const Eigen::Vector3d across = target.p - s.p_WB;
  const Eigen::Vector3d centre_shift =
      0.5 * (target.p + JawOnFrame(gripper, 1 - j, frame).p - state.bodies[gripper.jaws[0]].p_WB -
             state.bodies[gripper.jaws[1]].p_WB);
  const double turn = target.q.angularDistance(s.Q_WB);
  JawReach reach;
  reach.speed = ((across - axis.dot(across) * axis).norm() + std::abs(axis.dot(centre_shift)) +
                 turn * radius) / h +
                std::abs(axis.dot(s.v_WB)) + applied.head<3>().norm() / body.mass +
                h * scene.gravity.norm();
  reach.closing = (h * std::abs(gripper.force(state.t)) / body.mass) * axis;
  return reach;
}

// Each body's box for the step [t, t + h]: its hull's box at the start pose grown by how far any
// of its points can move within the step — h (|v| + |ω| r + |p_applied| / m + h |g|) for its
// own motion, plus h V_max for what a contact can give it: a body struck by another, or pushed,
// ends the step no faster than the fastest body of the scene (V_max, kinematic ones included)
// brings in, plus gravity and loads. A kinematic body's box holds its hull at the step's two ends.
std::vector<Box> StepBoxes(const Scene& scene, const State& state) {
  const double h = scene.h;
  std::vector<Box> boxes;
  std::vector<double> speed(scene.bodies.size());
  std::vector<Eigen::Vector3d> closing(scene.bodies.size(), Eigen::Vector3d::Zero());
  double fastest = 0;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const BodyState& s = state.bodies[b];
    const Eigen::Matrix3d R = s.Q_WB.toRotationMatrix();
    boxes.push_back(HullBox(*body.hull, s.p_WB, R));
    const double radius = 0.5 * boxes.back().diagonal().norm() + (boxes.back().center() - s.p_WB).norm();
    if (body.IsKinematic()) {
      const KinematicPose end = body.motion->PoseAt(state.t + h);
      boxes.back().extend(HullBox(*body.hull, end.p, end.q.toRotationMatrix()));
      speed[b] = 0;
      fastest = std::max(fastest, (end.p - s.p_WB).norm() / h + s.w_WB.norm() * radius);
      continue;
    }
    const Eigen::Matrix<double, 6, 1> applied =
        AppliedImpulse(scene.loads, scene.impulses, static_cast<int>(b), state.t, h, R);
    if (body.IsJaw()) {
      const JawReach reach = JawReachOf(scene, static_cast<int>(b), state, radius, applied);
      speed[b] = reach.speed;
      closing[b] = reach.closing;
    } else {
      speed[b] = s.v_WB.norm() + s.w_WB.norm() * radius + applied.head<3>().norm() / body.mass +
                 h * scene.gravity.norm();
    }
    // a body struck by a jaw can get its closing speed in any direction
    fastest = std::max(fastest, speed[b] + closing[b].norm());
  }
  for (size_t b = 0; b < boxes.size(); ++b) {
    Eigen::Array3d grow = h * closing[b].cwiseAbs().array();
    grow += h * (speed[b] + fastest) + kBroadPhaseRelMargin * boxes[b].diagonal().norm();
    // a bound that overflowed (or is NaN) bounds nothing: the box then reaches everything, so a
    // contact is never missed
    if (!grow.allFinite()) grow.setConstant(INFINITY);
    boxes[b].min().array() -= grow;
    boxes[b].max().array() += grow;
  }
  return boxes;
}

// whether anything in `box` can touch the fixed convex `obstacle` (world frame): a half-space's
// constraint at the box's point deepest into it, else the obstacle's own box
bool InReach(const Box& box, const geometry::ConvexShape& obstacle) {
  if (!box.min().allFinite() || !box.max().allFinite()) return true;
  const Eigen::Vector3d centre = box.center(), half = 0.5 * box.sizes();
  if (obstacle.IsHalfSpace()) {
    const Eigen::Vector3d g = obstacle.Gradient(0, centre);
    return obstacle.Value(0, centre) - g.cwiseAbs().dot(half) <= 0;
  }
  Box reach;
  for (int i = 0; i < 3; ++i) {
    reach.extend(obstacle.Support(Eigen::Vector3d::Unit(i)));
    reach.extend(obstacle.Support(-Eigen::Vector3d::Unit(i)));
  }
  return reach.intersects(box);
}

std::string BodyNames(const Scene& scene, const Island& island) {
  std::string names;
  for (int b : island.bodies)
    names += fmt::format("{}'{}'", names.empty() ? "" : ", ", scene.bodies[b].name);
  return names;
}

}  // namespace

namespace {

// FormIslands into `islands`, over their last contents
void FormIslandsInto(const Scene& scene, const State& state, std::vector<Island>& islands) {
  const int n = static_cast<int>(scene.bodies.size());
  // union–find over the dynamic bodies joined by a contact in the step
  std::vector<int>& root = scratch.root;
  root.resize(n);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int b) {
    while (root[b] != b) b = root[b] = root[root[b]];
    return b;
  };
  std::vector<char>& in_step = scratch.in_step;
  in_step.assign(scene.contacts.size(), true);
  std::vector<Box> boxes;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody()) continue;
    if (boxes.empty()) boxes = StepBoxes(scene, state);
    in_step[k] = boxes[pair.body].intersects(boxes[pair.other_body]);
    if (in_step[k] && !scene.bodies[pair.other_body].IsKinematic())
      root[find(pair.body)] = find(pair.other_body);
  }
  // a gripper's jaws move as one (island_gripper.h)
  for (const Gripper& gripper : scene.grippers) root[find(gripper.jaws[0])] = find(gripper.jaws[1]);
  std::vector<int>& island_of = scratch.island_of;
  island_of.assign(n, -1);
  size_t count = 0;
  for (int b = 0; b < n; ++b) {
    if (scene.bodies[b].IsKinematic()) continue;
    const int r = find(b);
    if (island_of[r] < 0) {
      island_of[r] = static_cast<int>(count);
      if (count == islands.size()) islands.emplace_back();
      islands[count].bodies.clear();
      islands[count].contacts.clear();
      ++count;
    }
    islands[island_of[r]].bodies.push_back(b);
  }
  islands.resize(count);
  // an obstacle out of reach of a body of a coupled island leaves its MNCP: there every contact
  // is a block of the coupled Newton system (the stack's upper boxes over the ground, a gripper's
  // jaws over the table), while a body alone takes far obstacles in closed form (free flight)
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.WithBody() || islands[island_of[find(pair.body)]].bodies.size() < 2) continue;
    if (boxes.empty()) boxes = StepBoxes(scene, state);
    in_step[k] = InReach(boxes[pair.body], *scene.obstacles[pair.obstacle].shape);
  }
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (in_step[k]) islands[island_of[find(scene.contacts[k].body)]].contacts.push_back(static_cast<int>(k));
}

}  // namespace

std::vector<Island> FormIslands(const Scene& scene, const State& state) {
  std::vector<Island> islands;
  FormIslandsInto(scene, state, islands);
  return islands;
}

StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model) {
  StepReport report;
  report.converged = true;
  report.models.assign(scene.bodies.size(), StepModel::kKinematic);
  // the step's results, written into `state` only once every island is solved (a failure leaves
  // it as it was); the contacts' states are not copied as a whole: with every pair of bodies a
  // potential contact they outnumber the bodies by far (2,016 pairs for 64 boxes)
  std::vector<Island>& islands = scratch.islands;
  FormIslandsInto(scene, state, islands);
  std::vector<IslandState>& solved = scratch.solved;
  solved.resize(islands.size());

  for (size_t island_index = 0; island_index < islands.size(); ++island_index) {
    const Island& island = islands[island_index];
    IslandState& local = solved[island_index];
    std::string tried;
    double residual = 0;
    bool solved = false;
    // the sub-step ladder with the model's Advance; only where that fails at every length,
    // again with its last resort (if it has one), so that what Advance solves stays as it was
    bool has_last_resort = true;
    for (int attempt = 0; attempt < 2 * kLadderLength && !solved && has_last_resort; ++attempt) {
      const bool last_resort = attempt >= kLadderLength;
      const int substeps = kSubsteps[attempt % kLadderLength];
      Gather(island, state, local);
      const double h = scene.h / substeps;
      double island_residual = 0;
      StepModel island_model = StepModel::kFree;
      bool ok = true;
      // a contact's impulses are the whole step's: the sub-steps' sum
      std::vector<Eigen::Vector4d>& impulse = scratch.impulse;
      impulse.assign(island.contacts.size(), Eigen::Vector4d::Zero());
      for (int i = 0; i < substeps && ok; ++i) {
        std::optional<AdvanceResult> attempted =
            last_resort ? model.AdvanceAsLastResort(island, state.t + i * h, h, local)
                        : model.Advance(island, state.t + i * h, h, local);
        if (!attempted) {  // the model has none
          has_last_resort = ok = false;
          break;
        }
        AdvanceResult& result = *attempted;
        for (size_t k = 0; k < island.contacts.size(); ++k) {
          const ContactState& c = local.contacts[k];
          impulse[k] += Eigen::Vector4d(c.p_n, c.p_t, c.p_o, c.p_r);
        }
        report.iterations += result.iterations;
        report.retries += result.retries;
        residual = result.residual;
        island_residual = std::max(island_residual, result.residual);
        island_model = std::max(island_model, result.model);
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
      for (int b : island.bodies) report.models[b] = island_model;
      for (size_t i = 0; i < island.contacts.size(); ++i) {
        ContactState& c = local.contacts[i];
        c.p_n = impulse[i][0];
        c.p_t = impulse[i][1];
        c.p_o = impulse[i][2];
        c.p_r = impulse[i][3];
      }
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
  // drifts) and the step's twist (a motion that throws leaves `state` as it was)
  std::vector<BodyState>& next_bodies = scratch.next_bodies;
  next_bodies = state.bodies;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    if (!body.IsKinematic()) continue;
    const KinematicMotion::Twist twist = body.motion->StepTwist(state.t, scene.h);
    const KinematicPose end =
        body.motion->PoseAt(static_cast<double>(state.steps + 1) * scene.h);
    next_bodies[b] = {end.p, end.q, twist.v, twist.w};
  }

  // every island solved: the step is committed (copied over the state's own storage)
  state.bodies.swap(next_bodies);
  std::vector<char>& in_island = scratch.in_island;
  in_island.assign(scene.contacts.size(), false);
  for (size_t i = 0; i < islands.size(); ++i) {
    const Island& island = islands[i];
    for (size_t j = 0; j < island.bodies.size(); ++j) state.bodies[island.bodies[j]] = solved[i].bodies[j];
    for (size_t j = 0; j < island.contacts.size(); ++j) {
      state.contacts[island.contacts[j]] = solved[i].contacts[j];
      in_island[island.contacts[j]] = true;
    }
  }
  // contacts in no island: their bodies are apart for the whole step
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    if (in_island[k]) continue;
    ContactState& c = state.contacts[k];
    c.p_n = c.p_t = c.p_o = c.p_r = c.sigma = 0;
    c.warm_start = std::monostate();
  }
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
