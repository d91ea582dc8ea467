#pragma once
// A saved copy of a frame's background (the clear and the ground), reused while nothing it depends
// on changes.

#include <vector>

#include "render/render_target.h"

namespace ecpsim::render {

/// Colour, depth and stencil buffers of a RenderTarget's drawing size, holding the target's
/// contents as they were after its background was drawn, together with a key: every value the
/// background was drawn from (camera, planes, sizes). Restoring copies the buffers back with
/// glBlitFramebuffer (same size, same formats: a byte copy, so the restored frame is identical to
/// one drawn afresh). On llvmpipe the copy costs ~2 ms where drawing the ground costs ~15–20 ms
/// of a 1280×720 frame (1.5× supersampling). Only single-sample targets are cached (a
/// multisampled target is never restored: Restore returns false). Needs a current GlContext for
/// its whole life, and the target must outlive it.
class BackgroundCache {
 public:
  explicit BackgroundCache(const RenderTarget& target);
  ~BackgroundCache();
  BackgroundCache(const BackgroundCache&) = delete;
  BackgroundCache& operator=(const BackgroundCache&) = delete;

  /// If the saved background was drawn from exactly `key` (element-wise equal), copies it into
  /// the target's drawing buffers and returns true; otherwise leaves the target untouched and
  /// returns false. Leaves the target bound.
  bool Restore(const std::vector<double>& key) const;

  /// Tells the cache that the target's drawing buffers now hold the background of `key`. They are
  /// saved when the previous call was for the same key: a background drawn twice in a row is
  /// likely to stay, while a camera that moves every frame never pays for the copy. Leaves the
  /// target bound.
  void Drawn(std::vector<double> key);

 private:
  const RenderTarget& target_;
  bool valid_ = false;  // the saved buffers hold the background of key_
  std::vector<double> key_;
  std::vector<double> last_drawn_;
  unsigned fbo_ = 0, color_ = 0, depth_ = 0;
};

}  // namespace ecpsim::render
