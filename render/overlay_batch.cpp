#include "render/overlay_batch.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// circle tessellation: a chord deviates from the arc by less than this, so MSAA sees round dots
constexpr double kMaxChordError = 0.15;  // pixels
constexpr int kMinCircleSegments = 12;
constexpr int kMaxCircleSegments = 96;
// a polygon outline's corner is bevelled (2 triangles) instead of rounded (a disc of ≥ 12) where
// the round join's arc lies within this of the bevel's chord: far below a supersample, so no
// sample changes in practice, while the many slight corners of a round patch's hull (the 100k
// torus: 250 corners turning 1.4° each, 0.0002 px) cost ~5 ms less per frame on llvmpipe
constexpr double kMaxBevelError = 0.02;  // pixels

int CircleSegments(double radius) {
  const int n = static_cast<int>(
      std::ceil(M_PI / std::acos(std::max(0.0, 1 - kMaxChordError / std::max(radius, 1e-3)))));
  return std::clamp(n, kMinCircleSegments, kMaxCircleSegments);
}

}  // namespace

void OverlayBatch::Vertex(const Pixel& p, const Rgba& colour, double u, double v) {
  data_.insert(data_.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                             static_cast<float>(p.z()), colour[0], colour[1], colour[2], colour[3],
                             static_cast<float>(u), static_cast<float>(v)});
}

void OverlayBatch::Triangle(const Pixel& a, const Pixel& b, const Pixel& c, const Rgba& colour) {
  Vertex(a, colour);
  Vertex(b, colour);
  Vertex(c, colour);
}

void OverlayBatch::Segment(const Pixel& a, const Pixel& b, double width, const Rgba& colour) {
  Eigen::Vector2d along = (b - a).head<2>();
  const double length = along.norm();
  along = length > 1e-9 ? Eigen::Vector2d(along / length) : Eigen::Vector2d::UnitX();
  const Pixel d(along.x() * 0.5 * width, along.y() * 0.5 * width, 0);
  const Pixel n(-d.y(), d.x(), 0);
  const Pixel p0 = a - d - n, p1 = b + d - n, p2 = b + d + n, p3 = a - d + n;
  Triangle(p0, p1, p2, colour);
  Triangle(p0, p2, p3, colour);
}

void OverlayBatch::Outline(const std::vector<Pixel>& polygon, double width, const Rgba& colour) {
  const size_t n = polygon.size();
  // each edge's unit direction (zero for a degenerate edge)
  std::vector<Eigen::Vector2d> along(n, Eigen::Vector2d::Zero());
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d edge = (polygon[(i + 1) % n] - polygon[i]).head<2>();
    if (edge.norm() > 1e-9) along[i] = edge.normalized();
  }
  const double half = 0.5 * width;
  const auto offset = [half](const Eigen::Vector2d& u) {
    return Pixel(-u.y() * half, u.x() * half, 0);
  };
  for (size_t i = 0; i < n; ++i) {
    const Pixel& a = polygon[i];
    const Pixel& b = polygon[(i + 1) % n];
    // a segment without extended ends plus a join at each corner
    if (along[i].squaredNorm() > 0) {
      const Pixel m = offset(along[i]);
      Triangle(a - m, b - m, b + m, colour);
      Triangle(a - m, b + m, a + m, colour);
    }
    // the join at a: round, except where the turn is so slight that a bevel looks the same
    const Eigen::Vector2d& in = along[(i + n - 1) % n];
    const Eigen::Vector2d& out = along[i];
    const double cos_turn = in.dot(out);
    const bool slight = in.squaredNorm() > 0 && out.squaredNorm() > 0 && cos_turn > 0 &&
                        half * (1 - std::sqrt(0.5 * (1 + cos_turn))) < kMaxBevelError;
    if (slight) {
      const Pixel m_in = offset(in), m_out = offset(out);
      Triangle(a, a + m_in, a + m_out, colour);
      Triangle(a, a - m_in, a - m_out, colour);
    } else {
      Disc(a, half, colour);
    }
  }
}

void OverlayBatch::Disc(const Pixel& centre, double radius, const Rgba& colour,
                        double inner_radius) {
  const int segments = CircleSegments(radius);
  for (int i = 0; i < segments; ++i) {
    const double t0 = 2 * M_PI * i / segments, t1 = 2 * M_PI * (i + 1) / segments;
    const Pixel u0(std::cos(t0), std::sin(t0), 0), u1(std::cos(t1), std::sin(t1), 0);
    if (inner_radius > 0) {
      Triangle(centre + inner_radius * u0, centre + radius * u0, centre + radius * u1, colour);
      Triangle(centre + inner_radius * u0, centre + radius * u1, centre + inner_radius * u1,
               colour);
    } else {
      Triangle(centre, centre + radius * u0, centre + radius * u1, colour);
    }
  }
}

void OverlayBatch::Arrow(const Pixel& tail, const Pixel& head, double width, double head_size,
                         const Rgba& colour) {
  const Eigen::Vector2d along = (head - tail).head<2>();
  const double length = along.norm();
  if (length < 1e-9) return;
  const Pixel u(along.x() / length, along.y() / length, 0);
  const Pixel n(-u.y(), u.x(), 0);
  const double head_length = std::min(head_size, 0.5 * length);
  const Pixel base = head - u * head_length;
  const Pixel m = n * (0.5 * width);
  Triangle(tail - m, base - m, base + m, colour);
  Triangle(tail - m, base + m, tail + m, colour);
  Triangle(head, base + n * (0.45 * head_length), base - n * (0.45 * head_length), colour);
}

void OverlayBatch::Rectangle(double x0, double y0, double x1, double y1, const Rgba& colour,
                             double u0, double v0, double u1, double v1) {
  Vertex({x0, y0, 0}, colour, u0, v0);
  Vertex({x1, y0, 0}, colour, u1, v0);
  Vertex({x1, y1, 0}, colour, u1, v1);
  Vertex({x0, y0, 0}, colour, u0, v0);
  Vertex({x1, y1, 0}, colour, u1, v1);
  Vertex({x0, y1, 0}, colour, u0, v1);
}

OverlayDrawer::OverlayDrawer() {
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  const GLsizei stride = OverlayBatch::kFloatsPerVertex * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(7 * sizeof(float)));
  glBindVertexArray(0);
}

OverlayDrawer::~OverlayDrawer() {
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
}

void OverlayDrawer::Draw(const OverlayBatch& batch, unsigned atlas) {
  if (batch.empty()) return;
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(batch.data().size() * sizeof(float)),
               batch.data().data(), GL_STREAM_DRAW);
  if (atlas != 0) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, atlas);
  }
  glDrawArrays(GL_TRIANGLES, 0,
               static_cast<GLsizei>(batch.data().size() / OverlayBatch::kFloatsPerVertex));
  glBindVertexArray(0);
}

void OverlayDrawer::FillPolygons(const std::vector<std::vector<Pixel>>& polygons,
                                 const Rgba& colour, bool depth_tested, float hidden_alpha,
                                 int alpha_scale_uniform) {
  // fans from each polygon's first vertex cover every interior point an odd number of times
  OverlayBatch fans;
  for (const auto& polygon : polygons) {
    for (size_t i = 1; i + 1 < polygon.size(); ++i) {
      fans.Triangle(polygon[0], polygon[i], polygon[i + 1], colour);
    }
  }
  if (fans.empty()) return;

  // pass 1: invert the stencil under every fan triangle, whatever the depth, colour untouched
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0x01);
  glStencilFunc(GL_ALWAYS, 0, 0x01);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INVERT);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  Draw(fans);

  // pass 2: colour where the count is odd, once per pixel (the stencil is reset where drawn);
  // the fans again as cover, since their depth is the polygons' depth
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glStencilFunc(GL_EQUAL, 1, 0x01);
  glStencilOp(GL_KEEP, GL_KEEP, GL_ZERO);
  glDepthMask(GL_FALSE);
  if (depth_tested) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    Draw(fans);
    // pass 3: the hidden rest, faded
    glDepthFunc(GL_GREATER);
    glUniform1f(alpha_scale_uniform, hidden_alpha);
    Draw(fans);
    glUniform1f(alpha_scale_uniform, 1.0f);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
  } else {
    Draw(fans);
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_STENCIL_TEST);
}

}  // namespace ecpsim::render
