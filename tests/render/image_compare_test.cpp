// Image comparison: counts against hand-made images, the diff image, and bad tolerances.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/image_compare.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

Image Flat(int width, int height, std::uint8_t value) {
  Image image;
  image.width = width;
  image.height = height;
  image.pixels.assign(static_cast<size_t>(width) * height * 3, value);
  return image;
}

TEST(CompareImages, IdenticalImagesMatchWithZeroDifference) {
  const ImageComparison c = CompareImages(Flat(10, 10, 90), Flat(10, 10, 90), {0, 0.0});
  EXPECT_TRUE(c.match);
  EXPECT_EQ(c.differing_pixels, 0);
  EXPECT_EQ(c.max_channel_difference, 0);
  EXPECT_EQ(c.total_pixels, 100);
}

TEST(CompareImages, CountsPixelsOverTheThresholdOnly) {
  // 100 × 100 pixels: one differs by 30 in green, one by 10 in blue
  Image actual = Flat(100, 100, 90);
  actual.Pixel(3, 4)[1] = 120;
  actual.Pixel(50, 60)[2] = 100;
  const ImageComparison c = CompareImages(Flat(100, 100, 90), actual, {24, 1e-4});
  EXPECT_EQ(c.differing_pixels, 1);
  EXPECT_DOUBLE_EQ(c.differing_fraction, 1e-4);
  EXPECT_EQ(c.max_channel_difference, 30);
  EXPECT_TRUE(c.match);  // 1e-4 ≤ 1e-4
  EXPECT_FALSE(CompareImages(Flat(100, 100, 90), actual, {24, 0.5e-4}).match);
  EXPECT_EQ(CompareImages(Flat(100, 100, 90), actual, {30, 0.0}).differing_pixels, 0);
  EXPECT_EQ(CompareImages(Flat(100, 100, 90), actual, {9, 0.0}).differing_pixels, 2);
}

TEST(CompareImages, DiffMarksOverThresholdRedAndUnderThresholdOrange) {
  Image actual = Flat(4, 4, 0);
  actual.Pixel(1, 2)[0] = 200;
  actual.Pixel(3, 0)[0] = 5;
  const ImageComparison c = CompareImages(Flat(4, 4, 0), actual, {24, 0.0});
  ASSERT_EQ(c.diff.width, 4);
  ASSERT_EQ(c.diff.height, 4);
  EXPECT_EQ(c.diff.Pixel(1, 2)[0], 230);
  EXPECT_EQ(c.diff.Pixel(1, 2)[1], 0);
  EXPECT_EQ(c.diff.Pixel(3, 0)[0], 255);
  EXPECT_EQ(c.diff.Pixel(3, 0)[1], 170);
  // unchanged pixels: grey 160 + luminance / 9 (0 here)
  EXPECT_EQ(c.diff.Pixel(0, 0)[0], 160);
  EXPECT_EQ(c.diff.Pixel(0, 0)[2], 160);
}

TEST(CompareImages, DifferentSizesDoNotMatch) {
  const ImageComparison c = CompareImages(Flat(4, 4, 0), Flat(4, 5, 0));
  EXPECT_FALSE(c.same_size);
  EXPECT_FALSE(c.match);
  EXPECT_TRUE(c.diff.pixels.empty());
  EXPECT_EQ(c.Summary({}), "the images differ in size");
}

TEST(CompareImages, OutOfRangeToleranceIsAnInputError) {
  EXPECT_THAT(
      [] {
        CompareImages(Flat(1, 1, 0), Flat(1, 1, 0), {300, 0.0});
      },
      ThrowsMessage<InputError>(HasSubstr("threshold = 300")));
  EXPECT_THAT(
      [] {
        CompareImages(Flat(1, 1, 0), Flat(1, 1, 0), {0, 1.5});
      },
      ThrowsMessage<InputError>(HasSubstr("max fraction = 1.5")));
}

}  // namespace
}  // namespace ecpsim::render
