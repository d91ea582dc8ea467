#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

// Every length here is relative to the camera's distance from its target (or, for automatic
// framing, to the bodies' bounding spheres), so that a scene in millimetres or kilometres gives
// the frame of the same scene in metres.

// the framed spheres fill at most this fraction of the smaller field of view
constexpr double kFramingFill = 0.8;
// automatic framing with nothing to frame (no bodies) looks at a sphere of this radius
constexpr double kEmptyFrameRadius = 0.1;  // m
// eye and target within this fraction of their distance from the origin are one point (rounding);
// up within this sine of the view direction is parallel
constexpr double kSameEyeAndTarget = 1e-12;
constexpr double kMinUpSine = 1e-6;
// the near plane: this fraction of the distance to the target, so bodies near the eye still draw
constexpr double kNearFraction = 0.02;
// the far plane: past the ground sheets' far corners (kGroundHalfExtent distances around the
// target's foot, which lies within about a distance of the eye) and past every body
constexpr double kFarMargin = 1.25;
// a point at most this fraction of its distance in front of the eye plane counts as behind it
constexpr double kBehindEye = 1e-12;

std::string Format(const Eigen::Vector3d& v) {
  return fmt::format("({}, {}, {})", v.x(), v.y(), v.z());
}

}  // namespace

double GroundHalfExtent(const Camera& camera) {
  return kGroundHalfExtent * (camera.target - camera.eye).norm();
}

bool Camera::ToPixel(const Eigen::Vector3d& p_W, Eigen::Vector3d* pixel) const {
  const Eigen::Vector4d clip = view_projection * p_W.homogeneous();
  if (!(clip.w() > kBehindEye * (p_W - eye).norm())) return false;
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  *pixel = Eigen::Vector3d((ndc.x() + 1) * 0.5 * width, (1 - ndc.y()) * 0.5 * height, ndc.z());
  return true;
}

Camera MakeCamera(const CameraSpec& spec, const std::vector<BoundingSphere>& spheres, int width,
                  int height) {
  if (!spec.position.allFinite() || !spec.target.allFinite() || !spec.up.allFinite() ||
      !std::isfinite(spec.fov_y_deg)) {
    throw InputError(
        fmt::format("camera: position {}, target {}, up {}, fov {}: expected finite values",
                    Format(spec.position), Format(spec.target), Format(spec.up), spec.fov_y_deg));
  }
  if (!(spec.fov_y_deg > 1 && spec.fov_y_deg < 170)) {
    throw InputError(fmt::format(
        "camera: fov = {}: expected a vertical field of view in (1, 170) degrees", spec.fov_y_deg));
  }
  Eigen::Vector3d direction = spec.position - spec.target;  // target → eye
  if (!(direction.norm() > kSameEyeAndTarget * (spec.position.norm() + spec.target.norm()))) {
    throw InputError(fmt::format("camera: position {} equals target {}: expected distinct points",
                                 Format(spec.position), Format(spec.target)));
  }
  if (spec.up.cross(direction).norm() < kMinUpSine * spec.up.norm() * direction.norm()) {
    throw InputError(
        fmt::format("camera: up {} is parallel to the viewing direction {}: expected a "
                    "different up vector",
                    Format(spec.up), Format(direction)));
  }

  const double fov_y = spec.fov_y_deg * M_PI / 180;
  const double aspect = static_cast<double>(width) / height;
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.target = spec.target;
  camera.eye = spec.position;
  if (spec.automatic) {
    // the union of the spheres, as one sphere around their centroid
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const BoundingSphere& s : spheres) centre += s.centre;
    if (!spheres.empty()) centre /= static_cast<double>(spheres.size());
    double radius = 0;
    for (const BoundingSphere& s : spheres) {
      radius = std::max(radius, (s.centre - centre).norm() + s.radius);
    }
    if (!(radius > 0)) radius = kEmptyFrameRadius;
    const double half_fov = 0.5 * std::min(fov_y, 2 * std::atan(std::tan(fov_y / 2) * aspect));
    const double distance = radius / std::sin(half_fov * kFramingFill);
    camera.target = centre;
    camera.eye = centre + direction.normalized() * distance;
  }

  // view: right-handed look-at, camera looking down its −z
  const Eigen::Vector3d f = (camera.target - camera.eye).normalized();
  const Eigen::Vector3d s = f.cross(spec.up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = s.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -s.dot(camera.eye);
  view(1, 3) = -u.dot(camera.eye);
  view(2, 3) = f.dot(camera.eye);

  // projection: OpenGL perspective with depth range [near, far]
  const double distance = (camera.target - camera.eye).norm();
  const double near = kNearFraction * distance;
  double far = (2 + std::sqrt(2.0) * kGroundHalfExtent) * distance;
  for (const BoundingSphere& sphere : spheres) {
    far = std::max(far, (sphere.centre - camera.eye).norm() + sphere.radius);
  }
  far *= kFarMargin;
  const double cot = 1 / std::tan(fov_y / 2);
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = cot / aspect;
  projection(1, 1) = cot;
  projection(2, 2) = (far + near) / (near - far);
  projection(2, 3) = 2 * far * near / (near - far);
  projection(3, 2) = -1;

  camera.view = view;
  camera.projection = projection;
  camera.view_projection = projection * view;
  return camera;
}

}  // namespace ecpsim::render
