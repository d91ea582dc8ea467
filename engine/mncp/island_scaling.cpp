#include "engine/mncp/island_scaling.h"

#include <algorithm>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Other = IslandContact::Other;

// a vector of the island's scales: each body's part at its ν⁺ in its own Scales, each contact's
// block in ContactScales
template <typename BodyPart, typename ContactPart>
void IslandScaleVector(const IslandProblem& problem, const IslandLayout& layout,
                       const IslandScales& scales, BodyPart body_part, ContactPart contact_part,
                       Eigen::VectorXd& scale) {
  scale.setOnes(layout.size);
  for (int b = 0; b < layout.num_bodies; ++b)
    body_part(IslandLayout::Velocity(b), scales.bodies[b], scale);
  for (size_t k = 0; k < layout.contacts.size(); ++k) {
    contact_part(layout.contacts[k], problem.contacts[k].friction,
                 ContactScales(problem, scales, static_cast<int>(k)), scale);
  }
}

}  // namespace

Scales ContactScales(const IslandProblem& problem, const IslandScales& scales, int contact) {
  ECPSIM_DEMAND(scales.bodies.size() == problem.bodies.size());
  const IslandContact& cp = problem.contacts[contact];
  const Scales& body = scales.bodies[cp.body];
  if (cp.other_kind != Other::kBody) return body;
  const Scales& other = scales.bodies[cp.other];
  return {std::min(body.length, other.length), std::min(body.velocity, other.velocity),
          std::min(body.impulse, other.impulse)};
}

void IslandVariableScales(const IslandProblem& problem, const IslandLayout& layout,
                          const IslandScales& scales, Eigen::VectorXd& scale) {
  IslandScaleVector(problem, layout, scales, SetVelocityScales, SetContactVariableScales, scale);
}

Eigen::VectorXd IslandVariableScales(const IslandProblem& problem, const IslandLayout& layout,
                                     const IslandScales& scales) {
  Eigen::VectorXd scale;
  IslandVariableScales(problem, layout, scales, scale);
  return scale;
}

void IslandRowScales(const IslandProblem& problem, const IslandLayout& layout,
                     const IslandScales& scales, Eigen::VectorXd& scale) {
  IslandScaleVector(problem, layout, scales, SetNewtonEulerRowScales, SetContactRowScales, scale);
}

Eigen::VectorXd IslandRowScales(const IslandProblem& problem, const IslandLayout& layout,
                                const IslandScales& scales) {
  Eigen::VectorXd scale;
  IslandRowScales(problem, layout, scales, scale);
  return scale;
}

IslandResidualUnits MakeIslandResidualUnits(const IslandProblem& problem,
                                            const IslandScales& scales, double tolerance) {
  IslandResidualUnits units;
  MakeIslandResidualUnits(problem, scales, tolerance, units);
  return units;
}

void MakeIslandResidualUnits(const IslandProblem& problem, const IslandScales& scales,
                             double tolerance, IslandResidualUnits& units) {
  units.tolerance = tolerance;
  units.body_length.clear();
  units.contact_length.clear();
  units.contact_coordinates.clear();
  for (const Scales& s : scales.bodies) units.body_length.push_back(s.length);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    units.contact_length.push_back(ContactScales(problem, scales, static_cast<int>(k)).length);
    double coordinates = problem.bodies[cp.body].c.cwiseAbs().maxCoeff();
    if (cp.other_kind == Other::kBody) {
      coordinates = std::max(coordinates, problem.bodies[cp.other].c.cwiseAbs().maxCoeff());
    } else if (cp.other_kind == Other::kKinematic) {
      coordinates = std::max(coordinates, problem.kinematic[cp.other].c.cwiseAbs().maxCoeff());
    }
    units.contact_coordinates.push_back(coordinates);
  }
}

double IslandEnergyScale(const IslandProblem& problem, const IslandScales& scales) {
  double energy = 0;
  for (size_t b = 0; b < problem.bodies.size(); ++b)
    energy += EnergyScale(problem.bodies[b], scales.bodies[b]);
  return energy;
}

}  // namespace ecpsim::engine
