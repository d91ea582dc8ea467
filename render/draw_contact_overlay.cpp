// The contact overlays: patch faces, edges and points, the patch hull, the ECP, the centre-of-mass
// projection and the force arrow, in the main view and in the top-down inset.

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "render/draw_context.h"
#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// sizes in pixels at pixel_scale 1 (240–480 rows)
constexpr double kEdgeWidth = 4.0;
constexpr double kPointRadius = 4.0;
constexpr double kHullWidth = 2.0;
constexpr double kEcpRadius = 5.0;
constexpr double kEcpRim = 1.5;
constexpr double kCmRadius = 7.0;
constexpr double kCmWidth = 2.5;
constexpr double kForceWidth = 3.0;
constexpr double kForceHead = 12.0;
// the inset: its side as a fraction of the image height, and its margin
constexpr double kInsetFraction = 0.42;
constexpr double kInsetMargin = 8.0;
// patch features hidden by a body are drawn with this fraction of their opacity (x-ray view)
constexpr float kHiddenAlpha = 0.4f;
// the smallest region the inset shows, so a single point does not zoom without bound, in
// distances from the camera to its target (0.02 × 2.5 m: 5 cm for the paper's bodies)
constexpr double kInsetMinExtent = 0.02;
// planes within these tolerances are the same plane for the inset (offsets in camera distances)
constexpr double kSamePlaneNormal = 1e-9;
constexpr double kSamePlaneOffset = 1e-9;

// maps a world point to an overlay pixel (with depth, or z = 0 for flat views); false if hidden
using ToPixel = std::function<bool(const Eigen::Vector3d&, Pixel*)>;

std::vector<Pixel> Project(const std::vector<Eigen::Vector3d>& points, const ToPixel& to_pixel) {
  std::vector<Pixel> pixels;
  for (const auto& p : points) {
    Pixel q;
    if (!to_pixel(p, &q)) return {};
    pixels.push_back(q);
  }
  return pixels;
}

// every contact's features through one world → pixel map (the main camera or the inset's); with
// `depth_tested`, patch features hidden by the bodies are drawn faded, markers always on top
void DrawContacts(const std::vector<const ContactVisual*>& contacts, const ToPixel& to_pixel,
                  double scale, double force_scale, bool depth_tested, DrawContext& context) {
  UseOverlayProgram(context, false);
  const int alpha_scale = context.overlay_program.Uniform("u_alpha_scale");

  // patch faces first, filled
  std::vector<std::vector<Pixel>> faces;
  for (const ContactVisual* contact : contacts) {
    for (const auto& polygon : contact->patch.polygons) {
      auto pixels = Project(polygon, to_pixel);
      if (pixels.size() >= 3) faces.push_back(std::move(pixels));
    }
  }
  context.overlay.FillPolygons(faces, palette::kPatchFace, depth_tested, kHiddenAlpha, alpha_scale);

  // patch edges, points and hull
  OverlayBatch features;
  Pixel a, b;
  for (const ContactVisual* contact : contacts) {
    const geometry::ContactPatch& patch = contact->patch;
    // a line contact's hull segment runs under its segments; a polygon hull outlines on top
    const auto hull = Project(patch.hull, to_pixel);
    if (hull.size() == 2) {
      features.Segment(hull[0], hull[1], kHullWidth * scale, palette::kPatchHull);
    }
    for (const auto& segment : patch.segments) {
      if (to_pixel(segment[0], &a) && to_pixel(segment[1], &b)) {
        features.Segment(a, b, kEdgeWidth * scale, palette::kPatchEdge);
      }
    }
    for (const auto& point : patch.points) {
      if (to_pixel(point, &a)) features.Disc(a, kPointRadius * scale, palette::kPatchPoint);
    }
    if (hull.size() >= 3) features.Outline(hull, kHullWidth * scale, palette::kPatchHull);
  }
  if (depth_tested) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    context.overlay.Draw(features);
    glDepthFunc(GL_GREATER);
    glUniform1f(alpha_scale, kHiddenAlpha);
    context.overlay.Draw(features);
    glUniform1f(alpha_scale, 1.0f);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
  } else {
    context.overlay.Draw(features);
  }

  // force arrows, centre-of-mass rings and ECPs on top of everything
  OverlayBatch markers;
  for (const ContactVisual* contact : contacts) {
    if (force_scale > 0 && contact->force && contact->a1) {
      const Eigen::Vector3d tip = *contact->a1 + force_scale * *contact->force;
      if (to_pixel(*contact->a1, &a) && to_pixel(tip, &b)) {
        markers.Arrow(a, b, kForceWidth * scale, kForceHead * scale, palette::kForce);
      }
    }
  }
  for (const ContactVisual* contact : contacts) {
    if (contact->cm_projection && to_pixel(*contact->cm_projection, &a)) {
      markers.Disc(a, (kCmRadius + kEcpRim) * scale, palette::kMarkerRim,
                   (kCmRadius - kCmWidth - kEcpRim) * scale);
      markers.Disc(a, kCmRadius * scale, palette::kCentreOfMass, (kCmRadius - kCmWidth) * scale);
    }
  }
  for (const ContactVisual* contact : contacts) {
    if (contact->a1 && to_pixel(*contact->a1, &a)) {
      markers.Disc(a, (kEcpRadius + kEcpRim) * scale, palette::kMarkerRim);
      markers.Disc(a, kEcpRadius * scale, palette::kEcp);
    }
  }
  context.overlay.Draw(markers);
}

// a 1, 2 or 5 × 10^k length not above `limit`
double NiceLength(double limit) {
  const double decade = std::pow(10.0, std::floor(std::log10(limit)));
  for (double step : {5.0, 2.0, 1.0}) {
    if (step * decade <= limit) return step * decade;
  }
  return decade;
}

// a scale-bar length in the unit that keeps its number between 1 and 999 (ASCII "um": the font
// atlas holds ASCII only)
std::string LengthLabel(double metres) {
  if (metres >= 1e3) return fmt::format("{:g} km", std::round(metres) / 1e3);
  if (metres >= 1) return fmt::format("{:g} m", metres);
  if (metres >= 0.01) return fmt::format("{:g} cm", std::round(metres * 1e4) / 1e2);
  if (metres >= 1e-3) return fmt::format("{:g} mm", std::round(metres * 1e6) / 1e3);
  return fmt::format("{:g} um", std::round(metres * 1e9) / 1e3);
}

}  // namespace

void UseOverlayProgram(DrawContext& context, bool textured) {
  context.overlay_program.Use();
  glUniform2f(context.overlay_program.Uniform("u_viewport"), float(context.target.width()),
              float(context.target.height()));
  glUniform1i(context.overlay_program.Uniform("u_textured"), textured ? 1 : 0);
  glUniform1i(context.overlay_program.Uniform("u_atlas"), 0);
  glUniform1f(context.overlay_program.Uniform("u_alpha_scale"), 1.0f);
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
}

void DrawContactOverlay(const FrameInput& frame, DrawContext& context) {
  std::vector<const ContactVisual*> contacts;
  for (const ContactVisual& contact : frame.contacts) contacts.push_back(&contact);
  const ToPixel to_pixel = [&](const Eigen::Vector3d& p, Pixel* q) {
    return context.camera.ToPixel(p, q);
  };
  DrawContacts(contacts, to_pixel, context.pixel_scale,
               frame.show.force_arrow ? frame.force_scale : 0, true, context);
}

void DrawContactInset(const FrameInput& frame, DrawContext& context) {
  if (!frame.show.inset) return;

  // the contacts on the plane of the first contact that has anything to show
  const ContactVisual* first = nullptr;
  for (const ContactVisual& contact : frame.contacts) {
    if (contact.patch.mode != geometry::ContactMode::kNone || contact.a1) {
      first = &contact;
      break;
    }
  }
  if (first == nullptr) return;
  const Eigen::Vector3d n = first->plane.normal.normalized();
  const double camera_distance = (context.camera.target - context.camera.eye).norm();  // m
  std::vector<const ContactVisual*> contacts;
  for (const ContactVisual& contact : frame.contacts) {
    if ((contact.plane.normal.normalized() - n).norm() < kSamePlaneNormal &&
        std::abs(contact.plane.offset - first->plane.offset) < kSamePlaneOffset * camera_distance) {
      contacts.push_back(&contact);
    }
  }

  // plane axes: u along the main camera's right direction, so the inset turns with the view
  const Eigen::Vector3d right = context.camera.view.block<1, 3>(0, 0).transpose();
  Eigen::Vector3d u = right - right.dot(n) * n;
  if (u.norm() < 1e-6) u = Eigen::Vector3d::UnitX() - n.x() * n;
  u.normalize();
  const Eigen::Vector3d v = n.cross(u);

  // bounds of everything shown, in plane coordinates
  Eigen::Vector2d lo(1e30, 1e30), hi(-1e30, -1e30);
  const auto extend = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d q(u.dot(p), v.dot(p));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  };
  for (const ContactVisual* contact : contacts) {
    for (const auto& polygon : contact->patch.polygons)
      for (const auto& p : polygon) extend(p);
    for (const auto& segment : contact->patch.segments) {
      extend(segment[0]);
      extend(segment[1]);
    }
    for (const auto& p : contact->patch.points) extend(p);
    if (contact->a1) extend(*contact->a1);
    if (contact->cm_projection) extend(*contact->cm_projection);
  }
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  const double extent =
      std::max({hi.x() - lo.x(), hi.y() - lo.y(), kInsetMinExtent * camera_distance});

  // the panel, top-right, with room for a title above and a scale bar below the plot
  const double s = context.pixel_scale;
  const int side = static_cast<int>(std::round(kInsetFraction * context.target.height()));
  const int x0 = context.target.width() - side - static_cast<int>(std::round(kInsetMargin * s));
  const int y0 = static_cast<int>(std::round(kInsetMargin * s));
  context.target.ClearRect(x0, y0, side, side, {0.99f, 0.99f, 0.99f, 1.0f});
  const double line = context.font.line_height();
  const double plot_top = y0 + line + 4 * s, plot_bottom = y0 + side - line - 6 * s;
  const double plot_size = std::min(plot_bottom - plot_top, side - 12 * s);
  const double scale = 0.82 * plot_size / extent;  // pixels per metre
  const Eigen::Vector2d plot_centre(x0 + 0.5 * side, 0.5 * (plot_top + plot_bottom));
  const ToPixel to_pixel = [&](const Eigen::Vector3d& p, Pixel* q) {
    *q = Pixel(plot_centre.x() + scale * (u.dot(p) - centre.x()),
               plot_centre.y() - scale * (v.dot(p) - centre.y()), 0);
    return true;
  };
  DrawContacts(contacts, to_pixel, s, 0, false, context);

  // border, scale bar and labels
  OverlayBatch shapes, text;
  shapes.Outline({{x0 + 0.5, y0 + 0.5, 0},
                  {x0 + side - 0.5, y0 + 0.5, 0},
                  {x0 + side - 0.5, y0 + side - 0.5, 0},
                  {x0 + 0.5, y0 + side - 0.5, 0}},
                 s, palette::kPanelBorder);
  const double bar = NiceLength(0.3 * side / scale);
  const double bar_y = y0 + side - 0.5 * line - 3 * s;
  const double bar_x = x0 + 8 * s;
  shapes.Segment({bar_x, bar_y, 0}, {bar_x + bar * scale, bar_y, 0}, 2 * s, palette::kText);
  // the mode as a title where it fits (the text overlay names it too)
  const std::string mode = geometry::ContactModeName(first->patch.mode);
  if (context.font.TextWidth(mode) <= side - 12 * s) {
    context.font.AddText(text, mode, x0 + 6 * s, y0 + 3 * s + context.font.ascender(),
                         palette::kText);
  }
  context.font.AddText(text, LengthLabel(bar), bar_x + bar * scale + 6 * s,
                       bar_y + 0.35 * context.font.ascender(), palette::kText);
  UseOverlayProgram(context, false);
  context.overlay.Draw(shapes);
  UseOverlayProgram(context, true);
  context.overlay.Draw(text, context.font.texture());
}

}  // namespace ecpsim::render
