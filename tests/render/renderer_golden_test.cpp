// Golden-image tests of whole frames: the canonical contacts of the paper's bodies at 320×240.

#include <memory>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "tests/render/canonical_frames.h"
#include "tests/render/golden.h"

namespace ecpsim::render {
namespace {

using testing::MatchesGolden;

// The goldens are rendered by llvmpipe, which is bit-for-bit deterministic on one machine (two
// renders compare with max channel difference 0: RendererTest.SameInputGivesIdenticalPixels).
// Another CPU or Mesa build may flip single supersamples on anti-aliased edges, changing an edge
// pixel by up to a quarter of the edge contrast (≤ 64 levels) but not changing flat areas; a
// threshold of 24 levels ignores shading and glyph-hinting noise below that, and 0.05% of the
// 76800 pixels (38 pixels) bounds the flipped edge pixels. An ECP moved by 2.5 pixels changes
// more than twice that many (RendererTest.ComparisonCatchesEcpMovedByAFewPixels), so real
// changes fail.
const CompareTolerance kGoldenTolerance{24, 0.0005};

class RendererGolden : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    RenderSettings settings;
    settings.width = 320;
    settings.height = 240;
    settings.supersample = 2;
    renderer_ = std::make_unique<Renderer>(settings);
  }
  static void TearDownTestSuite() { renderer_.reset(); }
  static std::unique_ptr<Renderer> renderer_;
};
std::unique_ptr<Renderer> RendererGolden::renderer_;

TEST_F(RendererGolden, DeskRestingFlat) {
  const FrameInput frame = testing::DeskRestingFlat();
  // four square feet; their hull a square whose centre carries the ECP
  ASSERT_EQ(frame.contacts[0].patch.polygons.size(), 4u);
  ASSERT_EQ(frame.contacts[0].patch.hull.size(), 4u);
  EXPECT_TRUE(MatchesGolden(renderer_->Render(frame), "desk_resting_flat", kGoldenTolerance));
}

TEST_F(RendererGolden, TBarTwoPoint) {
  const FrameInput frame = testing::TBarTwoPoint();
  ASSERT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kTwoPoint);
  ASSERT_EQ(frame.contacts[0].patch.points.size(), 2u);
  EXPECT_TRUE(MatchesGolden(renderer_->Render(frame), "tbar_two_point", kGoldenTolerance));
}

TEST_F(RendererGolden, DumbbellOnItsSide) {
  const FrameInput frame = testing::DumbbellOnItsSide();
  // two rims on the ground (segments or thin facets) whose hull is one long segment
  ASSERT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kNonConvexLine);
  EXPECT_TRUE(MatchesGolden(renderer_->Render(frame), "dumbbell_on_its_side", kGoldenTolerance));
}

TEST_F(RendererGolden, HullOfNonConvexBlock) {
  const FrameInput frame = testing::HullOfNonConvexBlock();
  ASSERT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kNonConvexPatch);
  EXPECT_TRUE(MatchesGolden(renderer_->Render(frame), "hull_of_l_block", kGoldenTolerance));
}

TEST_F(RendererGolden, ContactInset) {
  const FrameInput frame = testing::TBarFlatWithForce();
  ASSERT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kNonConvexPatch);
  EXPECT_TRUE(MatchesGolden(renderer_->Render(frame), "tbar_flat_inset", kGoldenTolerance));
}

}  // namespace
}  // namespace ecpsim::render
