#include "geometry/mass_properties.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "common/errors.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::geometry {
namespace {

// a closed mesh whose |volume| is below this fraction of (bounding-box diagonal)³ is flat up to
// round-off (a double-sided sheet integrates to ~1e-16 diag³), whatever its absolute size
constexpr double kFlatVolumeFraction = 1e-12;

// volume integrals of the solid about a reference point r: V, ∫(x − r) dV, ∫(x − r)(x − r)ᵀ dV
struct VolumeIntegrals {
  double volume = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
};

// divergence theorem over signed tetrahedra (r, a, b, c), one per triangle: with a, b, c taken
// relative to r and D = a·(b×c), the tetrahedron has volume D/6, first moment D/24 (a + b + c)
// and second moment D/120 (aaᵀ + bbᵀ + ccᵀ + ssᵀ), s = a + b + c (the canonical tetrahedron's
// covariance mapped by [a b c]; cf. libigl / Eberly "Polyhedral Mass Properties")
VolumeIntegrals IntegrateVolume(const TriangleMesh& mesh, const Eigen::Vector3d& reference) {
  VolumeIntegrals integrals;
  double volume6 = 0;
  Eigen::Vector3d first24 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second120 = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]] - reference;
    const Eigen::Vector3d b = mesh.vertices[t[1]] - reference;
    const Eigen::Vector3d c = mesh.vertices[t[2]] - reference;
    const double d = a.dot(b.cross(c));
    const Eigen::Vector3d s = a + b + c;
    volume6 += d;
    first24 += d * s;
    second120 +=
        d * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  integrals.volume = volume6 / 6.0;
  integrals.first = first24 / 24.0;
  integrals.second = second120 / 120.0;
  return integrals;
}

}  // namespace

MassProperties ComputeMassProperties(const TriangleMesh& mesh, double density,
                                     const std::string& source) {
  if (!std::isfinite(density) || density <= 0.0) {
    throw InputError(
        fmt::format("{}: density = {}: expected a finite density > 0 kg/m³", source, density));
  }
  if (mesh.triangles.empty()) {
    throw InputError(
        fmt::format("{}: mesh has no triangles; mass properties need a closed surface", source));
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw InputError(fmt::format("{}: vertex {} has a non-finite coordinate", source, i));
    }
  }

  // only the boundary of a solid encloses a volume
  const MeshTopology topology = AnalyzeTopology(mesh);
  if (!topology.closed) {
    throw InputError(
        fmt::format("{}: mesh is open ({} boundary edges, {} non-manifold edges); mass properties "
                    "need a closed "
                    "surface (repair the mesh, or use its convex hull)",
                    source, topology.boundary_edges, topology.non_manifold_edges));
  }
  if (!topology.consistently_oriented) {
    throw InputError(fmt::format(
        "{}: mesh is inconsistently oriented (neighbouring triangles wound in opposite senses); "
        "mass properties need a consistently oriented closed surface",
        source));
  }

  // integrate about the bounding-box centre: coordinates far from the origin then lose nothing
  Eigen::Vector3d lo = mesh.vertices.front();
  Eigen::Vector3d hi = lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d reference = 0.5 * (lo + hi);
  VolumeIntegrals integrals = IntegrateVolume(mesh, reference);

  // an inward-wound closed mesh integrates to the negated integrals
  if (integrals.volume < 0.0) {
    integrals.volume = -integrals.volume;
    integrals.first = -integrals.first;
    integrals.second = -integrals.second;
  }
  const double diagonal = (hi - lo).norm();
  const double flat_volume = kFlatVolumeFraction * diagonal * diagonal * diagonal;
  if (integrals.volume <= kMinVolume || integrals.volume <= flat_volume) {
    throw InputError(fmt::format(
        "{}: mesh encloses a volume of {:.3g} m³ (at most {:.3g} m³): it is flat or degenerate, "
        "not a solid",
        source, integrals.volume, std::max(kMinVolume, flat_volume)));
  }

  // centre of mass, then the second moment about it (parallel-axis shift)
  MassProperties props;
  props.volume = integrals.volume;
  props.mass = density * integrals.volume;
  const Eigen::Vector3d offset = integrals.first / integrals.volume;
  props.center_of_mass = reference + offset;
  Eigen::Matrix3d covariance = integrals.second - integrals.volume * offset * offset.transpose();
  covariance = 0.5 * (covariance + covariance.transpose());
  props.inertia = density * (covariance.trace() * Eigen::Matrix3d::Identity() - covariance);

  // principal moments ascending, axes as a right-handed rotation
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(props.inertia);
  ECPSIM_DEMAND(solver.info() == Eigen::Success);
  props.principal_moments = solver.eigenvalues();
  props.principal_axes = solver.eigenvectors();
  if (props.principal_axes.determinant() < 0.0) props.principal_axes.col(2) *= -1.0;
  return props;
}

MassProperties ComputeMassPropertiesForMass(const TriangleMesh& mesh, double mass,
                                            const std::string& source) {
  if (!std::isfinite(mass) || mass <= 0.0) {
    throw InputError(fmt::format("{}: mass = {}: expected a finite mass > 0 kg", source, mass));
  }
  // the geometry at unit density, then scaled: inertia is linear in the density
  MassProperties props = ComputeMassProperties(mesh, 1.0, source);
  const double density = mass / props.volume;
  props.mass = mass;
  props.inertia *= density;
  props.principal_moments *= density;
  return props;
}

}  // namespace ecpsim::geometry
