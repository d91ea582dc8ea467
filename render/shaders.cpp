#include "render/shaders.h"

#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_normal;
out vec3 v_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  gl_Position = u_view_projection * world;
}
)";

// a key light with a soft specular, a fill from the camera, and ambient; two-sided so that the
// inside of a translucent hull is lit too (shared by the per-pixel and per-vertex programs)
#define ECPSIM_SHADE_FUNCTION                                                      \
  "uniform vec4 u_color;\n"                                                        \
  "uniform vec3 u_eye;\n"                                                          \
  "uniform vec3 u_light_dir;\n"                                                    \
  "vec4 Shade(vec3 normal, vec3 world) {\n"                                        \
  "  vec3 n = normalize(normal);\n"                                                \
  "  vec3 v = normalize(u_eye - world);\n"                                         \
  "  if (dot(n, v) < 0.0) n = -n;\n"                                               \
  "  float key = max(dot(n, u_light_dir), 0.0);\n"                                 \
  "  float fill = max(dot(n, v), 0.0);\n"                                          \
  "  vec3 h = normalize(u_light_dir + v);\n"                                       \
  "  float specular = 0.18 * pow(max(dot(n, h), 0.0), 40.0);\n"                    \
  "  vec3 c = u_color.rgb * (0.28 + 0.52 * key + 0.25 * fill) + vec3(specular);\n" \
  "  return vec4(min(c, vec3(1.0)), u_color.a);\n"                                 \
  "}\n"

constexpr const char* kMeshFragment =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec3 v_world;\n"
    "out vec4 frag_color;\n" ECPSIM_SHADE_FUNCTION
    "void main() { frag_color = Shade(v_normal, v_world); }\n";

// the mesh program's lighting evaluated per vertex, so that the many fragments of large, flat
// hull faces cost no more than a blended fill on llvmpipe, and the 4 × 4 pixel blocks of a dense
// mesh's tiny triangles no more than a fill
constexpr const char* kVertexLitVertex =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "uniform mat4 u_model;\n"
    "uniform mat3 u_normal_matrix;\n"
    "uniform mat4 u_view_projection;\n"
    "out vec4 v_color;\n" ECPSIM_SHADE_FUNCTION
    "void main() {\n"
    "  vec4 world = u_model * vec4(a_position, 1.0);\n"
    "  v_color = Shade(u_normal_matrix * a_normal, world.xyz);\n"
    "  gl_Position = u_view_projection * world;\n"
    "}\n";

#undef ECPSIM_SHADE_FUNCTION

// an interpolated per-vertex colour (the vertex-lit program, the ground)
constexpr const char* kColorFragment = R"(#version 330 core
in vec4 v_color;
out vec4 frag_color;
void main() { frag_color = v_color; }
)";

// the ground: world-space triangles with per-vertex colour (the sheet's fade to the background
// and the grid lines' opacity are interpolated, so the shader costs no more than a fill; a
// per-pixel procedural grid cost ~45 ms per supersampled 1280×720 frame on llvmpipe)
constexpr const char* kGroundVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_view_projection;
out vec4 v_color;
void main() {
  v_color = a_color;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
)";

constexpr const char* kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec3 a_pixel;
layout(location = 1) in vec4 a_color;
layout(location = 2) in vec2 a_uv;
uniform vec2 u_viewport;
out vec4 v_color;
out vec2 v_uv;
void main() {
  v_color = a_color;
  v_uv = a_uv;
  gl_Position = vec4(2.0 * a_pixel.x / u_viewport.x - 1.0, 1.0 - 2.0 * a_pixel.y / u_viewport.y,
                     a_pixel.z, 1.0);
}
)";

constexpr const char* kOverlayFragment = R"(#version 330 core
in vec4 v_color;
in vec2 v_uv;
uniform int u_textured;
uniform sampler2D u_atlas;
uniform float u_alpha_scale;
out vec4 frag_color;
void main() {
  float coverage = u_textured != 0 ? texture(u_atlas, v_uv).r : 1.0;
  frag_color = vec4(v_color.rgb, v_color.a * coverage * u_alpha_scale);
}
)";

unsigned Compile(const std::string& name, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(length) + 1, '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw std::runtime_error(fmt::format("{} {} shader does not compile: {}", name,
                                         stage == GL_VERTEX_SHADER ? "vertex" : "fragment",
                                         log.data()));
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::string& name, const char* vertex_source,
                             const char* fragment_source) {
  const GLuint vertex = Compile(name, GL_VERTEX_SHADER, vertex_source);
  const GLuint fragment = Compile(name, GL_FRAGMENT_SHADER, fragment_source);
  id_ = glCreateProgram();
  glAttachShader(id_, vertex);
  glAttachShader(id_, fragment);
  glLinkProgram(id_);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(length) + 1, '\0');
    glGetProgramInfoLog(id_, length, nullptr, log.data());
    glDeleteProgram(id_);
    throw std::runtime_error(fmt::format("{} program does not link: {}", name, log.data()));
  }
}

ShaderProgram::~ShaderProgram() { glDeleteProgram(id_); }

void ShaderProgram::Use() const { glUseProgram(id_); }

int ShaderProgram::Uniform(const char* name) const { return glGetUniformLocation(id_, name); }

ShaderProgram MakeMeshProgram() { return ShaderProgram("mesh", kMeshVertex, kMeshFragment); }
ShaderProgram MakeVertexLitProgram() {
  return ShaderProgram("vertex-lit", kVertexLitVertex, kColorFragment);
}
ShaderProgram MakeGroundProgram() { return ShaderProgram("ground", kGroundVertex, kColorFragment); }
ShaderProgram MakeOverlayProgram() {
  return ShaderProgram("overlay", kOverlayVertex, kOverlayFragment);
}

}  // namespace ecpsim::render
