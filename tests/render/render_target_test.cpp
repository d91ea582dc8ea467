// The pixel path without golden images: exact colours at exact positions through MSAA resolve and
// read-back, with row 0 at the top.

#include <cstdio>
#include <stdexcept>

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
