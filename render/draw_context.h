#pragma once
// What the drawing passes of one frame share: the camera, the GL programs, the overlay drawer,
// the mesh cache and the font (internal to ecpsim_render).

#include "render/camera.h"
#include "render/font_atlas.h"
#include "render/frame_input.h"
#include "render/mesh_cache.h"
#include "render/overlay_batch.h"
#include "render/render_target.h"
#include "render/shaders.h"

namespace ecpsim::render {

struct DrawContext {
  const Camera& camera;
  const RenderTarget& target;
  const ShaderProgram& mesh_program;
  const ShaderProgram& vertex_lit_program;
  const ShaderProgram& ground_program;
  const ShaderProgram& overlay_program;
  OverlayDrawer& overlay;
  MeshCache& meshes;
  const FontAtlas& font;
  double pixel_scale;  // line widths and marker sizes scale with the image height
};

/// Colours of the overlays, shared by the main view and the inset.
namespace palette {
inline const Rgba kPatchFace(0.98f, 0.62f, 0.10f, 0.85f);
inline const Rgba kPatchEdge(0.90f, 0.45f, 0.02f, 1.0f);
inline const Rgba kPatchPoint(0.85f, 0.35f, 0.0f, 1.0f);
inline const Rgba kPatchHull(0.86f, 0.08f, 0.08f, 1.0f);
inline const Rgba kEcp(0.90f, 0.0f, 0.0f, 1.0f);
inline const Rgba kMarkerRim(1.0f, 1.0f, 1.0f, 1.0f);
inline const Rgba kCentreOfMass(0.10f, 0.25f, 0.75f, 1.0f);
inline const Rgba kForce(0.10f, 0.55f, 0.20f, 1.0f);
inline const Rgba kHullEdge(0.20f, 0.30f, 0.55f, 0.9f);
inline const Rgba kHullBackEdge(0.20f, 0.30f, 0.55f, 0.3f);
inline const Rgba kText(0.10f, 0.10f, 0.12f, 1.0f);
inline const Rgba kPanel(1.0f, 1.0f, 1.0f, 0.75f);
inline const Rgba kPanelBorder(0.35f, 0.37f, 0.42f, 1.0f);
}  // namespace palette

/// Background colour (RGBA) behind the ground's fade-out.
inline constexpr std::array<float, 4> kBackground = {0.95f, 0.96f, 0.97f, 1.0f};

/// Makes the overlay program current for drawing pixels of the target: depth test and depth
/// writes off, alpha blending on; `textured` samples the glyph atlas.
void UseOverlayProgram(DrawContext& context, bool textured);

/// Ground sheets with their metric grid (depth-tested, depth-writing).
void DrawPlanes(const FrameInput& frame, DrawContext& context);
/// Bodies, opaque and shaded.
void DrawBodies(const FrameInput& frame, DrawContext& context);
/// Hulls: translucent faces (depth-tested, not depth-writing) and feature edges on top.
void DrawHulls(const FrameInput& frame, DrawContext& context);
/// Patches, patch hulls, ECPs, centre-of-mass projections and force arrows in the main view.
void DrawContactOverlay(const FrameInput& frame, DrawContext& context);
/// The top-down contact inset in the top-right corner.
void DrawContactInset(const FrameInput& frame, DrawContext& context);
/// Time, contact modes and solver iterations in the top-left corner.
void DrawTextOverlay(const FrameInput& frame, DrawContext& context);

}  // namespace ecpsim::render
