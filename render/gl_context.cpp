#include "render/gl_context.h"

#include <stdexcept>
#include <vector>

#include <GL/osmesa.h>
#include <fmt/format.h>

namespace ecpsim::render {
namespace {

// the placeholder default framebuffer: every frame is drawn into framebuffer objects
constexpr int kPlaceholderSize = 4;  // pixels per side

// the shaders are GLSL 3.30, so the context must offer at least OpenGL 3.3
constexpr int kMinMajor = 3;
constexpr int kMinMinor = 3;

OSMesaContext CreateContext(bool core, bool* got_core) {
  // core profile first: Mesa ≥ 11.2 offers it through the attribute-list entry point
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            8,
                            OSMESA_PROFILE,
                            core ? OSMESA_CORE_PROFILE : OSMESA_COMPAT_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            kMinMajor,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            kMinMinor,
                            0};
  OSMesaContext context = OSMesaCreateContextAttribs(attributes, nullptr);
  *got_core = core && context != nullptr;
  return context;
}

}  // namespace

struct GlContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> placeholder =
      std::vector<unsigned char>(4 * kPlaceholderSize * kPlaceholderSize);
};

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  impl_->context = CreateContext(true, &core_profile_);
  if (impl_->context == nullptr) impl_->context = CreateContext(false, &core_profile_);
  if (impl_->context == nullptr) {
    throw std::runtime_error(fmt::format(
        "OSMesa could not create an OpenGL {}.{} context (core or compatibility profile); the "
        "renderer needs Mesa's libOSMesa with llvmpipe (Debian package libosmesa6)",
        kMinMajor, kMinMinor));
  }
  MakeCurrent();
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  renderer_ = renderer ? renderer : "unknown";
  version_ = version ? version : "unknown";
}

GlContext::~GlContext() {
  if (impl_ && impl_->context) OSMesaDestroyContext(impl_->context);
}

void GlContext::MakeCurrent() {
  if (!OSMesaMakeCurrent(impl_->context, impl_->placeholder.data(), GL_UNSIGNED_BYTE,
                         kPlaceholderSize, kPlaceholderSize)) {
    throw std::runtime_error("OSMesaMakeCurrent failed: the OpenGL context cannot be used");
  }
}

}  // namespace ecpsim::render
