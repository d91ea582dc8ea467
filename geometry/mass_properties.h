#pragma once
// Volume, centre of mass and inertia of the solid bounded by a closed triangle mesh.

#include <string>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// m³; a closed mesh enclosing no more than this (a 0.1 mm cube) is flat or degenerate, not a body.
inline constexpr double kMinVolume = 1e-12;

struct MassProperties {
  double volume = 0;                   // m³
  double mass = 0;                     // kg
  Eigen::Vector3d center_of_mass;      // m, in the mesh frame
  Eigen::Matrix3d inertia;             // kg·m², about the centre of mass, mesh-frame axes
  Eigen::Vector3d principal_moments;   // kg·m², ascending
  Eigen::Matrix3d principal_axes;      // columns: unit axes of principal_moments, right-handed
};

/// Mass properties of the solid bounded by `mesh` (metres) at uniform `density` (kg/m³).
/// An inward-wound closed mesh is handled (the sign of the volume is flipped).
/// @throws InputError if the mesh is open, inconsistently wound, or encloses ≤ kMinVolume, or if
///         `density` is not finite and > 0. `source` names the mesh in the message.
MassProperties ComputeMassProperties(const TriangleMesh& mesh, double density,
                                     const std::string& source = "mesh");

/// As ComputeMassProperties, with the density chosen so the total mass is `mass` kg.
MassProperties ComputeMassPropertiesForMass(const TriangleMesh& mesh, double mass,
                                            const std::string& source = "mesh");

}  // namespace ecpsim::geometry
