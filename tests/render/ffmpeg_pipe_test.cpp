// MP4 through the ffmpeg program: a playable file from raw frames, odd sizes padded, clear errors.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/ffmpeg_pipe.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string TempDir(const std::string& name) {
  const std::string dir = std::string(ECPSIM_BINARY_DIR) + "/tests/render/ffmpeg_pipe_test/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

Image Frame(int width, int height, int k) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgb.resize(static_cast<size_t>(width) * height * 3);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<std::uint8_t>(i * 7 + k);
  return image;
}

TEST(FfmpegPipe, WritesAnMp4FromOddSizedFrames) {
  const std::string dir = TempDir("video");
  const std::string path = dir + "/video.mp4";
  {
    FfmpegPipe pipe(path, 65, 49, 25);
    for (int k = 0; k < 10; ++k) pipe.Write(Frame(65, 49, k));
    EXPECT_FALSE(std::filesystem::exists(path));  // only after Finish
    pipe.Finish();
    EXPECT_EQ(pipe.frames(), 10);
  }
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(bytes.substr(4, 4), "ftyp");  // an ISO media file
  // nothing else left in the folder: no temporary video, no log
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(FfmpegPipe, UnfinishedVideoLeavesNoFile) {
  const std::string dir = TempDir("unfinished");
  {
    FfmpegPipe pipe(dir + "/video.mp4", 32, 32, 25);
    pipe.Write(Frame(32, 32, 0));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(FfmpegPipe, MissingProgramIsAnInputError) {
  EXPECT_THAT(
      [] { FfmpegPipe pipe(TempDir("missing") + "/v.mp4", 32, 32, 25, "ecpsim-no-such-ffmpeg"); },
      ThrowsMessage<InputError>(HasSubstr("'ecpsim-no-such-ffmpeg' is not on PATH")));
}

TEST(FfmpegPipe, BadFrameRateIsAnInputError) {
  EXPECT_THAT([] { FfmpegPipe pipe(TempDir("fps") + "/v.mp4", 32, 32, 0.0); },
              ThrowsMessage<InputError>(HasSubstr("fps = 0")));
}

TEST(FfmpegPipe, MissingFolderIsAnInputError) {
  EXPECT_THAT([] { FfmpegPipe pipe("/nonexistent/dir/v.mp4", 32, 32, 25); },
              ThrowsMessage<InputError>(HasSubstr("the folder '/nonexistent/dir' does not exist")));
}

TEST(FfmpegPipe, EncoderFailureIsReportedWithItsExitStatus) {
  // a program that exits 1 at once stands in for an ffmpeg that fails
  const std::string dir = TempDir("failing");
  FfmpegPipe pipe(dir + "/v.mp4", 32, 32, 25, "false");
  EXPECT_THAT(
      [&] {
        for (int k = 0; k < 2000; ++k) pipe.Write(Frame(32, 32, k));
        pipe.Finish();
      },
      ThrowsMessage<std::runtime_error>(HasSubstr("exit status 1")));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace ecpsim::render
