#pragma once
// 2-D overlay geometry in pixels (thick segments, dots, rings, arrows, glyph quads), built on the
// CPU each frame and drawn in one call; and stencil-filled polygons of any shape.

#include <vector>

#include <Eigen/Core>

namespace ecpsim::render {

/// RGBA in [0, 1].
using Rgba = Eigen::Vector4f;

/// A point of the overlay: x right and y down in pixels, z the OpenGL depth (NDC, −1 near to
/// 1 far) for overlays tested against the scene, 0 for flat 2-D overlays.
using Pixel = Eigen::Vector3d;

/// Triangles in pixel coordinates with depth, each vertex with a colour and a texture coordinate
/// (used only when the batch is drawn textured).
class OverlayBatch {
 public:
  void Clear() { data_.clear(); }
  bool empty() const { return data_.empty(); }

  void Triangle(const Pixel& a, const Pixel& b, const Pixel& c, const Rgba& colour);
  /// A segment `width` pixels wide with square ends extended by `width`/2 (so joined segments and
  /// dots meet without gaps).
  void Segment(const Pixel& a, const Pixel& b, double width, const Rgba& colour);
  /// A closed polygon outline with round joins (bevelled where the turn is so slight that the
  /// two differ by less than 0.02 pixels).
  void Outline(const std::vector<Pixel>& polygon, double width, const Rgba& colour);
  /// A filled disc; a ring when `inner_radius` > 0.
  void Disc(const Pixel& centre, double radius, const Rgba& colour, double inner_radius = 0);
  /// An arrow from `tail` to `head` with a triangular head `head_size` pixels long.
  void Arrow(const Pixel& tail, const Pixel& head, double width, double head_size,
             const Rgba& colour);
  /// An axis-aligned rectangle [x0, x1] × [y0, y1] with texture coordinates [u0, u1] × [v0, v1].
  void Rectangle(double x0, double y0, double x1, double y1, const Rgba& colour, double u0 = 0,
                 double v0 = 0, double u1 = 0, double v1 = 0);

  /// Floats per vertex: x, y, z, r, g, b, a, u, v.
  static constexpr int kFloatsPerVertex = 9;
  const std::vector<float>& data() const { return data_; }

 private:
  void Vertex(const Pixel& p, const Rgba& colour, double u = 0, double v = 0);
  std::vector<float> data_;
};

/// Draws batches and polygon fills with the overlay program; depth testing off, alpha blending on.
/// Needs a current GlContext for its whole life.
class OverlayDrawer {
 public:
  OverlayDrawer();
  ~OverlayDrawer();
  OverlayDrawer(const OverlayDrawer&) = delete;
  OverlayDrawer& operator=(const OverlayDrawer&) = delete;

  /// Draws `batch` with the overlay program and the depth/blend state set by the caller;
  /// `atlas` ≠ 0 binds that R8 glyph texture for a textured draw.
  void Draw(const OverlayBatch& batch, unsigned atlas = 0);

  /// Fills the union of `polygons` (simple, possibly non-convex, pairwise disjoint) with `colour`
  /// by even-odd stencil counting, so no triangulation is needed, and clears the stencil after.
  /// With `depth_tested`, parts hidden by the scene are drawn with their alpha scaled by
  /// `hidden_alpha` (an x-ray view); without it, the fill lies on top of everything. The overlay
  /// program must be in use; its u_alpha_scale is left at 1.
  void FillPolygons(const std::vector<std::vector<Pixel>>& polygons, const Rgba& colour,
                    bool depth_tested, float hidden_alpha, int alpha_scale_uniform);

 private:
  unsigned vao_ = 0, vbo_ = 0;
};

}  // namespace ecpsim::render
