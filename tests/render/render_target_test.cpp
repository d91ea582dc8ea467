// The pixel path without golden images: exact colours at exact positions through MSAA resolve and
// read-back, with row 0 at the top.

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "render/gl_context.h"
#include "render/render_target.h"

namespace ecpsim::render {
namespace {

TEST(RenderTarget, ClearRectLandsAtImageCoordinatesTopRowFirst) {
  GlContext context;
  RenderTarget target(8, 6, 4);
  target.Clear({0, 0, 1, 1});
  // a red block at the top-left (3 × 2) and a green one at the bottom-right (2 × 1)
  target.ClearRect(0, 0, 3, 2, {1, 0, 0, 1});
  target.ClearRect(6, 5, 2, 1, {0, 1, 0, 1});
  const Image image = target.Read();
  ASSERT_EQ(image.width, 8);
  ASSERT_EQ(image.height, 6);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      const bool red = x < 3 && y < 2;
      const bool green = x >= 6 && y == 5;
      const std::uint8_t* p = image.Pixel(x, y);
      // uniform clears resolve exactly: every sample of a pixel has the same colour
      EXPECT_EQ(p[0], red ? 255 : 0) << x << "," << y;
      EXPECT_EQ(p[1], green ? 255 : 0) << x << "," << y;
      EXPECT_EQ(p[2], red || green ? 0 : 255) << x << "," << y;
    }
  }
}

TEST(RenderTarget, SupersamplesAreAveragedExactly) {
  // a 4 × 3 image drawn at 8 × 6: image pixel (0, 0) is 2 × 2 red drawing pixels, image pixel
  // (1, 0) has its left column red and its right column blue: (2·255 + 2·0 + 2) / 4 = 128
  GlContext context;
  RenderTarget target(4, 3, 1, 2);
  EXPECT_EQ(target.width(), 8);
  EXPECT_EQ(target.height(), 6);
  target.Clear({0, 0, 1, 1});
  target.ClearRect(0, 0, 3, 2, {1, 0, 0, 1});
  const Image image = target.Read();
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 3);
  EXPECT_EQ(image.Pixel(0, 0)[0], 255);
  EXPECT_EQ(image.Pixel(0, 0)[2], 0);
  EXPECT_EQ(image.Pixel(1, 0)[0], 128);
  EXPECT_EQ(image.Pixel(1, 0)[2], 128);
  EXPECT_EQ(image.Pixel(0, 1)[0], 0);  // the row below: all blue
  EXPECT_EQ(image.Pixel(0, 1)[2], 255);
  EXPECT_EQ(image.Pixel(3, 2)[2], 255);
}

TEST(RenderTarget, ThreeHalvesSupersamplesAreAreaWeighted) {
  // a 4 × 3 image drawn at 6 × 5 (3 × 3 drawing pixels per 2 × 2 image pixels, the odd last row
  // from 1.5 drawing rows): image pixel (0, 0) covers drawing pixels (0, 0) with weight 4,
  // (1, 0) and (0, 1) with 2 and (1, 1) with 1, ninths. Red drawing columns 0..1 on rows 0..1:
  // image (0, 0) is all red; image (1, 0) overlaps red column 1 with weights 1 + ½ of 9/4 ...
  // exactly: its taps are columns 1 (weight 1) and 2 (weight 2), rows 0 (2) and 1 (1), so red
  // weight 1·2 + 1·1 = 3 of 9: (3·255 + 4) / 9 = 85, blue (6·255 + 4) / 9 = 170
  GlContext context;
  RenderTarget target(4, 3, 1, 1.5);
  EXPECT_EQ(target.width(), 6);
  EXPECT_EQ(target.height(), 5);
  target.Clear({0, 0, 1, 1});
  target.ClearRect(0, 0, 2, 2, {1, 0, 0, 1});
  const Image image = target.Read();
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 3);
  EXPECT_EQ(image.Pixel(0, 0)[0], 255);
  EXPECT_EQ(image.Pixel(0, 0)[2], 0);
  EXPECT_EQ(image.Pixel(1, 0)[0], 85);
  EXPECT_EQ(image.Pixel(1, 0)[2], 170);
  // image row 1 takes drawing rows 1 (weight 1) and 2 (2): red weight 1·(2 + 1) = 3 of 9 at
  // x = 0, and 1·1 = 1 of 9 at x = 1: (255 + 4) / 9 = 28
  EXPECT_EQ(image.Pixel(0, 1)[0], 85);
  EXPECT_EQ(image.Pixel(1, 1)[0], 28);
  EXPECT_EQ(image.Pixel(1, 1)[2], (8 * 255 + 4) / 9);
  // the last row (drawing rows 3 and 4) and column (drawing columns 4 and 5) are all blue
  EXPECT_EQ(image.Pixel(3, 2)[0], 0);
  EXPECT_EQ(image.Pixel(3, 2)[2], 255);
}

TEST(RenderTarget, ThreeHalvesOddWidthTakesItsLastPixelFromTwoColumns) {
  // a 5 × 2 image drawn at 8 × 3: image column 4 (even) takes drawing columns 6 (weight 2) and 7
  // (weight 1); column 6 red over all rows, column 7 blue: red (6·255 + 4) / 9 = 170 and blue
  // (3·255 + 4) / 9 = 85 in both image rows; column 3 (drawing columns 4 (1) and 5 (2)) is green
  GlContext context;
  RenderTarget target(5, 2, 1, 1.5);
  ASSERT_EQ(target.width(), 8);
  ASSERT_EQ(target.height(), 3);
  target.Clear({0, 1, 0, 1});
  target.ClearRect(6, 0, 1, 3, {1, 0, 0, 1});
  target.ClearRect(7, 0, 1, 3, {0, 0, 1, 1});
  const Image image = target.Read();
  ASSERT_EQ(image.width, 5);
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(image.Pixel(4, y)[0], 170);
    EXPECT_EQ(image.Pixel(4, y)[1], 0);
    EXPECT_EQ(image.Pixel(4, y)[2], 85);
    EXPECT_EQ(image.Pixel(3, y)[0], 0);
    EXPECT_EQ(image.Pixel(3, y)[1], 255);
  }
}

// every pixel of a busy 1.5× frame against the area-weighted mean computed here from the same
// drawing read at 1×: the vectorized downsample must equal the definition to the bit, for an even
// and an odd width (the odd one's last column and a last row of 1.5 drawing rows included)
TEST(RenderTarget, ThreeHalvesEqualsTheAreaWeightedMeanEverywhere) {
  GlContext context;
  for (const int width : {38, 37}) {
    const int height = 25;
    RenderTarget target(width, height, 1, 1.5);
    RenderTarget drawing(target.width(), target.height(), 1, 1);
    // 1-pixel-wide and wider rectangles of pseudo-random colours, the same in both targets
    unsigned state = 12345;
    const auto next = [&state](unsigned range) {
      state = state * 1103515245u + 12345u;
      return (state >> 16) % range;
    };
    for (RenderTarget* t : {&target, &drawing}) {
      t->Clear({0.1f, 0.5f, 0.9f, 1});
    }
    for (int i = 0; i < 200; ++i) {
      const int x = static_cast<int>(next(target.width()));
      const int y = static_cast<int>(next(target.height()));
      const int w = 1 + static_cast<int>(next(4)), h = 1 + static_cast<int>(next(4));
      const std::array<float, 4> colour = {next(256) / 255.0f, next(256) / 255.0f,
                                           next(256) / 255.0f, 1};
      for (RenderTarget* t : {&target, &drawing}) {
        t->ClearRect(x, y, std::min(w, t->width() - x), std::min(h, t->height() - y), colour);
      }
    }
    const Image image = target.Read();
    const Image full = drawing.Read();
    ASSERT_EQ(full.width, target.width());
    // image pixel i spans drawing pixels [1.5 i, 1.5 i + 1.5): weights 2, 1 (even i) or 1, 2
    const auto taps = [](int i, int last) {
      const int k = i / 2;
      std::array<std::pair<int, int>, 2> t =
          i % 2 == 0 ? std::array<std::pair<int, int>, 2>{{{3 * k, 2}, {3 * k + 1, 1}}}
                     : std::array<std::pair<int, int>, 2>{{{3 * k + 1, 1}, {3 * k + 2, 2}}};
      for (auto& tap : t) tap.first = std::min(tap.first, last);
      return t;
    };
    int mismatches = 0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        for (int c = 0; c < 3; ++c) {
          int sum = 4;  // rounding
          for (const auto& [row, wy] : taps(y, full.height - 1)) {
            for (const auto& [column, wx] : taps(x, full.width - 1)) {
              sum += wx * wy * full.Pixel(column, row)[c];
            }
          }
          if (image.Pixel(x, y)[c] != sum / 9) ++mismatches;
        }
      }
    }
    EXPECT_EQ(mismatches, 0) << "width " << width;
  }
}

// the same pseudo-random rectangles (1 to 4 drawing pixels wide) in every target given
void FillWithRectangles(const std::vector<RenderTarget*>& targets) {
  unsigned state = 777;
  const auto next = [&state](unsigned range) {
    state = state * 1103515245u + 12345u;
    return (state >> 16) % range;
  };
  for (RenderTarget* t : targets) t->Clear({0.9f, 0.5f, 0.1f, 1});
  const int width = targets.front()->width(), height = targets.front()->height();
  for (int i = 0; i < 100; ++i) {
    const int x = static_cast<int>(next(width)), y = static_cast<int>(next(height));
    const int w = 1 + static_cast<int>(next(4)), h = 1 + static_cast<int>(next(4));
    const std::array<float, 4> colour = {next(256) / 255.0f, next(256) / 255.0f, next(256) / 255.0f,
                                         1};
    for (RenderTarget* t : targets) {
      t->ClearRect(x, y, std::min(w, width - x), std::min(h, height - y), colour);
    }
  }
}

// a drawing downsampled later (on another thread, by FfmpegPipe) is the image Read() gives, for
// every supersampling factor and an odd size; a spare drawing's buffer is reused
TEST(RenderTarget, DownsampledDrawingEqualsTheReadImage) {
  GlContext context;
  for (const double factor : {1.0, 1.5, 2.0, 3.0, 4.0}) {
    RenderTarget target(37, 21, 1, factor);
    FillWithRectangles({&target});
    const Image read = target.Read();
    Drawing drawing = target.ReadDrawing();
    EXPECT_EQ(drawing.drawing_width, target.width());
    EXPECT_EQ(drawing.drawing_height, target.height());
    const Image later = Downsample(drawing);
    EXPECT_EQ(later.width, read.width);
    EXPECT_EQ(later.height, read.height);
    EXPECT_TRUE(later.pixels == read.pixels) << "supersample " << factor;
    const std::uint8_t* buffer = drawing.rgba.get();
    const Drawing again = target.ReadDrawing(std::move(drawing));
    EXPECT_EQ(again.rgba.get(), buffer);
    EXPECT_TRUE(Downsample(again).pixels == read.pixels) << "supersample " << factor;
  }
}

// frames for a video alone come in B, G, R order: the same pixels as R, G, B, bytes swapped
TEST(RenderTarget, BgrOrderHoldsTheSamePixelsWithRedAndBlueSwapped) {
  GlContext context;
  RenderTarget rgb(37, 21, 1, 1.5);
  RenderTarget bgr(37, 21, 1, 1.5, ChannelOrder::kBgr);
  FillWithRectangles({&rgb, &bgr});
  const Image a = rgb.Read();
  for (const Image& b : {bgr.Read(), Downsample(bgr.ReadDrawing())}) {
    EXPECT_EQ(a.order, ChannelOrder::kRgb);
    ASSERT_EQ(b.order, ChannelOrder::kBgr);
    ASSERT_EQ(b.pixels.size(), a.pixels.size());
    int mismatches = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 3) {
      mismatches += a.pixels[i] != b.pixels[i + 2] || a.pixels[i + 1] != b.pixels[i + 1] ||
                    a.pixels[i + 2] != b.pixels[i];
    }
    EXPECT_EQ(mismatches, 0);
  }
  // red differs from blue almost everywhere (the clear colour is 0.9, 0.5, 0.1), so a missing
  // swap cannot pass
  int red_is_blue = 0;
  for (size_t i = 0; i < a.pixels.size(); i += 3) red_is_blue += a.pixels[i] == a.pixels[i + 2];
  EXPECT_LT(red_is_blue, static_cast<int>(a.pixels.size() / 3 / 10));
}

TEST(RenderTarget, UnsupportedSupersampleIsRejected) {
  GlContext context;
  EXPECT_THROW(RenderTarget(4, 3, 1, 2.5), std::runtime_error);
  EXPECT_THROW(RenderTarget(4, 3, 1, 5), std::runtime_error);
}

TEST(RenderTarget, ContextIsOpenGl33OrNewer) {
  GlContext context;
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(context.version().c_str(), "%d.%d", &major, &minor), 2)
      << context.version();
  EXPECT_GE(major * 10 + minor, 33) << context.version();
}

}  // namespace
}  // namespace ecpsim::render
