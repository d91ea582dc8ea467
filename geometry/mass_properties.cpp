#include "geometry/mass_properties.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "common/errors.h"
#include "geometry/mesh_bounds.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::geometry {
namespace {

// a closed mesh whose |volume| is below this fraction of (bounding-box diagonal)³ is flat up to
// round-off (a double-sided sheet integrates to ~1e-16 diag³), whatever its absolute size: a
// 0.1 mm microrobot part and a 1 km hull are judged alike
constexpr double kFlatVolumeFraction = 1e-12;

// dimensionless, × the largest principal moment: how far the triangle inequality I1 + I2 ≥ I3
// may fail by round-off. I1 + I2 − I3 = 2 × the smallest eigenvalue of the second moment about
// the centre of mass, whose round-off is a few ulps of V·diag² per summed triangle (≤ 2e-10 of
// I3 for 10⁶ triangles); a part wound inside out violates it by O(1)
constexpr double kInertiaRoundOff = 1e-9;

// dimensionless, × the bounding-box diagonal: how far outside the vertices' bounding polytope the
// computed centre of mass may lie by round-off (first moment / volume: a few ulps of diag)
constexpr double kCenterOfMassRoundOff = 1e-9;

// the 13 directions (up to sign) of a 26-sided bounding polytope (faces, edges and corners of a
// cube): a cheap enclosure of the vertices' convex hull, much tighter than the bounding box
constexpr double kPolytopeDirections[13][3] = {
    {1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
    {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};

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

// throws unless the centre of mass lies in the vertices' 26-sided bounding polytope (it lies in
// their convex hull for every solid of positive density)
void CheckCenterOfMassInside(const TriangleMesh& mesh, const Eigen::Vector3d& center,
                             double diagonal, const std::string& source) {
  // the extent of the vertices along each direction, in one pass over them
  constexpr int kDirections = 13;
  Eigen::Matrix<double, kDirections, 3> directions;
  for (int d = 0; d < kDirections; ++d) {
    const auto& x = kPolytopeDirections[d];
    directions.row(d) = Eigen::Vector3d(x[0], x[1], x[2]).normalized().transpose();
  }
  Eigen::Matrix<double, kDirections, 1> lo =
      Eigen::Matrix<double, kDirections, 1>::Constant(std::numeric_limits<double>::infinity());
  Eigen::Matrix<double, kDirections, 1> hi = -lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    const Eigen::Matrix<double, kDirections, 1> x = directions * v;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Eigen::Matrix<double, kDirections, 1> x = directions * center;
  const double slack = kCenterOfMassRoundOff * diagonal;
  if ((x.array() < lo.array() - slack).any() || (x.array() > hi.array() + slack).any()) {
    throw InputError(fmt::format(
        "{}: the centre of mass ({:.6g}, {:.6g}, {:.6g}) m lies outside the mesh's vertices; "
        "the parts of the mesh are probably wound in opposite senses (a mirrored or inside-out "
        "part), which a solid's mass properties cannot come from",
        source, center.x(), center.y(), center.z()));
  }
}

// throws unless the principal moments are positive and obey the triangle inequality, as every
// solid's do (the smallest two add up to at least the largest)
void CheckPrincipalMoments(const Eigen::Vector3d& moments, const std::string& source) {
  const bool positive = moments[0] > 0.0;
  const bool triangle = moments[0] + moments[1] >= moments[2] * (1.0 - kInertiaRoundOff);
  if (!positive || !triangle) {
    throw InputError(fmt::format(
        "{}: the principal moments of inertia ({:.6g}, {:.6g}, {:.6g}) are {}; the parts of the "
        "mesh are probably wound in opposite senses (a mirrored or inside-out part), which a "
        "solid's mass properties cannot come from",
        source, moments[0], moments[1], moments[2],
        positive ? "not a triangle (I1 + I2 < I3)" : "not all positive"));
  }
}

// throws unless mass and inertia are finite, positive numbers at full precision (an extreme
// density can push them past the double range or into subnormals)
void CheckRepresentable(const MassProperties& props, const std::string& source) {
  const bool ok = std::isnormal(props.mass) && props.mass > 0.0 && props.inertia.allFinite() &&
                  props.principal_moments.allFinite() && std::isnormal(props.principal_moments[2]);
  if (!ok) {
    throw InputError(fmt::format(
        "{}: density {:.3g} kg/m³ over a volume of {:.3g} m³ gives a mass of {:.3g} kg and "
        "principal moments up to {:.3g} kg·m², beyond the range of double precision; expected a "
        "realistic density or mass",
        source, props.mass / props.volume, props.volume, props.mass, props.principal_moments[2]));
  }
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

  // within the size range, L⁵ (the inertia) neither overflows nor underflows
  const MeshBounds bounds = ComputeMeshBounds(mesh.vertices);
  if (!IsInSupportedSizeRange(bounds)) {
    throw InputError(fmt::format(
        "{}: the mesh is {:.3g} m across (bounding-box diagonal; largest |coordinate| {:.3g} m); "
        "expected {}",
        source, bounds.diagonal, bounds.max_abs, SupportedSizeRangeText()));
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
  const Eigen::Vector3d reference = 0.5 * (bounds.lo + bounds.hi);
  VolumeIntegrals integrals = IntegrateVolume(mesh, reference);

  // an inward-wound closed mesh integrates to the negated integrals
  if (integrals.volume < 0.0) {
    integrals.volume = -integrals.volume;
    integrals.first = -integrals.first;
    integrals.second = -integrals.second;
  }
  const double diagonal = bounds.diagonal;
  const double flat_volume = kFlatVolumeFraction * diagonal * diagonal * diagonal;
  if (integrals.volume <= flat_volume) {
    throw InputError(fmt::format(
        "{}: mesh encloses a volume of {:.3g} m³, at most {:g} × its bounding-box diagonal³ "
        "({:.3g} m³): it is flat or degenerate, not a solid",
        source, integrals.volume, kFlatVolumeFraction, flat_volume));
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

  // what every solid satisfies; parts wound against each other (a mirrored node, an inside-out
  // part) integrate to numbers that fail here
  CheckRepresentable(props, source);
  CheckPrincipalMoments(props.principal_moments, source);
  CheckCenterOfMassInside(mesh, props.center_of_mass, diagonal, source);
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
  CheckRepresentable(props, source);
  return props;
}

}  // namespace ecpsim::geometry
