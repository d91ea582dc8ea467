#pragma once
// Which states of a simulation become a video's frames: frame k shows the state nearest to
// k / fps after the recording began, at any step h (the CLI's --frames/--video and Python's
// Simulation.record share this rule).

namespace ecpsim::render {

/// Whether frame `frame` (0, 1, …) is due once the recording has reached the state at `elapsed`
/// s after its first frame, stepping at `h` s: frame / fps ≤ elapsed + h / 2, so the frame shows
/// the state nearest to its time (the earlier one on a tie). `fps` > 0 frames per simulated s.
bool FrameDue(int frame, double fps, double h, double elapsed);

/// How many frames are due once the recording has reached `elapsed` s (FrameDue): 1 at 0.
int FramesDue(double fps, double h, double elapsed);

}  // namespace ecpsim::render
