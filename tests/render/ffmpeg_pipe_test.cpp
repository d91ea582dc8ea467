// MP4 through the ffmpeg program: a playable file from raw frames, odd sizes padded, clear errors;
// a video continued by a second segment holds the earlier frames' bits and the new frames after.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/ffmpeg_pipe.h"
#include "render/gl_context.h"
#include "render/render_target.h"
#include "tests/render/decode_video.h"

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
  image.pixels.resize(static_cast<size_t>(width) * height * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = static_cast<std::uint8_t>(i * 7 + k);
  return image;
}

// a dark frame with a bright bar 4 pixels wide at x = 4k: frames that H.264 keeps apart
Image Bar(int width, int height, int k) {
  Image image;
  image.width = width;
  image.height = height;
  image.pixels.assign(static_cast<size_t>(width) * height * 3, 20);
  for (int y = 0; y < height; ++y) {
    for (int x = 4 * k; x < 4 * k + 4 && x < width; ++x) image.Pixel(x, y)[0] = 240;
  }
  return image;
}

int FilesIn(const std::string& dir) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  return files;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

// frames k in [from, to) of Bar as a video at `path`, continuing the one there with kAppend
void WriteBars(const std::string& path, int from, int to, VideoStart start) {
  FfmpegPipe pipe(path, 64, 48, 20, "ffmpeg", start);
  for (int k = from; k < to; ++k) pipe.Write(Bar(64, 48, k));
  pipe.Finish();
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
  const std::string bytes = ReadBytes(path);
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(bytes.substr(4, 4), "ftyp");  // an ISO media file
  // nothing else left in the folder: no temporary video, no log
  EXPECT_EQ(FilesIn(dir), 1);
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

TEST(FfmpegPipe, AppendedFramesFollowTheEarlierOnesLosslessly) {
  const std::string dir = TempDir("append");
  const std::string path = dir + "/video.mp4";
  WriteBars(path, 0, 6, VideoStart::kReplace);
  const std::vector<Image> before = testing::DecodeVideo(path, 64, 48);
  ASSERT_EQ(before.size(), 6u);
  EXPECT_EQ(CountVideoFrames(path), 6);

  WriteBars(path, 6, 10, VideoStart::kAppend);
  // decoding to a constant frame rate duplicates or drops frames where timestamps leave a gap
  // or overlap, so the count also checks the join's timing
  const std::vector<Image> after = testing::DecodeVideo(path, 64, 48);
  ASSERT_EQ(after.size(), 10u);
  EXPECT_EQ(CountVideoFrames(path), 10);
  // the earlier frames keep their bits (joined, not encoded again)
  for (size_t k = 0; k < before.size(); ++k) EXPECT_TRUE(after[k].pixels == before[k].pixels) << k;
  // every frame once, in order: each decoded frame is nearest to its own source
  std::vector<Image> sources;
  for (int k = 0; k < 10; ++k) sources.push_back(Bar(64, 48, k));
  for (int k = 0; k < 10; ++k) EXPECT_EQ(testing::NearestImage(after[k], sources), k);
  // nothing but the video left: no segment, no concat list, no temporary name
  EXPECT_EQ(FilesIn(dir), 1);
}

// `image` with its red and blue bytes swapped, marked as holding `order`
Image SwapRedBlue(Image image, ChannelOrder order) {
  for (size_t i = 0; i < image.pixels.size(); i += 3)
    std::swap(image.pixels[i], image.pixels[i + 2]);
  image.order = order;
  return image;
}

// B, G, R frames (what a video alone sends) show the colours of their R, G, B originals
TEST(FfmpegPipe, BgrFramesShowTheirOwnColours) {
  const std::string path = TempDir("bgr") + "/video.mp4";
  {
    FfmpegPipe pipe(path, 64, 48, 20, "ffmpeg", VideoStart::kReplace, ChannelOrder::kBgr);
    for (int k = 0; k < 6; ++k) pipe.Write(SwapRedBlue(Bar(64, 48, k), ChannelOrder::kBgr));
    pipe.Finish();
  }
  const std::vector<Image> decoded = testing::DecodeVideo(path, 64, 48);
  ASSERT_EQ(decoded.size(), 6u);
  std::vector<Image> red_bars, blue_bars;
  for (int k = 0; k < 6; ++k) {
    red_bars.push_back(Bar(64, 48, k));
    blue_bars.push_back(SwapRedBlue(Bar(64, 48, k), ChannelOrder::kRgb));
  }
  for (int k = 0; k < 6; ++k) {
    // its own frame, and red (as drawn), not blue (bytes taken in the wrong order)
    EXPECT_EQ(testing::NearestImage(decoded[k], red_bars), k);
    EXPECT_EQ(testing::NearestImage(decoded[k], {red_bars[k], blue_bars[k]}), 0) << k;
  }
}

// frames handed over as drawings, downsampled on the writer thread, make the video that the
// images read on the caller's thread make (same bytes into a deterministic encoder)
TEST(FfmpegPipe, DrawingsMakeTheVideoOfTheirImages) {
  const std::string dir = TempDir("drawings");
  GlContext context;
  RenderTarget target(64, 48, 1, 1.5);
  FfmpegPipe from_drawings(dir + "/drawings.mp4", 64, 48, 20);
  FfmpegPipe from_images(dir + "/images.mp4", 64, 48, 20);
  for (int k = 0; k < 8; ++k) {
    target.Clear({0.1f, 0.1f, 0.1f, 1});
    // a bar 6 drawing pixels (4 image pixels) wide at x = 4k image pixels
    target.ClearRect(6 * k, 0, 6, target.height(), {0.9f, 0.3f, 0.1f, 1});
    from_drawings.Write(target.ReadDrawing(from_drawings.SpareDrawing()));
    from_images.Write(target.Read());
  }
  from_drawings.Finish();
  from_images.Finish();
  // the drawings' buffers come back for reuse
  EXPECT_NE(from_drawings.SpareDrawing().rgba, nullptr);
  const std::vector<Image> a = testing::DecodeVideo(dir + "/drawings.mp4", 64, 48);
  const std::vector<Image> b = testing::DecodeVideo(dir + "/images.mp4", 64, 48);
  ASSERT_EQ(a.size(), 8u);
  ASSERT_EQ(b.size(), 8u);
  for (size_t k = 0; k < a.size(); ++k) EXPECT_TRUE(a[k].pixels == b[k].pixels) << "frame " << k;
}

TEST(FfmpegPipe, AppendingNoFrameLeavesTheVideoAsItWas) {
  const std::string path = TempDir("append_nothing") + "/video.mp4";
  WriteBars(path, 0, 3, VideoStart::kReplace);
  const std::string bytes = ReadBytes(path);
  WriteBars(path, 3, 3, VideoStart::kAppend);
  EXPECT_TRUE(ReadBytes(path) == bytes);
}

TEST(FfmpegPipe, AFailedAppendLeavesTheEarlierVideo) {
  const std::string dir = TempDir("append_failing");
  const std::string path = dir + "/video.mp4";
  WriteBars(path, 0, 3, VideoStart::kReplace);
  const std::string bytes = ReadBytes(path);
  // `false` exits at once: the second segment fails, the first stays whole
  FfmpegPipe pipe(path, 32, 32, 25, "false", VideoStart::kAppend);
  EXPECT_THROW(
      {
        for (int k = 0; k < 2000; ++k) pipe.Write(Frame(32, 32, k));
        pipe.Finish();
      },
      std::runtime_error);
  EXPECT_TRUE(ReadBytes(path) == bytes);
  EXPECT_EQ(FilesIn(dir), 1);
}

TEST(FfmpegPipe, AppendNeedsAVideoToContinue) {
  EXPECT_THAT(
      [] {
        FfmpegPipe pipe(TempDir("append_missing") + "/v.mp4", 32, 32, 25, "ffmpeg",
                        VideoStart::kAppend);
      },
      ThrowsMessage<InputError>(HasSubstr("there is no video to continue")));
}

TEST(FfmpegPipe, CountingFramesOfWhatIsNoVideoIsAnInputError) {
  const std::string path = TempDir("not_a_video") + "/v.mp4";
  std::ofstream(path) << "not a video";
  EXPECT_THAT([&] { CountVideoFrames(path); },
              ThrowsMessage<InputError>(HasSubstr("not a readable video")));
}

}  // namespace
}  // namespace ecpsim::render
