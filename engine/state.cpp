#include "engine/state.h"

#include <algorithm>

#include "engine/obstacle_queries.h"

namespace ecpsim::engine {

bool IsFinite(const BodyState& body) {
  return body.p_WB.allFinite() && body.Q_WB.coeffs().allFinite() && body.v_WB.allFinite() &&
         body.w_WB.allFinite();
}

Eigen::Isometry3d PoseOf(const BodyState& body) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = body.Q_WB.toRotationMatrix();
  X.translation() = body.p_WB;
  return X;
}

void AdvanceTime(double h, State& state) {
  ++state.steps;
  state.t = static_cast<double>(state.steps) * h;
}

State InitialState(const Scene& scene) {
  State state;
  state.t = 0;
  for (const Body& body : scene.bodies) {
    BodyState b;
    b.p_WB = body.p0;
    b.Q_WB = body.q0.normalized();
    b.v_WB = body.v0;
    b.w_WB = body.w0;
    if (body.IsKinematic()) {
      // its motion's pose at t = 0, and its first step's twist once the step is known
      const KinematicPose pose = body.motion->PoseAt(0);
      b.p_WB = pose.p;
      b.Q_WB = pose.q;
      b.v_WB = b.w_WB = Eigen::Vector3d::Zero();
    }
    state.bodies.push_back(b);
  }
  for (const ContactPair& pair : scene.contacts) {
    ContactState c;
    const Eigen::Vector3d& p = state.bodies[pair.body].p_WB;
    if (pair.WithBody()) {
      // from G's centre toward F's: the side of G that F faces
      const Eigen::Vector3d d = p - state.bodies[pair.other_body].p_WB;
      c.n = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitZ();
    } else {
      c.n = ObstacleNormalToward(*scene.obstacles[pair.obstacle].shape, p);
    }
    c.a1 = c.a2 = p;
    state.contacts.push_back(c);
  }
  return state;
}

}  // namespace ecpsim::engine
