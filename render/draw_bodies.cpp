// The 3-D passes of a frame: ground sheets with a metric grid, shaded bodies, translucent hulls.
// Sizes are in pixels or relative to the camera's distance from its target, never in metres.

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/draw_context.h"
#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// key light from above, behind the default camera's left shoulder (world, towards the light)
const Eigen::Vector3f kLightDirection = Eigen::Vector3f(-0.35f, -0.55f, 1.0f).normalized();
const Rgba kHullFace(0.45f, 0.62f, 0.95f, 0.22f);
// a closed hull is drawn with its back faces culled: one layer of this opacity covers its
// silhouette between one layer of kHullFace (what tints a body inside it) and the two that
// tinted the ground around the body before culling (1 − (1 − 0.22)² = 0.39)
constexpr float kHullFrontAlpha = 0.3f;
// a mesh whose front triangles cover fewer drawing pixels than this on average is lit per vertex
// (the vertex-lit program, opaque): its triangles are a few image pixels wide, so lighting
// interpolated across them looks the same (the 100k torus at 1280×720: at most 10 levels at the
// specular highlight, none above the golden threshold), while llvmpipe shades each small
// triangle's 4 × 4 pixel blocks with the full lighting: ~10 ms of the torus's CPU per frame
constexpr double kDenseTrianglePixels = 32;

// hull edges between faces closer than this to coplanar (a tessellated cylinder's facets) are
// drawn only on the silhouette
constexpr double kSmoothEdgeCos = 0.94;  // cos(20°)

void SetMatrix(const ShaderProgram& program, const char* name, const Eigen::Matrix4d& m) {
  const Eigen::Matrix4f f = m.cast<float>();
  glUniformMatrix4fv(program.Uniform(name), 1, GL_FALSE, f.data());
}

void SetVector(const ShaderProgram& program, const char* name, const Eigen::Vector3d& v) {
  glUniform3f(program.Uniform(name), static_cast<float>(v.x()), static_cast<float>(v.y()),
              static_cast<float>(v.z()));
}

void UseMeshProgram(const ShaderProgram& program, const DrawContext& context) {
  program.Use();
  SetMatrix(program, "u_view_projection", context.camera.view_projection);
  SetVector(program, "u_eye", context.camera.eye);
  glUniform3fv(program.Uniform("u_light_dir"), 1, kLightDirection.data());
}

void DrawPosedMesh(const ShaderProgram& program, const GpuMesh& mesh, const Eigen::Isometry3d& X_WB,
                   const Rgba& colour) {
  SetMatrix(program, "u_model", X_WB.matrix());
  const Eigen::Matrix3f R = X_WB.linear().cast<float>();
  glUniformMatrix3fv(program.Uniform("u_normal_matrix"), 1, GL_FALSE, R.data());
  glUniform4fv(program.Uniform("u_color"), 1, colour.data());
  mesh.Draw();
}

// a unit vector in the plane, along world x where possible so the grid lines up with the axes
Eigen::Vector3d PlaneAxis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d seed =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (seed - seed.dot(n) * n).normalized();
}

// the ground's look: sheet and line colours and line widths (image pixels at the camera
// target's distance)
const Eigen::Vector3f kSheetColour(0.86f, 0.87f, 0.89f);
const Eigen::Vector3f kMinorColour(0.74f, 0.76f, 0.80f);
const Eigen::Vector3f kMajorColour(0.52f, 0.55f, 0.62f);
constexpr double kMinorWidth = 1.0;  // pixels
constexpr double kMajorWidth = 1.8;  // pixels
// the grid is metric at every scale: major lines every power of ten of metres not above this
// many camera distances (0.2 to 2 distances: 1 m for the paper's bodies framed from 1–5 m),
// minor lines every tenth of that
constexpr double kMajorSpacingDistances = 2;
constexpr double kMinorPerMajor = 10;
// minor lines fade out between these on-screen spacings (pixels), before they turn into moiré
constexpr double kMinorFadeStart = 10, kMinorFadeEnd = 4;
// the sheet fades into the background from this fraction of its half extent (squared radius)
constexpr double kFadeStart = 0.3;
// grid lines are cut into this many pieces so their opacity follows the fades smoothly
constexpr int kLinePieces = 40;
constexpr int kSheetCells = 16;  // per side
// a minor line within this fraction of a major spacing of a major line is that line
constexpr double kSameLine = 1e-6;

// the largest power of ten (m) not above `limit` (m)
double PowerOfTenBelow(double limit) { return std::pow(10.0, std::floor(std::log10(limit))); }

// vertices of position (3 floats) + colour (4 floats)
class GroundMesh {
 public:
  void Vertex(const Eigen::Vector3d& p, const Eigen::Vector3f& rgb, float alpha) {
    data_.insert(data_.end(),
                 {float(p.x()), float(p.y()), float(p.z()), rgb.x(), rgb.y(), rgb.z(), alpha});
  }
  const std::vector<float>& data() const { return data_; }

 private:
  std::vector<float> data_;
};

// true if the convex quad a, b, c, d lies wholly outside one plane of the view frustum (clip-space
// half-spaces are linear in homogeneous coordinates, so the test holds for points behind the eye
// too): such a grid piece would only cost vertex work
bool OutsideFrustum(const Eigen::Matrix4d& view_projection, const Eigen::Vector3d& a,
                    const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  Eigen::Matrix4d corners;
  corners << a, b, c, d, Eigen::RowVector4d::Ones();
  const Eigen::Matrix4d clip = view_projection * corners;
  for (int axis = 0; axis < 3; ++axis) {
    if ((clip.row(axis).array() > clip.row(3).array()).all()) return true;
    if ((clip.row(axis).array() < -clip.row(3).array()).all()) return true;
  }
  return false;
}

void DrawGroundMesh(const GroundMesh& mesh) {
  if (mesh.data().empty()) return;
  GLuint vao = 0, vbo = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.data().size() * sizeof(float)),
               mesh.data().data(), GL_STREAM_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 7 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(mesh.data().size() / 7));
  glBindVertexArray(0);
  glDeleteBuffers(1, &vbo);
  glDeleteVertexArrays(1, &vao);
}

}  // namespace

void DrawPlanes(const FrameInput& frame, DrawContext& context) {
  if (frame.planes.empty()) return;
  const Camera& camera = context.camera;
  const ShaderProgram& program = context.ground_program;
  program.Use();
  SetMatrix(program, "u_view_projection", camera.view_projection);
  const Eigen::Vector3f background(kBackground[0], kBackground[1], kBackground[2]);
  // metres per drawing pixel per metre of distance from the eye: 2 tan(fov/2) / height
  const double pixel_per_distance = 2.0 / (camera.projection(1, 1) * camera.height);
  const double target_distance = (camera.target - camera.eye).norm();
  const double pixel_at_target = context.pixel_scale * target_distance * pixel_per_distance;  // m
  const double major_spacing = PowerOfTenBelow(kMajorSpacingDistances * target_distance);     // m
  const double minor_spacing = major_spacing / kMinorPerMajor;                                // m
  const double R = GroundHalfExtent(camera);                                                  // m
  for (const PlaneVisual& visual : frame.planes) {
    const Eigen::Vector3d n = visual.plane.normal.normalized();
    const Eigen::Vector3d u = PlaneAxis(n);
    const Eigen::Vector3d v = n.cross(u);
    // the sheet is centred under the camera target; grid lines are anchored at the world
    // origin's projection so the grid stays fixed in space
    const Eigen::Vector3d origin = visual.plane.offset * n;
    const Eigen::Vector3d centre = camera.target - (n.dot(camera.target) - visual.plane.offset) * n;
    const auto point = [&](double a, double b) { return Eigen::Vector3d(centre + a * u + b * v); };
    const auto fade = [&](const Eigen::Vector3d& p) {
      const double r2 = (p - centre).squaredNorm() / (R * R);
      return static_cast<float>(std::clamp((r2 - kFadeStart) / (1 - kFadeStart), 0.0, 1.0));
    };

    // the sheet: a grid of cells whose vertex colours fade into the background
    GroundMesh sheet;
    for (int i = 0; i < kSheetCells; ++i) {
      for (int j = 0; j < kSheetCells; ++j) {
        const double a0 = -R + 2 * R * i / kSheetCells, a1 = -R + 2 * R * (i + 1) / kSheetCells;
        const double b0 = -R + 2 * R * j / kSheetCells, b1 = -R + 2 * R * (j + 1) / kSheetCells;
        const Eigen::Vector3d corners[4] = {point(a0, b0), point(a1, b0), point(a1, b1),
                                            point(a0, b1)};
        if (OutsideFrustum(camera.view_projection, corners[0], corners[1], corners[2],
                           corners[3])) {
          continue;
        }
        for (int k : {0, 1, 2, 0, 2, 3}) {
          const float f = fade(corners[k]);
          const Eigen::Vector3f colour = kSheetColour * (1 - f) + background * f;
          sheet.Vertex(corners[k], colour, 1.0f);
        }
      }
    }
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    // the sheet lies slightly behind its grid lines and behind faces resting on it
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 4.0f);
    DrawGroundMesh(sheet);
    glDisable(GL_POLYGON_OFFSET_FILL);

    // grid lines: quads on the plane, a few pixels wide at the target's distance, cut in pieces
    // whose opacity follows the rim fade and, for minor lines, the on-screen spacing
    GroundMesh lines;
    const Eigen::Vector2d c(u.dot(centre - origin), v.dot(centre - origin));
    const int pieces = kLinePieces;
    const auto add_lines = [&](double spacing, double width_px, const Eigen::Vector3f& colour,
                               bool minor) {
      const double half_width = 0.5 * width_px * pixel_at_target;
      for (int axis = 0; axis < 2; ++axis) {
        const double c_across = axis == 0 ? c.x() : c.y();
        const Eigen::Vector3d across = axis == 0 ? u : v, along = axis == 0 ? v : u;
        const long first = static_cast<long>(std::ceil((c_across - R) / spacing));
        const long last = static_cast<long>(std::floor((c_across + R) / spacing));
        for (long k = first; k <= last; ++k) {
          // major lines belong to the major pass only
          const double at = static_cast<double>(k) * spacing;
          if (minor && std::abs(std::remainder(at, major_spacing)) < kSameLine * major_spacing) {
            continue;
          }
          const double offset = at - c_across;
          const auto alpha = [&](const Eigen::Vector3d& q) {
            double opacity = 1 - fade(q);
            if (minor) {
              const double spacing_px =
                  spacing / ((q - camera.eye).norm() * pixel_per_distance * context.pixel_scale);
              opacity *= std::clamp(
                  (spacing_px - kMinorFadeEnd) / (kMinorFadeStart - kMinorFadeEnd), 0.0, 1.0);
            }
            return static_cast<float>(opacity);
          };
          for (int p = 0; p < pieces; ++p) {
            const double s0 = -R + 2 * R * p / pieces, s1 = -R + 2 * R * (p + 1) / pieces;
            const Eigen::Vector3d a = centre + offset * across + s0 * along;
            const Eigen::Vector3d b = centre + offset * across + s1 * along;
            const Eigen::Vector3d w = half_width * across;
            if (OutsideFrustum(camera.view_projection, a - w, b - w, b + w, a + w)) continue;
            const float alpha_a = alpha(a), alpha_b = alpha(b);
            if (alpha_a <= 0 && alpha_b <= 0) continue;
            lines.Vertex(a - w, colour, alpha_a);
            lines.Vertex(b - w, colour, alpha_b);
            lines.Vertex(b + w, colour, alpha_b);
            lines.Vertex(a - w, colour, alpha_a);
            lines.Vertex(b + w, colour, alpha_b);
            lines.Vertex(a + w, colour, alpha_a);
          }
        }
      }
    };
    add_lines(minor_spacing, kMinorWidth, kMinorColour, true);
    add_lines(major_spacing, kMajorWidth, kMajorColour, false);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthFunc(GL_LEQUAL);
    DrawGroundMesh(lines);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
}

void DrawBodies(const FrameInput& frame, DrawContext& context) {
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  const Camera& camera = context.camera;
  // focal length in drawing pixels: a sphere of radius r at distance d spans r·focal/d pixels
  const double focal = 0.5 * camera.projection(1, 1) * camera.height;
  const ShaderProgram* current = nullptr;
  // meshes from files may be wound either way: GpuMesh culls back faces only of closed,
  // outward-wound meshes
  for (const BodyVisual& body : frame.bodies) {
    if (!body.mesh) continue;
    const GpuMesh& mesh = context.meshes.Get(body.mesh);
    // a dense mesh's front half spread over its silhouette: small triangles are lit per vertex
    const double distance = (body.X_WB * mesh.centre() - camera.eye).norm();
    bool dense = false;
    if (distance > mesh.radius()) {
      const double radius_px = mesh.radius() * focal / distance;
      const double front_triangles = 0.5 * mesh.triangle_count();
      dense = M_PI * radius_px * radius_px < kDenseTrianglePixels * front_triangles;
    }
    const ShaderProgram& program = dense ? context.vertex_lit_program : context.mesh_program;
    if (current != &program) UseMeshProgram(program, context);
    current = &program;
    const Rgba colour(body.colour.x(), body.colour.y(), body.colour.z(), 1.0f);
    DrawPosedMesh(program, mesh, body.X_WB, colour);
  }
}

void DrawHulls(const FrameInput& frame, DrawContext& context) {
  if (!frame.show.hull) return;

  // translucent faces: tested against the bodies but not hiding each other; pulled slightly
  // towards the camera so that hull faces lying on body faces (the desk's top) win cleanly
  // instead of fighting over depth; lit per vertex (hull faces are flat, and translucent)
  UseMeshProgram(context.vertex_lit_program, context);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(-1.0f, -4.0f);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  for (const BodyVisual& body : frame.bodies) {
    if (!body.hull || body.hull->mesh.triangles.empty()) continue;
    // the aliasing pointer shares the hull's ownership, so the cache tracks the hull's lifetime
    const std::shared_ptr<const geometry::TriangleMesh> mesh(body.hull, &body.hull->mesh);
    const GpuMesh& gpu = context.meshes.Get(mesh);
    Rgba colour = kHullFace;
    if (gpu.closed_outward()) colour[3] = kHullFrontAlpha;
    DrawPosedMesh(context.vertex_lit_program, gpu, body.X_WB, colour);
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDepthMask(GL_TRUE);

  // feature edges (sharp, or on the silhouette) on top; edges whose faces both turn away from
  // the camera fainter and thinner
  OverlayBatch back, front;
  const double width = 1.5 * context.pixel_scale;
  for (const BodyVisual& body : frame.bodies) {
    if (!body.hull) continue;
    // facing is tested in the body frame, so only the drawn edges are posed: a 100k-triangle
    // mesh's hull has ~75k edges, most of them smooth and off the silhouette
    const Eigen::Vector3d eye_B = body.X_WB.inverse() * context.camera.eye;
    for (const HullEdge& edge : body.hull->edges) {
      const Eigen::Vector3d to_eye = eye_B - 0.5 * (edge.a + edge.b);
      const bool left = edge.n_left.dot(to_eye) > 0;
      const bool right = edge.n_right.dot(to_eye) > 0;
      const bool sharp = edge.n_left.dot(edge.n_right) < kSmoothEdgeCos;
      if (!sharp && left == right) continue;
      const bool visible = left || right;
      const Eigen::Vector3d a = body.X_WB * edge.a, b = body.X_WB * edge.b;
      Pixel pa, pb;
      if (!context.camera.ToPixel(a, &pa) || !context.camera.ToPixel(b, &pb)) continue;
      pa.z() = pb.z() = 0;
      if (visible) {
        front.Segment(pa, pb, width, palette::kHullEdge);
      } else {
        back.Segment(pa, pb, 0.7 * width, palette::kHullBackEdge);
      }
    }
  }
  UseOverlayProgram(context, false);
  context.overlay.Draw(back);
  context.overlay.Draw(front);
}

}  // namespace ecpsim::render
