// The pixel path without golden images: exact colours at exact positions through MSAA resolve and
// read-back, with row 0 at the top.

#include <cstdio>

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

TEST(RenderTarget, ContextIsOpenGl33OrNewer) {
  GlContext context;
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(context.version().c_str(), "%d.%d", &major, &minor), 2)
      << context.version();
  EXPECT_GE(major * 10 + minor, 33) << context.version();
}

}  // namespace
}  // namespace ecpsim::render
