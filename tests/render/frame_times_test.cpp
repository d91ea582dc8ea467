// The frame-time rule of render/frame_times.h: frame k shows the state nearest to k / fps.

#include "render/frame_times.h"

#include <gtest/gtest.h>

namespace ecpsim::render {
namespace {

TEST(FrameTimesTest, OneFrameAtTheStartThenOneEachOneOverFps) {
  // 20 frames/s at h = 0.01 s: frames at steps 0, 5, 10, ...
  EXPECT_EQ(FramesDue(20, 0.01, 0), 1);
  EXPECT_EQ(FramesDue(20, 0.01, 0.04), 1);
  EXPECT_EQ(FramesDue(20, 0.01, 0.05), 2);
  EXPECT_EQ(FramesDue(20, 0.01, 0.5), 11);  // the slide's 0.5 s: 11 frames, as the CLI tests
}

TEST(FrameTimesTest, AFrameTakesTheNearestStateTheEarlierOnATie) {
  // 30 frames/s at h = 0.02 s: frame 1 (t = 0.0333) is nearer to step 2 (0.04) than to step 1
  EXPECT_FALSE(FrameDue(1, 30, 0.02, 0.02));
  EXPECT_TRUE(FrameDue(1, 30, 0.02, 0.04));
  // 10 frames/s at h = 0.2 s: frame 1 (t = 0.1) lies halfway between steps 0 and 1: step 0
  EXPECT_TRUE(FrameDue(1, 10, 0.2, 0));
  EXPECT_EQ(FramesDue(10, 0.2, 0), 2);
}

}  // namespace
}  // namespace ecpsim::render
