#pragma once
// Volume, centre of mass and inertia of the solid bounded by a closed triangle mesh.

#include <string>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

struct MassProperties {
  double volume = 0;                  // m³
  double mass = 0;                    // kg
  Eigen::Vector3d center_of_mass;     // m, in the mesh frame
  Eigen::Matrix3d inertia;            // kg·m², about the centre of mass, mesh-frame axes
  Eigen::Vector3d principal_moments;  // kg·m², ascending
  Eigen::Matrix3d principal_axes;     // columns: unit axes of principal_moments, right-handed
};

/// Mass properties of the solid bounded by `mesh` (metres) at uniform `density` (kg/m³).
/// An inward-wound closed mesh is handled (the sign of the volume is flipped). Every threshold is
/// relative to the mesh's own size, so a 0.1 mm part and a 1 km hull are treated alike.
/// The results are checked as every solid's are: volume above round-off (> 1e-12 × bounding-box
/// diagonal³), positive principal moments obeying I1 + I2 ≥ I3, and the centre of mass inside the
/// vertices' bounding polytope; parts wound against each other fail these.
/// @throws InputError if the mesh is open, inconsistently wound, flat, outside the size range of
///         geometry/mesh_bounds.h, fails those checks, or if `density` is not finite and > 0 or
///         makes mass or inertia leave the double range. `source` names the mesh in the message.
MassProperties ComputeMassProperties(const TriangleMesh& mesh, double density,
                                     const std::string& source = "mesh");

/// As ComputeMassProperties, with the density chosen so the total mass is `mass` kg.
MassProperties ComputeMassPropertiesForMass(const TriangleMesh& mesh, double mass,
                                            const std::string& source = "mesh");

}  // namespace ecpsim::geometry
