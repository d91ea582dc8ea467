#include "render/frame_times.h"

namespace ecpsim::render {

bool FrameDue(int frame, double fps, double h, double elapsed) {
  return frame / fps <= elapsed + h / 2;
}

int FramesDue(double fps, double h, double elapsed) {
  int frames = 0;
  while (FrameDue(frames, fps, h, elapsed)) ++frames;
  return frames;
}

}  // namespace ecpsim::render
