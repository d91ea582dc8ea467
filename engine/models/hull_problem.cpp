#include "engine/models/hull_problem.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/errors.h"
#include "engine/mncp/contact_window.h"
#include "engine/mncp/island_gripper.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "engine/models/hull_model.h"
#include "engine/models/hull_tuning.h"
#include "engine/models/hull_warm_start.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "geometry/convex_separation.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// the island's index of scene body `scene_body`
int IslandIndex(const Island& island, int scene_body) {
  const auto it = std::find(island.bodies.begin(), island.bodies.end(), scene_body);
  ECPSIM_DEMAND(it != island.bodies.end());
  return static_cast<int>(it - island.bodies.begin());
}

}  // namespace

Vector3d WorldSupport(const geometry::ConvexShape& shape, const Vector3d& c, const Matrix3d& R,
                      const Vector3d& direction) {
  return c + R * shape.Support(R.transpose() * direction);
}

IslandProblem MakeHullProblem(const Scene& scene, const Island& island, double t, double h,
                              const IslandState& state) {
  IslandProblem p;
  p.h = h;
  for (size_t i = 0; i < island.bodies.size(); ++i)
    p.bodies.push_back(StartOfStep(scene, island.bodies[i], state.bodies[i], t, h));
  // scene index → index into p.kinematic, for the few kinematic bodies the island touches
  std::vector<std::pair<int, int>> kinematic_of;
  for (size_t k = 0; k < island.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[island.contacts[k]];
    IslandContact cp;
    cp.body = IslandIndex(island, pair.body);
    cp.hull = &ShapeOfBody(scene, pair);
    cp.friction = island.friction[k];
    if (!pair.WithBody()) {
      cp.other_kind = Other::kFixed;
      cp.other_shape = scene.obstacles[pair.obstacle].shape.get();
      cp.other_window.resize(cp.other_shape->NumConstraints());
      std::iota(cp.other_window.begin(), cp.other_window.end(), 0);
    } else {
      const Body& other = scene.bodies[pair.other_body];
      cp.other_shape = &ShapeOfOther(scene, pair);
      if (other.IsKinematic()) {
        auto known = std::find_if(
            kinematic_of.begin(), kinematic_of.end(),
            [&](const auto& known_body) { return known_body.first == pair.other_body; });
        if (known == kinematic_of.end()) {
          const KinematicPose pose = other.motion->PoseAt(t);
          const KinematicMotion::Twist twist = other.motion->StepTwist(t, h);
          p.kinematic.push_back({pose.p, pose.q.toRotationMatrix(), twist.v, twist.w});
          kinematic_of.emplace_back(pair.other_body, static_cast<int>(p.kinematic.size()) - 1);
          known = kinematic_of.end() - 1;
        }
        cp.other_kind = Other::kKinematic;
        cp.other = known->second;
      } else {
        cp.other_kind = Other::kBody;
        cp.other = IslandIndex(island, pair.other_body);
      }
    }
    p.contacts.push_back(std::move(cp));
  }
  // the grippers whose jaws are in the island (both are: FormIslands joins them)
  for (const Gripper& gripper : scene.grippers) {
    const auto jaw = std::find(island.bodies.begin(), island.bodies.end(), gripper.jaws[0]);
    if (jaw == island.bodies.end()) continue;
    const int jaw0 = static_cast<int>(jaw - island.bodies.begin());
    const int jaw1 = IslandIndex(island, gripper.jaws[1]);
    p.grippers.push_back(
        MakeIslandGripper(gripper, p.bodies[jaw0], p.bodies[jaw1], jaw0, jaw1, t, h));
    SetGripperFreeFlight(p.grippers.back(), p.bodies);
  }
  return p;
}

bool MakeIslandScales(const Scene& scene, const Island& island, const IslandProblem& problem,
                      const IslandState& state, IslandScales& scales,
                      std::vector<FailedAttempt>& tried) {
  scales.bodies.clear();
  for (size_t i = 0; i < island.bodies.size(); ++i) {
    const BodyProblem& body = problem.bodies[i];
    scales.bodies.push_back(
        BodyScales(scene.bodies[island.bodies[i]], state.bodies[i], body.p_ext, problem.h));
    if (!FreeFlightIsFinite(body, tried)) return false;
  }
  RaiseToGripperDrive(problem, scales);
  RaiseToIslandVelocity(problem, scales);
  return true;
}

bool Coupled(const IslandProblem& problem) {
  return std::any_of(problem.contacts.begin(), problem.contacts.end(),
                     [](const IslandContact& cp) { return cp.other_kind != Other::kFixed; });
}

void RaiseToGripperDrive(const IslandProblem& problem, IslandScales& scales) {
  for (const IslandGripper& g : problem.grippers) {
    for (int j = 0; j < 2; ++j) {
      Scales& s = scales.bodies[g.jaws[j]];
      const double mass = problem.bodies[g.jaws[j]].mass;
      const double drive = g.v[j].norm() + g.w[j].norm() * s.length + g.grip / mass;
      if (s.velocity >= drive) continue;
      s.velocity = drive;
      s.impulse = mass * drive;
    }
  }
}

void RaiseToIslandVelocity(const IslandProblem& problem, IslandScales& scales) {
  double velocity = 0;
  for (const Scales& s : scales.bodies) velocity = std::max(velocity, s.velocity);
  for (const IslandContact& cp : problem.contacts) {
    if (cp.other_kind != Other::kKinematic) continue;
    const KinematicBody& g = problem.kinematic[cp.other];
    velocity = std::max(velocity, g.v.norm() + g.w.norm() * scales.bodies[cp.body].length);
  }
  if (!Coupled(problem)) return;
  for (size_t b = 0; b < scales.bodies.size(); ++b) {
    Scales& s = scales.bodies[b];
    if (s.velocity >= velocity) continue;
    s.velocity = velocity;
    s.impulse = problem.bodies[b].mass * velocity;
  }
}

void SetStickCreep(const IslandScales& scales, IslandProblem& problem) {
  if (!Coupled(problem)) return;
  for (IslandContact& cp : problem.contacts)
    cp.stick_creep = kStickCreepFraction * scales.bodies[cp.body].velocity;
}

Matrix3d PredictedRotation(const IslandProblem& problem, int b) {
  const BodyProblem& body = problem.bodies[b];
  return ExpMap(problem.h * body.w) * body.R;
}

Matrix3d PredictedOtherRotation(const IslandProblem& problem, const IslandContact& cp) {
  if (cp.other_kind == Other::kBody) return PredictedRotation(problem, cp.other);
  const KinematicBody& g = problem.kinematic[cp.other];
  return ExpMap(problem.h * g.w) * g.R;
}

bool FlatOnOneFace(const ContactState& c) {
  const auto* warm = c.warm_start.Get<HullWarmStart>();
  if (warm == nullptr || !(c.p_n > 0) || warm->l.size() == 0) return false;
  const double largest = warm->l.maxCoeff();
  if (!(largest > 0)) return false;
  return (warm->l.array() > kDegenerateActiveFraction * largest).count() == 1;
}

void SelectWindows(const SolverSettings& settings, const IslandState& state,
                   IslandProblem& problem) {
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    IslandContact& cp = problem.contacts[k];
    const Vector3d& n = state.contacts[k].n;
    // a contact that ended the last step flat on one face takes one ring fewer: the faces at
    // the support vertex hold that face, and the window check grows the window where the ECP
    // reaches another (engine/README.md, "Large hulls: the window")
    const bool flat = problem.bodies.size() == 1 && cp.other_kind == Other::kFixed &&
                      FlatOnOneFace(state.contacts[k]);
    // ... and a fixed obstacle's contact without a warm start (a body placed on the ground, or
    // touching it for the first time) one ring more: nothing tells yet where on its hull the ECP
    // will go, and a root found in too small a window is solved again once it has grown
    const bool first = cp.other_kind == Other::kFixed &&
                       !(state.contacts[k].warm_start.Get<HullWarmStart>() != nullptr);
    const int rings = std::max(settings.window_rings - (flat ? 1 : 0), 0) + (first ? 1 : 0);
    cp.window = SelectWindow(*cp.hull, PredictedRotation(problem, cp.body).transpose() * -n, rings,
                             settings.use_window);
    if (cp.other_kind != Other::kFixed) {
      cp.other_window =
          SelectWindow(*cp.other_shape, PredictedOtherRotation(problem, cp).transpose() * n,
                       settings.window_rings, settings.use_window);
    }
  }
}

std::pair<Eigen::Isometry3d, Eigen::Isometry3d> StartPoses(const IslandProblem& problem,
                                                           const IslandContact& cp) {
  const auto pose = [](const Vector3d& c, const Matrix3d& R) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = R;
    X.translation() = c;
    return X;
  };
  const BodyProblem& body = problem.bodies[cp.body];
  if (cp.other_kind == Other::kBody) {
    const BodyProblem& other = problem.bodies[cp.other];
    return {pose(body.c, body.R), pose(other.c, other.R)};
  }
  const KinematicBody& g = problem.kinematic[cp.other];
  return {pose(body.c, body.R), pose(g.c, g.R)};
}

void SeparatePairs(const IslandProblem& problem, const IslandScales& scales, IslandState& state,
                   std::vector<double>& overlaps) {
  overlaps.assign(problem.contacts.size(), 0.0);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    if (cp.other_kind == Other::kFixed) continue;
    Vector3d& n = state.contacts[k].n;
    const auto [X_F, X_G] = StartPoses(problem, cp);
    overlaps[k] = -geometry::SeparationAlong(*cp.hull, X_F, *cp.other_shape, X_G, n).separation;
    if (state.contacts[k].p_n > 0 ||
        overlaps[k] <= kNegligibleDepthRel * scales.bodies[cp.body].length) {
      continue;
    }
    const geometry::AxisSeparation best =
        geometry::BestSeparatingAxis(*cp.hull, X_F, *cp.other_shape, X_G, {n});
    n = best.axis;
    overlaps[k] = -best.separation;
  }
}

double EjectionEnergy(const IslandProblem& problem, const IslandState& state,
                      const IslandScales& scales, const std::vector<double>& overlaps) {
  double depth = 0;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const BodyProblem& body = problem.bodies[cp.body];
    const Vector3d& n = state.contacts[k].n;
    if (cp.other_kind == Other::kFixed) {
      // F's deepest point along the last normal: a lower bound of the depth, exact for a
      // half-space
      const Vector3d lowest = WorldSupport(*cp.hull, body.c, body.R, -n);
      const double g = cp.other_shape->Value(LargestConstraint(*cp.other_shape, lowest), lowest);
      depth = std::max(depth, -g);
      continue;
    }
    // the overlap of the two hulls' extents along the normal bounds the depth from above
    // (SeparatePairs made it the best candidate axis), and is the depth of a resting or pushed
    // pair. Where the candidates leave an overlap, the depth is measured (GJK and EPA): an
    // overlap that is not one (two cylinders side by side, crossed edges) would let the
    // contact give the bodies energy they never had
    double pair_depth = overlaps[k];
    const double length = scales.bodies[cp.body].length;
    if (pair_depth > kNegligibleDepthRel * length) {
      const auto [X_F, X_G] = StartPoses(problem, cp);
      pair_depth = std::min(
          pair_depth, geometry::PenetrationDepth(*cp.hull, X_F, *cp.other_shape, X_G, length));
    }
    depth = std::max(depth, pair_depth);
  }
  const double speed = depth / problem.h;
  double energy = 0;
  for (const BodyProblem& body : problem.bodies)
    energy += body.mass * speed * speed + body.p_ext.head<3>().norm() * speed;
  return energy;
}

void CarryByFace(const std::vector<int>& from_window, const VectorXd& from, int from_at,
                 const std::vector<int>& to_window, VectorXd& to, int to_at) {
  for (size_t i = 0; i < to_window.size(); ++i) {
    const auto it = std::find(from_window.begin(), from_window.end(), to_window[i]);
    if (it != from_window.end()) to[to_at + i] = from[from_at + (it - from_window.begin())];
  }
}

VectorXd RemapWindows(const IslandProblem& from, const IslandLayout& from_layout, const VectorXd& z,
                      const IslandProblem& to, const IslandLayout& to_layout) {
  VectorXd out = VectorXd::Zero(to_layout.size);
  out.head(IslandLayout::Velocity(to_layout.num_bodies)) =
      z.head(IslandLayout::Velocity(from_layout.num_bodies));
  for (size_t k = 0; k < to.contacts.size(); ++k) {
    const MncpLayout::Contact& A = from_layout.contacts[k];
    const MncpLayout::Contact& B = to_layout.contacts[k];
    // the free block (a1 … p_r: 10 unknowns, 6 on a plane) and G's multipliers (none on a plane)
    out.segment(B.a1, B.p_r + 1 - B.a1) = z.segment(A.a1, A.p_r + 1 - A.a1);
    if (B.l_g_count > 0)
      CarryByFace(from.contacts[k].other_window, z, A.l_g, to.contacts[k].other_window, out, B.l_g);
    out[B.p_n] = z[A.p_n];
    out[B.sigma] = z[A.sigma];
    CarryByFace(from.contacts[k].window, z, A.l, to.contacts[k].window, out, B.l);
  }
  return out;
}

}  // namespace ecpsim::engine::hull
