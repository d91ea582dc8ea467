// The renderer as a whole: determinism, the comparator catching a moved ECP, the pixel path on a
// known frame, the mesh cache, and bad input.

#include <cfenv>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/image_compare.h"
#include "render/renderer.h"
#include "tests/render/canonical_frames.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// the golden tests' tolerance (renderer_golden_test.cpp explains the numbers)
const CompareTolerance kGoldenTolerance{24, 0.0005};

class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    RenderSettings settings;
    settings.width = 320;
    settings.height = 240;
    renderer_ = std::make_unique<Renderer>(settings);
  }
  static void TearDownTestSuite() { renderer_.reset(); }
  static std::unique_ptr<Renderer> renderer_;
};
std::unique_ptr<Renderer> RendererTest::renderer_;

TEST_F(RendererTest, SameInputGivesIdenticalPixels) {
  const FrameInput frame = testing::DeskRestingFlat();
  const Image first = renderer_->Render(frame);
  renderer_->Render(testing::TBarTwoPoint());  // other state in between must not leak
  const Image second = renderer_->Render(frame);
  const ImageComparison comparison = CompareImages(first, second, {0, 0.0});
  EXPECT_EQ(comparison.max_channel_difference, 0);
  EXPECT_EQ(comparison.differing_pixels, 0);
}

TEST_F(RendererTest, ComparisonCatchesEcpMovedByAFewPixels) {
  FrameInput frame = testing::DeskRestingFlat();
  const Image original = renderer_->Render(frame);

  // move the ECP 1.5 cm along x: check that this is a few pixels in the main view
  const Camera camera = renderer_->FrameCamera(frame);
  const Eigen::Vector3d a1 = *frame.contacts[0].a1;
  const Eigen::Vector3d moved = a1 + Eigen::Vector3d(0.015, 0, 0);
  Eigen::Vector3d p0, p1;
  ASSERT_TRUE(camera.ToPixel(a1, &p0));
  ASSERT_TRUE(camera.ToPixel(moved, &p1));
  const double shift = (p1 - p0).head<2>().norm();
  constexpr double kFewestPixels = 2.0, kMostPixels = 4.0;  // "a few pixels"
  ASSERT_GT(shift, kFewestPixels);
  ASSERT_LT(shift, kMostPixels);

  frame.contacts[0].a1 = moved;
  const ImageComparison comparison =
      CompareImages(original, renderer_->Render(frame), kGoldenTolerance);
  RecordProperty("ecp_shift_pixels", std::to_string(shift));
  RecordProperty("differing", comparison.Summary(kGoldenTolerance));
  EXPECT_FALSE(comparison.match) << comparison.Summary(kGoldenTolerance);
  // not just barely: the marker change is at least twice the allowed count of pixels
  EXPECT_GT(comparison.differing_pixels, 2 * kGoldenTolerance.max_fraction * 320 * 240);
}

TEST_F(RendererTest, EmptyFrameIsBackgroundEverywhere) {
  // nothing drawn but the clear colour: every pixel is (0.95, 0.96, 0.97) × 255 rounded
  FrameInput frame;
  frame.show.text = false;
  const Image image = renderer_->Render(frame);
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  ASSERT_EQ(image.pixels.size(), 320u * 240u * 3u);
  for (size_t i = 0; i < image.pixels.size(); i += 3) {
    ASSERT_EQ(image.pixels[i], 242);
    ASSERT_EQ(image.pixels[i + 1], 245);
    ASSERT_EQ(image.pixels[i + 2], 247);
  }
}

TEST_F(RendererTest, TextOverlayIsTopLeft) {
  // the text panel is drawn in the top-left corner: rows near the top differ from an empty
  // frame there, the bottom-left corner does not (a row-order check on the whole render path)
  FrameInput blank;
  blank.show.text = false;
  FrameInput text;
  text.title = "row order";
  const Image a = renderer_->Render(blank), b = renderer_->Render(text);
  const auto differs = [&](int x, int y) {
    return std::abs(int(a.Pixel(x, y)[0]) - int(b.Pixel(x, y)[0])) > 0;
  };
  EXPECT_TRUE(differs(12, 12));    // inside the panel, 8 px margin
  EXPECT_FALSE(differs(12, 227));  // mirrored position near the bottom
}

TEST_F(RendererTest, MeshesStayInGpuBuffersAndAreFreedWithTheirBodies) {
  const FrameInput frame = testing::DeskRestingFlat();
  renderer_->Render(frame);
  // the desk mesh and its hull mesh
  const int before = renderer_->CachedMeshCount();
  renderer_->Render(frame);
  EXPECT_EQ(renderer_->CachedMeshCount(), before);
  {
    const FrameInput other = testing::TBarTwoPoint();
    renderer_->Render(other);
    EXPECT_EQ(renderer_->CachedMeshCount(), before + 2);
  }
  // the T-bar's meshes died with `other`; the next frame frees their buffers
  renderer_->Render(frame);
  EXPECT_EQ(renderer_->CachedMeshCount(), before);
}

TEST_F(RendererTest, NonFinitePoseIsAnInputError) {
  FrameInput frame = testing::DeskRestingFlat();
  frame.bodies[0].X_WB.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([&] { renderer_->Render(frame); },
              ThrowsMessage<InputError>(HasSubstr("bodies[0].X_WB")));
}

TEST_F(RendererTest, NonFiniteEcpIsAnInputError) {
  FrameInput frame = testing::DeskRestingFlat();
  frame.contacts[0].a1 = Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 0);
  EXPECT_THAT([&] { renderer_->Render(frame); },
              ThrowsMessage<InputError>(HasSubstr("contacts[0].a1")));
}

// a fixed camera over the ground: the background is drawn twice, then copied; the copy must be
// invisible, also under bodies that moved since it was saved
TEST(RendererBackground, CopiedBackgroundGivesTheDrawnPixels) {
  RenderSettings settings;
  settings.width = 320;
  settings.height = 240;
  Renderer cached(settings), fresh(settings);
  FrameInput frame = testing::DeskRestingFlat();
  frame.camera.automatic = false;
  frame.camera.target = Eigen::Vector3d(0, 0, 0.3);
  const Image drawn = cached.Render(frame);
  EXPECT_FALSE(cached.LastBackgroundCached());
  cached.Render(frame);
  EXPECT_FALSE(cached.LastBackgroundCached());  // saved now, drawn
  const Image copied = cached.Render(frame);
  ASSERT_TRUE(cached.LastBackgroundCached());
  const ImageComparison same = CompareImages(drawn, copied, {0, 0.0});
  EXPECT_EQ(same.max_channel_difference, 0);

  // the desk moved and turned: the copied ground under it equals a freshly drawn one
  frame.bodies[0].X_WB.translation() += Eigen::Vector3d(0.05, -0.03, 0.02);
  frame.bodies[0].X_WB.rotate(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  const Image moved = cached.Render(frame);
  ASSERT_TRUE(cached.LastBackgroundCached());
  const Image reference = fresh.Render(frame);
  ASSERT_FALSE(fresh.LastBackgroundCached());
  const ImageComparison moved_same = CompareImages(reference, moved, {0, 0.0});
  EXPECT_EQ(moved_same.max_channel_difference, 0);
  EXPECT_GT(CompareImages(copied, moved, {0, 0.0}).differing_pixels, 1000);

  // another camera is drawn, not copied, and gives that camera's pixels
  frame.camera.position.x() += 0.1;
  const Image turned = cached.Render(frame);
  EXPECT_FALSE(cached.LastBackgroundCached());
  EXPECT_EQ(CompareImages(fresh.Render(frame), turned, {0, 0.0}).max_channel_difference, 0);
}

// The floating-point modes the calling thread computes in: rounding direction, and on x86 the
// SSE control bits (flush-to-zero, denormals-are-zero, rounding, exception masks; not the sticky
// exception flags) and the x87 control word.
struct FloatingPointModes {
  int rounding = std::fegetround();
#if defined(__x86_64__) || defined(__i386__)
  unsigned sse_control = [] {
    constexpr unsigned kSseExceptionFlags = 0x3f;  // MXCSR bits 0-5
    unsigned mxcsr = 0;
    asm volatile("stmxcsr %0" : "=m"(mxcsr));
    return mxcsr & ~kSseExceptionFlags;
  }();
  unsigned short x87_control = [] {
    unsigned short word = 0;
    asm volatile("fnstcw %0" : "=m"(word));
    return word;
  }();
#endif
  bool operator==(const FloatingPointModes& other) const {
#if defined(__x86_64__) || defined(__i386__)
    if (sse_control != other.sse_control || x87_control != other.x87_control) return false;
#endif
    return rounding == other.rounding;
  }
};

// Software OpenGL (llvmpipe) sets flush-to-zero and denormals-are-zero on its own threads; if
// it did so on the caller's, the engine stepping between frames would compute differently with
// frames than without. Making a context, compiling shaders, drawing, reading back and
// destroying must leave the caller's modes as they were.
TEST(RendererFloatingPoint, RenderingKeepsTheCallersFloatingPointModes) {
  const FloatingPointModes before;
  {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer renderer(settings);
    EXPECT_TRUE(FloatingPointModes() == before) << "after making the context";
    renderer.Render(testing::DeskRestingFlat());
    renderer.Render(testing::TBarTwoPoint());
    EXPECT_TRUE(FloatingPointModes() == before) << "after rendering";
  }
  EXPECT_TRUE(FloatingPointModes() == before) << "after destroying the context";
}

TEST(RendererSettings, BadResolutionIsAnInputError) {
  RenderSettings settings;
  settings.width = 0;
  EXPECT_THAT([&] { Renderer renderer(settings); },
              ThrowsMessage<InputError>(HasSubstr("resolution 0x720")));
}

TEST(RendererSettings, MissingFontIsAnInputError) {
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.font_path = "/nonexistent/font.ttf";
  EXPECT_THAT([&] { Renderer renderer(settings); },
              ThrowsMessage<InputError>(HasSubstr("/nonexistent/font.ttf")));
}

}  // namespace
}  // namespace ecpsim::render
