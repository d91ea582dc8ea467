#pragma once
// The perspective camera: view and projection matrices, automatic framing, world → pixel mapping.

#include <vector>

#include <Eigen/Core>

#include "render/frame_input.h"

namespace ecpsim::render {

/// A sphere enclosing one posed body (world, m), for automatic framing.
struct BoundingSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
};

/// A camera fixed for one frame of `width` × `height` pixels.
struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // m, world
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();        // world → eye
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();  // eye → clip (OpenGL convention)
  Eigen::Matrix4d view_projection = Eigen::Matrix4d::Identity();
  int width = 1, height = 1;

  /// Pixel position of world point `p_W`: x right, y down from the top-left corner (pixels,
  /// continuous, pixel centres at +0.5), and z its OpenGL depth (NDC, −1 at the near plane, 1 at
  /// the far plane). Returns false (and leaves `pixel` unchanged) for a point at or behind the
  /// eye plane.
  bool ToPixel(const Eigen::Vector3d& p_W, Eigen::Vector3d* pixel) const;
};

/// Half the side of a ground sheet, in distances from the eye to the target: the sheet is centred
/// under the target and fades out before its edge (draw_bodies.cpp), so it fills the view up to
/// where it fades into the background at any scale.
inline constexpr double kGroundHalfExtent = 4;

/// kGroundHalfExtent × |target − eye|, m.
double GroundHalfExtent(const Camera& camera);

/// The camera of `spec`; for automatic framing it looks at the union of `spheres` (empty: a
/// 0.1 m sphere at the origin) from the direction of spec.position − spec.target, far enough away
/// that the union fits the smaller field of view with a margin. The near plane is at 0.02 of the
/// distance to the target, the far plane past the ground sheet (GroundHalfExtent) and every
/// sphere: every length scales with the scene, so a scene scaled by s is framed alike.
/// @throws InputError if the spec is non-finite, the field of view is outside (1°, 170°), the eye
///         coincides with the target (within rounding), or `up` is parallel to the viewing
///         direction.
Camera MakeCamera(const CameraSpec& spec, const std::vector<BoundingSphere>& spheres, int width,
                  int height);

}  // namespace ecpsim::render
