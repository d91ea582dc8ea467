#pragma once
// The area moments of a contact patch: what a uniformly compliant patch's elastic energy under a
// load depends on (engine/README.md, "Steps whose solutions form a set").

#include <Eigen/Core>

#include "geometry/contact_patch.h"

namespace ecpsim::geometry {

/// A patch's area A, centroid and second moments about the centroid along its principal axes
/// (u1, u2 in the plane, I1 ≥ I2 ≥ 0: ∫ (u1·(x − centroid))² dA and ∫ (u2·(x − centroid))² dA).
struct PatchMoments {
  double area = 0;                                     // m²
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world, on the plane
  Eigen::Vector3d u1 = Eigen::Vector3d::UnitX();       // principal axes (unit, world) ...
  Eigen::Vector3d u2 = Eigen::Vector3d::UnitY();
  double I1 = 0, I2 = 0;  // m⁴, ... and the second moments along them
};

/// The moments of `patch`'s polygons (their union; segments and points carry no area) on
/// `plane`. Zero area where the patch has no polygon.
PatchMoments MomentsOf(const ContactPatch& patch, const Plane& plane);

}  // namespace ecpsim::geometry
