#pragma once
// The wrench a contact's impulses exert over a step, as forces: what a force/torque sensor on a
// kinematic finger reads, and the average contact force of every pair.

#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// A force and its moment about a reference point, world axes.
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // N·m
};

/// The average wrench that contact `k` exerted on its G side over the step of length `h` that
/// ended in `state` (the contact state's impulses are the step's, summed over sub-steps): the
/// force −(n p_n + t p_t + o p_o)/h at a2 and the torsional moment −n p_r/h, with the moment
/// taken about G's frame origin at the end of the step (the body's reference point p) when G is
/// a body, about the world origin when G is an obstacle. Equal and opposite to what it exerted
/// on F (at a1 = a2 while touching).
Wrench WrenchOnOther(const Scene& scene, const State& state, int k, double h);

/// The contacts a force/torque sensor on kinematic body `body` senses: those whose G side it is
/// (a kinematic body is never a contact's F), in the scene's order.
std::vector<int> SensedContacts(const Scene& scene, int body);

/// What a force/torque sensor on kinematic body `body` read over the step that ended in
/// `state`: the sum of WrenchOnOther over its SensedContacts, moments about its reference point.
Wrench SensorWrench(const Scene& scene, const State& state, int body);

}  // namespace ecpsim::engine
