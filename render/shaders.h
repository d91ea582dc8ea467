#pragma once
// The GLSL 3.30 programs of the renderer: lit meshes, the ground and its grid, and 2-D overlays.

#include <string>

namespace ecpsim::render {

/// A linked vertex + fragment program. Needs a current GlContext for its whole life.
class ShaderProgram {
 public:
  /// @throws std::runtime_error with the compiler's log if a stage fails to compile or link
  ///         (a bug in the shader source, not a user error).
  ShaderProgram(const std::string& name, const char* vertex_source, const char* fragment_source);
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void Use() const;
  /// Location of uniform `name`; −1 if the program has no such active uniform.
  int Uniform(const char* name) const;

 private:
  unsigned id_ = 0;
};

/// Lit meshes: attributes 0 = position (model frame), 1 = normal; uniforms u_model,
/// u_normal_matrix, u_view_projection, u_color (RGBA), u_eye, u_light_dir (unit, towards the light,
/// world).
ShaderProgram MakeMeshProgram();

/// Meshes lit per vertex (the mesh program's lighting, interpolated across each triangle), for
/// translucent hull faces and for meshes whose triangles are small on screen: the same
/// attributes and uniforms as MakeMeshProgram.
ShaderProgram MakeVertexLitProgram();

/// The ground sheet and its grid lines: attribute 0 = world position, 1 = colour (RGBA); uniform
/// u_view_projection.
ShaderProgram MakeGroundProgram();

/// Overlays in pixels: attributes 0 = pixel (x right, y down, NDC depth), 1 = colour (RGBA),
/// 2 = texture coordinate; uniforms u_viewport (pixels), u_textured (0/1), u_atlas (an R8 glyph
/// atlas whose red channel multiplies the alpha) and u_alpha_scale (multiplies the alpha).
ShaderProgram MakeOverlayProgram();

}  // namespace ecpsim::render
