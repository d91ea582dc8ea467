// PNG files: byte-exact round trip, header fields and row order, atomic writes, bad files.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/png_writer.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string TempDir(const std::string& name) {
  const std::string dir = std::string(ECPSIM_BINARY_DIR) + "/tests/render/png_writer_test/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// a 5 × 3 image with a distinct value in every byte, so any swap of rows, columns or channels shows
Image Gradient() {
  Image image;
  image.width = 5;
  image.height = 3;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 5; ++x) {
      image.pixels.push_back(static_cast<std::uint8_t>(10 * y + x));
      image.pixels.push_back(static_cast<std::uint8_t>(100 + 10 * y + x));
      image.pixels.push_back(static_cast<std::uint8_t>(200 + 10 * y + x));
    }
  }
  return image;
}

TEST(PngWriter, RoundTripIsByteExactAtEveryLevel) {
  const std::string dir = TempDir("round_trip");
  for (int level : {0, 1, 6, 9}) {
    const std::string path = dir + "/gradient.png";
    WritePng(path, Gradient(), level);
    const Image back = ReadPng(path);
    EXPECT_EQ(back.width, 5);
    EXPECT_EQ(back.height, 3);
    EXPECT_EQ(back.pixels, Gradient().pixels) << "level " << level;
  }
}

TEST(PngWriter, HeaderHoldsWidthHeightAndRgbType) {
  const std::string path = TempDir("header") + "/gradient.png";
  WritePng(path, Gradient());
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_GE(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  // big-endian width 5 and height 3, bit depth 8, colour type 2 (RGB)
  EXPECT_EQ(static_cast<int>(bytes[19]), 5);
  EXPECT_EQ(static_cast<int>(bytes[23]), 3);
  EXPECT_EQ(static_cast<int>(bytes[24]), 8);
  EXPECT_EQ(static_cast<int>(bytes[25]), 2);
}

TEST(PngWriter, StoredRowsAreTopRowFirst) {
  // at level 0 zlib stores the filtered rows verbatim; the fast levels use no filter, so each
  // row is filter byte 0 and its pixels unchanged, and the first row in the file is image row 0
  const std::string path = TempDir("rows") + "/gradient.png";
  WritePng(path, Gradient(), 0);
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string row0 = {0, 0, 100, static_cast<char>(200)};
  const std::string row2 = {0, 20, 120, static_cast<char>(220)};
  const size_t at0 = bytes.find(row0), at2 = bytes.find(row2);
  ASSERT_NE(at0, std::string::npos);
  ASSERT_NE(at2, std::string::npos);
  EXPECT_LT(at0, at2);
}

TEST(PngWriter, WriteLeavesNoTemporaryFile) {
  const std::string dir = TempDir("atomic");
  WritePng(dir + "/a.png", Gradient());
  WritePng(dir + "/a.png", Gradient());  // replacing an existing file
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename(), "a.png");
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(PngWriter, MissingDirectoryIsAnInputError) {
  EXPECT_THAT(
      [] { WritePng("/nonexistent/dir/frame.png", Gradient()); },
      ThrowsMessage<InputError>(HasSubstr("cannot write PNG '/nonexistent/dir/frame.png'")));
}

TEST(PngWriter, MismatchedBufferIsAnInputError) {
  Image image = Gradient();
  image.pixels.pop_back();
  const std::string path = TempDir("mismatch") + "/bad.png";
  EXPECT_THAT([&] { WritePng(path, image); },
              ThrowsMessage<InputError>(HasSubstr("image 5x3 with 44 bytes")));
}

TEST(PngReader, MissingFileIsAnInputError) {
  EXPECT_THAT([] { ReadPng("/nonexistent/expected.png"); },
              ThrowsMessage<InputError>(HasSubstr("'/nonexistent/expected.png': No such file")));
}

TEST(PngReader, NonPngFileIsAnInputError) {
  const std::string path = TempDir("not_png") + "/text.png";
  std::ofstream(path) << "this is not a PNG file\n";
  EXPECT_THAT([&] { ReadPng(path); }, ThrowsMessage<InputError>(HasSubstr("cannot read PNG")));
}

}  // namespace
}  // namespace ecpsim::render
