#include "render/background_cache.h"

#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// copies all of the colour, depth and stencil of framebuffer `from` into `to` (same size and
// formats, so Mesa copies bytes rather than drawing a textured quad)
void CopyBuffers(unsigned from, unsigned to, int width, int height) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, from);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, to);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xff);
  glBlitFramebuffer(0, 0, width, height, 0, 0, width, height,
                    GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
}

}  // namespace

BackgroundCache::BackgroundCache(const RenderTarget& target) : target_(target) {
  if (target.samples() > 1) return;
  const int width = target.width(), height = target.height();
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glGenRenderbuffers(1, &color_);
  glBindRenderbuffer(GL_RENDERBUFFER, color_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error(fmt::format(
        "the background cache framebuffer of {}x{} pixels is incomplete (status 0x{:x})", width,
        height, status));
  }
  target.Bind();
}

BackgroundCache::~BackgroundCache() {
  glDeleteFramebuffers(1, &fbo_);
  glDeleteRenderbuffers(1, &color_);
  glDeleteRenderbuffers(1, &depth_);
}

bool BackgroundCache::Restore(const std::vector<double>& key) const {
  if (!valid_ || key != key_) return false;
  CopyBuffers(fbo_, target_.framebuffer(), target_.width(), target_.height());
  target_.Bind();
  return true;
}

void BackgroundCache::Drawn(std::vector<double> key) {
  if (fbo_ == 0) return;
  if (key != last_drawn_) {
    last_drawn_ = std::move(key);
    return;
  }
  CopyBuffers(target_.framebuffer(), fbo_, target_.width(), target_.height());
  target_.Bind();
  key_ = std::move(key);
  valid_ = true;
}

}  // namespace ecpsim::render
