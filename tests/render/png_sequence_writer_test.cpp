// Numbered frames written on worker threads: every frame lands in its own file, intact, in order.

#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/png_sequence_writer.h"
#include "render/png_writer.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string TempDir(const std::string& name) {
  const std::string dir =
      std::string(ECPSIM_BINARY_DIR) + "/tests/render/png_sequence_writer_test/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

// frame k is a 7 × 5 image filled with the value k
Image Numbered(int k) {
  Image image;
  image.width = 7;
  image.height = 5;
  image.pixels.assign(7 * 5 * 3, static_cast<std::uint8_t>(k));
  return image;
}

TEST(PngSequenceWriter, WritesEveryFrameIntactInOrder) {
  const std::string dir = TempDir("frames") + "/frames";
  {
    // two encoders and a short queue, so frames finish out of order and Add has to wait
    PngSequenceWriter writer(dir, 2, 2);
    for (int k = 0; k < 12; ++k) {
      EXPECT_EQ(writer.Add(Numbered(k)), fmt::format("{}/frame_{:06d}.png", dir, k));
    }
    writer.Finish();
  }
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 12);
  for (int k = 0; k < 12; ++k) {
    EXPECT_EQ(ReadPng(fmt::format("{}/frame_{:06d}.png", dir, k)).pixels, Numbered(k).pixels) << k;
  }
}

TEST(PngSequenceWriter, FolderThatIsAFileIsAnInputError) {
  const std::string dir = TempDir("file");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/frames") << "x";
  EXPECT_THAT([&] { PngSequenceWriter writer(dir + "/frames"); },
              ThrowsMessage<InputError>(HasSubstr("cannot create the folder")));
}

TEST(PngSequenceWriter, WriteErrorReachesTheCaller) {
  // the folder disappears after construction: the encoder's error comes back from Finish
  const std::string dir = TempDir("vanishing") + "/frames";
  PngSequenceWriter writer(dir, 1, 1);
  std::filesystem::remove_all(dir);
  writer.Add(Numbered(0));
  EXPECT_THAT([&] { writer.Finish(); }, ThrowsMessage<InputError>(HasSubstr("frame_000000.png")));
}

}  // namespace
}  // namespace ecpsim::render
