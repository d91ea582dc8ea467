#pragma once
// An offscreen OpenGL context without display or GPU (OSMesa; the only file that uses OSMesa, so
// it can be swapped for surfaceless EGL).

#include <memory>
#include <string>

namespace ecpsim::render {

/// A current OpenGL ≥ 3.3 context on the calling thread. A core profile is requested through
/// OSMesaCreateContextAttribs; where the installed Mesa does not offer one, a compatibility
/// context of version ≥ 3.3 is used instead. Drawing goes to framebuffer objects
/// (render_target.h), so the context's own buffer is a small placeholder.
/// Not thread-safe: create, use and destroy it on one thread.
class GlContext {
 public:
  /// @throws std::runtime_error if OSMesa cannot create a context of version ≥ 3.3 or make it
  ///         current (the message names the library and the version found).
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// Makes this context current on the calling thread (it is current after construction).
  void MakeCurrent();

  /// True if the context is a core profile (false: the compatibility fallback).
  bool core_profile() const { return core_profile_; }
  /// GL_RENDERER and GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core
  /// Profile) Mesa 22.3.6".
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool core_profile_ = false;
  std::string renderer_;
  std::string version_;
};

}  // namespace ecpsim::render
