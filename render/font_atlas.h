#pragma once
// Text for the overlay: printable ASCII glyphs rendered once with FreeType into a GL texture.

#include <array>
#include <string>

#include "render/overlay_batch.h"

namespace ecpsim::render {

/// The default overlay font (Debian package fonts-dejavu-core).
inline constexpr const char* kDefaultFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Glyphs 32..126 of one font at one pixel size in an R8 texture. Needs a current GlContext.
class FontAtlas {
 public:
  /// @throws InputError if `font_path` cannot be opened as a font or `pixel_size` is not in
  ///         [6, 200] (the message names the file and the value).
  FontAtlas(const std::string& font_path, int pixel_size);
  ~FontAtlas();
  FontAtlas(const FontAtlas&) = delete;
  FontAtlas& operator=(const FontAtlas&) = delete;

  /// Appends quads for `text` starting at pen position (x, baseline) in pixels (y down); returns
  /// the pen's advance. Characters outside 32..126 are drawn as '?'.
  double AddText(OverlayBatch& batch, const std::string& text, double x, double baseline,
                 const Rgba& colour) const;
  /// Advance width of `text` in pixels.
  double TextWidth(const std::string& text) const;

  unsigned texture() const { return texture_; }
  int ascender() const { return ascender_; }        // pixels above the baseline
  int line_height() const { return line_height_; }  // pixels between baselines

 private:
  struct Glyph {
    int x = 0, y = 0, w = 0, h = 0;  // in the atlas, pixels
    int left = 0, top = 0;           // bitmap offset from the pen: right, up
    int advance = 0;                 // pixels
  };
  static constexpr int kFirst = 32, kLast = 126;
  std::array<Glyph, kLast - kFirst + 1> glyphs_{};
  int atlas_width_ = 0, atlas_height_ = 0;
  int ascender_ = 0, line_height_ = 0;
  unsigned texture_ = 0;
};

}  // namespace ecpsim::render
