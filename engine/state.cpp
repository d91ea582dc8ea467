#include "engine/state.h"

#include <algorithm>

#include "engine/obstacle_queries.h"

namespace ecpsim::engine {

bool IsFinite(const BodyState& body) {
  return body.p_WB.allFinite() && body.Q_WB.coeffs().allFinite() && body.v_WB.allFinite() &&
         body.w_WB.allFinite();
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
    state.bodies.push_back(b);
  }
  for (const ContactPair& pair : scene.contacts) {
    ContactState c;
    const Obstacle& obstacle = scene.obstacles[pair.obstacle];
    c.n = ObstacleNormalToward(*obstacle.shape, scene.bodies[pair.body].p0);
    c.a1 = c.a2 = scene.bodies[pair.body].p0;
    state.contacts.push_back(c);
  }
  return state;
}

}  // namespace ecpsim::engine
