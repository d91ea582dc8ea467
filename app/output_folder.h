#pragma once
// The output folder of `ecpsim run` and `ecpsim drop` holds one run: a new run into a folder first
// clears what an earlier run left there and it would not overwrite itself, so that frames of a
// longer earlier run never pass for this run's.

#include <string>

namespace ecpsim::app {

/// Whether `file_name` is a frame's name as PngSequenceWriter writes it: frame_NNNNNN.png.
bool IsFrameName(const std::string& file_name);

/// Makes `out_dir` ready for a run: creates it, checks that a regular file or nothing is at each
/// of the run's output names (trajectory.csv, summary.json, video.mp4, checkpoint.json), and
/// removes the temporary files that killed processes left in it and in its frames/ folder. For a
/// new run (not `resume`) it also removes the earlier run's frames (the regular files named
/// frame_NNNNNN.png in DIR/frames: nothing else there is touched, and the folder itself only if
/// that leaves it empty), DIR/video.mp4 and DIR/checkpoint.json.
/// @throws InputError if the folder cannot be created or an output name is taken by something
///         other than a regular file; nothing is removed then.
void PrepareOutputFolder(const std::string& out_dir, bool resume);

}  // namespace ecpsim::app
