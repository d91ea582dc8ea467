#include "render/font_atlas.h"

#include <cmath>
#include <vector>

#include <ft2build.h>
#include FT_FREETYPE_H
#include <fmt/format.h>

#include "common/errors.h"
#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

constexpr int kAtlasWidth = 512;  // pixels; 95 glyphs of ≤ 40 px fit in a few rows
constexpr int kPadding = 1;       // pixels between glyphs, so linear sampling never bleeds

struct FreeType {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  ~FreeType() {
    if (face) FT_Done_Face(face);
    if (library) FT_Done_FreeType(library);
  }
};

}  // namespace

FontAtlas::FontAtlas(const std::string& font_path, int pixel_size) {
  if (pixel_size < 6 || pixel_size > 200) {
    throw InputError(fmt::format("font size {} px: expected 6 to 200 pixels", pixel_size));
  }
  FreeType ft;
  if (FT_Init_FreeType(&ft.library) != 0) throw std::runtime_error("FreeType failed to initialize");
  if (FT_New_Face(ft.library, font_path.c_str(), 0, &ft.face) != 0) {
    throw InputError(
        fmt::format("font '{}': cannot be opened as a TrueType/OpenType font; install "
                    "the Debian package fonts-dejavu-core or give another font file",
                    font_path));
  }
  FT_Set_Pixel_Sizes(ft.face, 0, static_cast<FT_UInt>(pixel_size));
  ascender_ = static_cast<int>(ft.face->size->metrics.ascender >> 6);
  line_height_ = static_cast<int>(ft.face->size->metrics.height >> 6);

  // render every glyph and pack them in rows
  std::vector<std::vector<unsigned char>> bitmaps(glyphs_.size());
  int pen_x = kPadding, pen_y = kPadding, row_height = 0;
  for (int c = kFirst; c <= kLast; ++c) {
    if (FT_Load_Char(ft.face, static_cast<FT_ULong>(c), FT_LOAD_RENDER) != 0) continue;
    const FT_GlyphSlot slot = ft.face->glyph;
    Glyph& g = glyphs_[c - kFirst];
    g.w = static_cast<int>(slot->bitmap.width);
    g.h = static_cast<int>(slot->bitmap.rows);
    g.left = slot->bitmap_left;
    g.top = slot->bitmap_top;
    g.advance = static_cast<int>(slot->advance.x >> 6);
    if (pen_x + g.w + kPadding > kAtlasWidth) {
      pen_x = kPadding;
      pen_y += row_height + kPadding;
      row_height = 0;
    }
    g.x = pen_x;
    g.y = pen_y;
    pen_x += g.w + kPadding;
    row_height = std::max(row_height, g.h);
    auto& bitmap = bitmaps[c - kFirst];
    bitmap.resize(static_cast<size_t>(g.w) * g.h);
    for (int r = 0; r < g.h; ++r) {
      for (int k = 0; k < g.w; ++k) {
        bitmap[static_cast<size_t>(r) * g.w + k] = slot->bitmap.buffer[r * slot->bitmap.pitch + k];
      }
    }
  }
  atlas_width_ = kAtlasWidth;
  atlas_height_ = pen_y + row_height + kPadding;

  std::vector<unsigned char> atlas(static_cast<size_t>(atlas_width_) * atlas_height_, 0);
  for (size_t i = 0; i < glyphs_.size(); ++i) {
    const Glyph& g = glyphs_[i];
    for (int r = 0; r < g.h; ++r) {
      for (int k = 0; k < g.w; ++k) {
        atlas[static_cast<size_t>(g.y + r) * atlas_width_ + g.x + k] =
            bitmaps[i][static_cast<size_t>(r) * g.w + k];
      }
    }
  }

  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, atlas_width_, atlas_height_, 0, GL_RED, GL_UNSIGNED_BYTE,
               atlas.data());
  // glyphs are drawn at integer pixel positions 1:1, so nearest sampling reproduces them exactly
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

FontAtlas::~FontAtlas() { glDeleteTextures(1, &texture_); }

double FontAtlas::AddText(OverlayBatch& batch, const std::string& text, double x, double baseline,
                          const Rgba& colour) const {
  // whole pixels keep glyphs crisp
  double pen = std::round(x);
  const double base = std::round(baseline);
  for (char ch : text) {
    const int c = (ch >= kFirst && ch <= kLast) ? ch : '?';
    const Glyph& g = glyphs_[c - kFirst];
    if (g.w > 0 && g.h > 0) {
      const double x0 = pen + g.left, y0 = base - g.top;
      batch.Rectangle(x0, y0, x0 + g.w, y0 + g.h, colour, static_cast<double>(g.x) / atlas_width_,
                      static_cast<double>(g.y) / atlas_height_,
                      static_cast<double>(g.x + g.w) / atlas_width_,
                      static_cast<double>(g.y + g.h) / atlas_height_);
    }
    pen += g.advance;
  }
  return pen - std::round(x);
}

double FontAtlas::TextWidth(const std::string& text) const {
  double width = 0;
  for (char ch : text) {
    const int c = (ch >= kFirst && ch <= kLast) ? ch : '?';
    width += glyphs_[c - kFirst].advance;
  }
  return width;
}

}  // namespace ecpsim::render
