#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "render/background_cache.h"
#include "render/draw_context.h"
#include "render/gl_api.h"
#include "render/gl_context.h"

namespace ecpsim::render {
namespace {

// limits of the settings: below 16 pixels nothing is legible; 8192 is the common GL maximum
constexpr int kMinSize = 16, kMaxSize = 8192;
constexpr int kMaxSamples = 16;
// overlays are sized for 480 rows and grow with the image, never shrink below that size
constexpr double kReferenceHeight = 480;
constexpr double kFontPixels = 12;  // at pixel_scale 1

void CheckFinite(const Eigen::Vector3d& v, const std::string& what) {
  if (!v.allFinite()) {
    throw InputError(fmt::format("frame: {} = ({}, {}, {}): expected finite coordinates", what,
                                 v.x(), v.y(), v.z()));
  }
}

// every value that reaches a vertex buffer must be finite
void CheckFrame(const FrameInput& frame) {
  for (size_t i = 0; i < frame.bodies.size(); ++i) {
    if (!frame.bodies[i].X_WB.matrix().allFinite()) {
      throw InputError(fmt::format("frame: bodies[{}].X_WB: expected a finite pose", i));
    }
  }
  for (size_t i = 0; i < frame.contacts.size(); ++i) {
    const ContactVisual& c = frame.contacts[i];
    const std::string where = fmt::format("contacts[{}]", i);
    if (c.a1) CheckFinite(*c.a1, where + ".a1");
    if (c.cm_projection) CheckFinite(*c.cm_projection, where + ".cm_projection");
    if (c.force) CheckFinite(*c.force, where + ".force");
    for (const auto& polygon : c.patch.polygons) {
      for (const auto& p : polygon) CheckFinite(p, where + ".patch.polygons");
    }
    for (const auto& s : c.patch.segments) {
      CheckFinite(s[0], where + ".patch.segments");
      CheckFinite(s[1], where + ".patch.segments");
    }
    for (const auto& p : c.patch.points) CheckFinite(p, where + ".patch.points");
    for (const auto& p : c.patch.hull) CheckFinite(p, where + ".patch.hull");
  }
  if (!std::isfinite(frame.force_scale) || frame.force_scale < 0) {
    throw InputError(
        fmt::format("frame: force_scale = {}: expected a finite value ≥ 0 m/N", frame.force_scale));
  }
  if (!std::isfinite(frame.time)) {
    throw InputError(fmt::format("frame: time = {}: expected a finite time", frame.time));
  }
}

const RenderSettings& Checked(const RenderSettings& settings) {
  if (settings.width < kMinSize || settings.width > kMaxSize || settings.height < kMinSize ||
      settings.height > kMaxSize) {
    throw InputError(fmt::format("resolution {}x{}: expected {} to {} pixels per side",
                                 settings.width, settings.height, kMinSize, kMaxSize));
  }
  const double s = settings.supersample;
  if (s != 1 && s != 1.5 && s != 2 && s != 3 && s != 4) {
    throw InputError(fmt::format("supersample = {}: expected 1 (no anti-aliasing), 1.5, 2, 3 or 4",
                                 settings.supersample));
  }
  if (settings.samples < 1 || settings.samples > kMaxSamples) {
    throw InputError(fmt::format("samples = {}: expected 1 (no anti-aliasing) to {}",
                                 settings.samples, kMaxSamples));
  }
  return settings;
}

// drawing pixels per reference pixel: overlays keep their size in the image when supersampled
double PixelScale(const RenderSettings& settings) {
  return std::max(1.0, settings.height / kReferenceHeight) * settings.supersample;
}

// every value the background (the clear and DrawPlanes) is drawn from: the camera in drawing
// pixels, the overlay scale and the planes; equal keys draw identical backgrounds
std::vector<double> BackgroundKey(const Camera& camera, double pixel_scale,
                                  const std::vector<PlaneVisual>& planes) {
  std::vector<double> key = {static_cast<double>(camera.width), static_cast<double>(camera.height),
                             pixel_scale};
  const auto append = [&key](const auto& matrix) {
    key.insert(key.end(), matrix.data(), matrix.data() + matrix.size());
  };
  append(camera.eye);
  append(camera.target);
  append(camera.view);
  append(camera.projection);
  append(camera.view_projection);
  for (const PlaneVisual& plane : planes) {
    append(plane.plane.normal);
    key.push_back(plane.plane.offset);
  }
  return key;
}

}  // namespace

struct Renderer::Impl {
  explicit Impl(const RenderSettings& s)
      : settings(Checked(s)),
        target(settings.width, settings.height, settings.samples, settings.supersample,
               settings.channel_order),
        mesh_program(MakeMeshProgram()),
        vertex_lit_program(MakeVertexLitProgram()),
        ground_program(MakeGroundProgram()),
        overlay_program(MakeOverlayProgram()),
        font(settings.font_path, static_cast<int>(std::lround(kFontPixels * PixelScale(settings)))),
        background(target) {}

  RenderSettings settings;
  GlContext context;  // constructed before, destroyed after, every GL object below
  RenderTarget target;
  ShaderProgram mesh_program;
  ShaderProgram vertex_lit_program;
  ShaderProgram ground_program;
  ShaderProgram overlay_program;
  OverlayDrawer overlay;
  MeshCache meshes;
  FontAtlas font;
  BackgroundCache background;
  bool background_cached = false;  // the last frame's background was copied, not drawn
};

Renderer::Renderer(const RenderSettings& settings) : impl_(std::make_unique<Impl>(settings)) {}

Renderer::~Renderer() = default;

const RenderSettings& Renderer::settings() const { return impl_->settings; }

std::string Renderer::Description() const {
  return fmt::format("{}, OpenGL {}", impl_->context.renderer(), impl_->context.version());
}

int Renderer::CachedMeshCount() const { return impl_->meshes.size(); }

bool Renderer::LastBackgroundCached() const { return impl_->background_cached; }

Camera Renderer::FrameCamera(const FrameInput& frame) {
  CheckFrame(frame);
  Impl& impl = *impl_;
  impl.context.MakeCurrent();
  // automatic framing follows each body's bounding sphere
  std::vector<BoundingSphere> spheres;
  for (const BodyVisual& body : frame.bodies) {
    if (!body.mesh || body.fixed) continue;
    const GpuMesh& mesh = impl.meshes.Get(body.mesh);
    spheres.push_back({body.X_WB * mesh.centre(), mesh.radius()});
  }
  return MakeCamera(frame.camera, spheres, impl.settings.width, impl.settings.height);
}

Image Renderer::Render(const FrameInput& frame) {
  Draw(frame);
  return impl_->target.Read();
}

Drawing Renderer::RenderDrawing(const FrameInput& frame, Drawing spare) {
  Draw(frame);
  return impl_->target.ReadDrawing(std::move(spare));
}

void Renderer::Draw(const FrameInput& frame) {
  Impl& impl = *impl_;
  // the same view in drawing pixels (supersampled)
  Camera camera = FrameCamera(frame);
  camera.width = impl.target.width();
  camera.height = impl.target.height();

  DrawContext context{camera,
                      impl.target,
                      impl.mesh_program,
                      impl.vertex_lit_program,
                      impl.ground_program,
                      impl.overlay_program,
                      impl.overlay,
                      impl.meshes,
                      impl.font,
                      PixelScale(impl.settings)};
  // with a fixed camera (a scene's output.camera, most videos) the ground is drawn once and
  // copied back afterwards: it is ~40% of a desk frame's CPU on llvmpipe
  std::vector<double> key;
  if (!frame.planes.empty()) {
    key = BackgroundKey(camera, context.pixel_scale, frame.planes);
  }
  impl.background_cached = !key.empty() && impl.background.Restore(key);
  if (!impl.background_cached) {
    impl.target.Clear(kBackground);
    DrawPlanes(frame, context);
    if (!key.empty()) impl.background.Drawn(std::move(key));
  }
  DrawBodies(frame, context);
  DrawHulls(frame, context);
  DrawContactOverlay(frame, context);
  DrawContactInset(frame, context);
  DrawTextOverlay(frame, context);
  impl.meshes.EndFrame();
}

}  // namespace ecpsim::render
