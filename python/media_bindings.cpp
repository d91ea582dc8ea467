// Videos and image comparison for Python, made as the CLI makes them: Simulation.record steps and
// writes an MP4 as `ecpsim run --video` does, Simulation.recorder does the same for a controller's
// own loop, and compare_images compares two images as `ecpsim compare`. Reference: docs/python.md,
// "Videos" and "Comparing images".

#include "python/media_bindings.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "common/errors.h"
#include "engine/scene_io/loaded_scene.h"
#include "engine/scene_limits.h"
#include "python/conversions.h"
#include "python/step_interrupt.h"
#include "render/ffmpeg_pipe.h"
#include "render/frame_times.h"
#include "render/image_compare.h"
#include "render/png_writer.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

// ---- videos -------------------------------------------------------------------------------

// a str or os.PathLike as a path
std::string PathOf(const py::handle& path, const std::string& what) {
  try {
    return py::module_::import("os").attr("fspath")(path).cast<std::string>();
  } catch (const py::error_already_set&) {
    throw InputError(fmt::format("{} = {}: expected a path (str or os.PathLike)", what,
                                 py::repr(path).cast<std::string>()));
  }
}

// what a video shows and where it goes; unset arguments take the scene's `output` settings, as
// `ecpsim run --video` without --fps, --width, --height
struct VideoSettings {
  std::string path;
  double fps = 0;  // frames per simulated second
  int width = 0, height = 0;
  render::CameraSpec camera;
  bool overlays = true;
  std::string title;  // the scene file's name, as the CLI's frames
};

VideoSettings SettingsOf(const PySimulation& self, const char* where, const py::handle& path,
                         const py::object& fps, const py::object& width, const py::object& height,
                         const py::object& camera, bool overlays) {
  const engine::OutputSettings& output = self.scene->output;
  VideoSettings settings;
  settings.path = PathOf(path, fmt::format("{}: path", where));
  settings.fps = fps.is_none() ? output.fps : ToDouble(fps, fmt::format("{}: fps", where));
  settings.width = width.is_none() ? output.width : width.cast<int>();
  settings.height = height.is_none() ? output.height : height.cast<int>();
  for (const int pixels : {settings.width, settings.height}) {
    if (pixels < engine::kMinFramePixels || pixels > engine::kMaxFramePixels) {
      throw InputError(fmt::format("{}: width × height = {} × {}: expected {} … {} pixels each",
                                   where, settings.width, settings.height, engine::kMinFramePixels,
                                   engine::kMaxFramePixels));
    }
  }
  // the range FfmpegPipe takes, checked here so that the message names the argument
  if (!std::isfinite(settings.fps) || settings.fps <= 0 || settings.fps > 1000) {
    throw InputError(
        fmt::format("{}: fps = {}: expected a finite frame rate in (0, 1000] frames "
                    "per simulated second",
                    where, settings.fps));
  }
  settings.camera = CameraOf(output, camera);
  settings.overlays = overlays;
  const std::string& source = self.scene->scene.source;
  settings.title = source.substr(source.rfind('/') + 1);
  return settings;
}

// One MP4 of one Simulation being written, frame k showing the state nearest to k / fps after
// the first (render/frame_times.h, the CLI's rule). As the CLI's video alone
// (app/frame_recorder.cpp): frames drawn in B, G, R straight into ffmpeg and downsampled on the
// pipe's writer thread while the next draws; the file appears under `path` only when finished
// (render/ffmpeg_pipe.h: a temporary name, then a rename). Made, used and destroyed on one
// thread (its OpenGL context).
class VideoRecording {
 public:
  // starts ffmpeg and the renderer; the first Capture() is frame 0
  // @throws InputError if ffmpeg is missing or `path` cannot be written (render/ffmpeg_pipe.h)
  VideoRecording(const Simulation& sim, VideoSettings settings)
      : settings_(std::move(settings)),
        video_(settings_.path, settings_.width, settings_.height, settings_.fps, "ffmpeg",
               render::VideoStart::kReplace, render::ChannelOrder::kBgr),
        renderer_(RendererSettings(settings_)),
        builder_(sim.scene()),
        t0_(sim.state().t) {}

  // renders every frame due at the simulation's state (none, one, or more when fps > 1 / h)
  void Capture(const Simulation& sim) {
    const engine::State& state = sim.state();
    const engine::StepReport& report = sim.last_report();
    while (render::FrameDue(frames_, settings_.fps, sim.scene().h, state.t - t0_)) {
      render::FrameInput frame = builder_.Build(state, report.iterations, report.models);
      frame.camera = settings_.camera;
      frame.title = settings_.title;
      frame.show.hull = frame.show.inset = frame.show.text = frame.show.force_arrow =
          settings_.overlays;
      video_.Write(renderer_.RenderDrawing(frame, video_.SpareDrawing()));
      ++frames_;
    }
  }

  // closes the video with every frame so far and renames it to `path`
  // @throws std::runtime_error with ffmpeg's message if it failed
  void Finish() { video_.Finish(); }

  // as Finish after a failure (as the CLI after a SolverFailure): the frames so far make a
  // valid video; an encoder error is dropped, the failure is the error to report
  void FinishAfterFailure() noexcept {
    try {
      video_.Finish();
    } catch (const std::exception&) {
      // the temporary file is removed; `path` keeps what it held
    }
  }

  int frames() const { return frames_; }
  const std::string& path() const { return settings_.path; }

 private:
  static render::RenderSettings RendererSettings(const VideoSettings& settings) {
    render::RenderSettings renderer;
    renderer.width = settings.width;
    renderer.height = settings.height;
    renderer.channel_order = render::ChannelOrder::kBgr;
    return renderer;
  }

  VideoSettings settings_;
  render::FfmpegPipe video_;  // first: ffmpeg and the path are checked before the renderer starts
  render::Renderer renderer_;
  render::SceneFrameBuilder builder_;  // of the Simulation's scene, which outlives the recording
  double t0_;                          // s, the state of frame 0
  int frames_ = 0;
};

py::dict Record(PySimulation& self, const py::handle& path, const py::object& fps,
                const py::object& duration_arg, const py::object& width, const py::object& height,
                const py::object& camera, bool overlays) {
  VideoSettings settings = SettingsOf(self, "record", path, fps, width, height, camera, overlays);
  const engine::Scene& scene = self.scene->scene;
  const double duration =
      duration_arg.is_none() ? scene.duration : ToDouble(duration_arg, "record: duration");
  const std::string problem = std::isfinite(duration) && duration > 0
                                  ? engine::StepCountProblem(duration, scene.h)
                                  : std::string("a finite duration > 0 s");
  if (!problem.empty()) {
    throw InputError(
        fmt::format("record: duration = {}, h = {}: expected {}", duration, scene.h, problem));
  }
  const long steps = engine::PlannedSteps(duration, scene.h);
  const std::string video_path = settings.path;
  // as `ecpsim run`: a step that fails, or Ctrl-C (python/step_interrupt.h), ends the video at
  // the last good state
  std::unique_ptr<VideoRecording> recording;
  bool interrupted = false;  // while ffmpeg and the renderer start and frame 0 is drawn
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(self.mutex);
    CancelFlag setup_flag;  // nothing here reads it: the guard only records a SIGINT
    const StepInterrupt guard(setup_flag);
    recording = std::make_unique<VideoRecording>(self.sim, std::move(settings));
    try {
      recording->Capture(self.sim);
    } catch (...) {
      recording->FinishAfterFailure();
      throw;
    }
    interrupted = guard.interrupted();
  }
  try {
    if (interrupted) HandOverInterrupt();
    StepInterruptibly(self, steps, [&] { recording->Capture(self.sim); });
  } catch (...) {
    const py::gil_scoped_release release;
    recording->FinishAfterFailure();
    throw;
  }
  int frames = 0;
  double t_end = 0;
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(self.mutex);
    recording->Finish();
    frames = recording->frames();
    t_end = self.sim.state().t;
  }
  py::dict result;
  result["path"] = video_path;
  result["frames"] = frames;
  result["steps"] = steps;
  result["time"] = t_end;
  return result;
}

// The Python Recorder: a VideoRecording of a Simulation that a controller's loop feeds
struct PyRecorder {
  py::object owner;  // the Simulation, kept alive while recording
  PySimulation* self = nullptr;
  std::unique_ptr<VideoRecording> recording;  // null once closed
  std::thread::id thread;                     // the one that made it (its OpenGL context)
  int frames = 0;
  std::string path;

  void RequireOpenOnThisThread(const char* what) const {
    if (!recording) {
      throw InputError(fmt::format("Recorder.{}: the recording of '{}' is closed", what, path));
    }
    if (std::this_thread::get_id() != thread) {
      throw InputError(fmt::format(
          "Recorder.{}: called from another thread than the one that made the recorder (its "
          "OpenGL context is that thread's)",
          what));
    }
  }
};

void Capture(PyRecorder& recorder) {
  recorder.RequireOpenOnThisThread("capture");
  py::gil_scoped_release release;
  const std::lock_guard<std::mutex> lock(recorder.self->mutex);
  recorder.recording->Capture(recorder.self->sim);
  recorder.frames = recorder.recording->frames();
}

void Close(PyRecorder& recorder, bool failed) {
  if (!recorder.recording) return;
  recorder.RequireOpenOnThisThread("close");
  std::unique_ptr<VideoRecording> recording = std::move(recorder.recording);
  py::gil_scoped_release release;
  if (failed) {
    recording->FinishAfterFailure();
  } else {
    recording->Finish();
  }
}

// ---- image comparison ---------------------------------------------------------------------

// an image given as a PNG path or a uint8 (H, W, 3) array; `name` names it in messages
render::Image ImageOf(const py::handle& value, const char* which, std::string& name) {
  if (py::isinstance<py::array>(value)) {
    const py::array array = py::reinterpret_borrow<py::array>(value);
    if (!py::isinstance<py::array_t<std::uint8_t>>(value) || array.ndim() != 3 ||
        array.shape(2) != 3) {
      throw InputError(fmt::format(
          "compare_images: {} is an array of dtype {} and shape {}: expected uint8 (height, "
          "width, 3), RGB, top row first",
          which, py::str(array.dtype()).cast<std::string>(),
          py::str(value.attr("shape")).cast<std::string>()));
    }
    const auto pixels = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>(
        py::reinterpret_borrow<py::object>(value));
    render::Image image;
    image.height = static_cast<int>(pixels.shape(0));
    image.width = static_cast<int>(pixels.shape(1));
    image.pixels.assign(pixels.data(), pixels.data() + pixels.size());
    name = fmt::format("the {} array", which);
    return image;
  }
  name = PathOf(value, fmt::format("compare_images: {}", which));
  py::gil_scoped_release release;
  return render::ReadPng(name);
}

py::dict CompareImages(const py::handle& expected_arg, const py::handle& actual_arg, int threshold,
                       double max_fraction, const py::object& diff_arg) {
  render::CompareTolerance tolerance;
  tolerance.channel_threshold = threshold;
  tolerance.max_fraction = max_fraction;
  std::string expected_name, actual_name;
  const render::Image expected = ImageOf(expected_arg, "expected", expected_name);
  const render::Image actual = ImageOf(actual_arg, "actual", actual_name);
  const std::string diff_path = diff_arg.is_none() ? "" : PathOf(diff_arg, "compare_images: diff");
  render::ImageComparison comparison;
  {
    py::gil_scoped_release release;
    comparison = render::CompareImages(expected, actual, tolerance);
    if (!diff_path.empty() && !comparison.diff.pixels.empty()) {
      render::WritePng(diff_path, comparison.diff);
    }
  }
  // the line `ecpsim compare` prints after "same: " or "different: "
  const std::string summary =
      comparison.same_size
          ? comparison.Summary(tolerance)
          : fmt::format("sizes differ: {} is {}x{}, {} is {}x{}", expected_name, expected.width,
                        expected.height, actual_name, actual.width, actual.height);
  py::dict result;
  result["match"] = comparison.match;
  result["same_size"] = comparison.same_size;
  result["total_pixels"] = comparison.total_pixels;
  result["differing_pixels"] = comparison.differing_pixels;
  result["differing_fraction"] = comparison.differing_fraction;
  result["max_channel_difference"] = comparison.max_channel_difference;
  result["summary"] = summary;
  if (comparison.diff.pixels.empty()) {
    result["diff_image"] = py::none();
  } else {
    const render::Image& diff = comparison.diff;
    py::array_t<std::uint8_t> image({diff.height, diff.width, 3});
    std::memcpy(image.mutable_data(), diff.pixels.data(), diff.pixels.size());
    result["diff_image"] = image;
  }
  result["diff"] = diff_path.empty() || comparison.diff.pixels.empty()
                       ? py::object(py::none())
                       : py::object(py::str(diff_path));
  return result;
}

}  // namespace

void BindMedia(py::module_& m, py::class_<PySimulation>& sim) {
  sim.def("record", &Record, py::arg("path"), py::arg("fps") = py::none(),
          py::arg("duration") = py::none(), py::arg("width") = py::none(),
          py::arg("height") = py::none(), py::arg("camera") = py::none(),
          py::arg("overlays") = true,
          "Steps `duration` s (default: scene.duration) from the current state and writes an MP4 "
          "of it to `path` as `ecpsim run --video` does: frame k shows the state nearest to k / "
          "fps after the start (fps, width, height default to the scene's output block; camera "
          "and overlays as render()), H.264 through the ffmpeg program, written under a "
          "temporary name and renamed when complete. Releases the GIL. Returns {path, frames, "
          "steps, time}.\n"
          "Raises InputError (ffmpeg missing, a folder that does not exist, bad fps, size or "
          "duration) before any step; SolverFailure or ModelInvalid from a step, after closing "
          "the video with the frames up to the last good state, as the CLI.");
  sim.def(
      "recorder",
      [](py::object owner, const py::handle& path, const py::object& fps, const py::object& width,
         const py::object& height, const py::object& camera, bool overlays) {
        PySimulation& self = owner.cast<PySimulation&>();
        VideoSettings settings =
            SettingsOf(self, "recorder", path, fps, width, height, camera, overlays);
        auto recorder = std::make_unique<PyRecorder>();
        recorder->owner = owner;
        recorder->self = &self;
        recorder->thread = std::this_thread::get_id();
        recorder->path = settings.path;
        {
          py::gil_scoped_release release;
          const std::lock_guard<std::mutex> lock(self.mutex);
          recorder->recording = std::make_unique<VideoRecording>(self.sim, std::move(settings));
          // frame 0: the state now, as the CLI's first frame is the initial state
          recorder->recording->Capture(self.sim);
          recorder->frames = recorder->recording->frames();
        }
        return recorder;
      },
      py::arg("path"), py::arg("fps") = py::none(), py::arg("width") = py::none(),
      py::arg("height") = py::none(), py::arg("camera") = py::none(), py::arg("overlays") = true,
      "A Recorder writing an MP4 of this Simulation to `path` while your own loop steps it: "
      "`with sim.recorder('out.mp4') as rec:` then `sim.step(); rec.capture()` in the loop. "
      "Frame 0 is the state now, and frame k shows the state nearest to k / fps after it (the "
      "CLI's rule), so that loop writes the video record() would; arguments as record(). Starts "
      "ffmpeg now (InputError if it is missing or `path` cannot be written).");

  py::class_<PyRecorder>(
      m, "Recorder",
      "An MP4 being written from a Simulation (Simulation.recorder()). capture() after each "
      "step adds the frames due by then; the video appears at `path` when the `with` block or "
      "close() ends it, also when the block raised (the frames so far, as the CLI after a "
      "failure). A recorder never closed leaves `path` as it was. Use it on the thread that "
      "made it.")
      .def("capture", &Capture,
           "Renders the frames due at the Simulation's state: frame k once the time since the "
           "recorder started reaches k / fps − h / 2 (so none, one, or several when fps > 1 / "
           "h). Call it after every step (after step(n), the frames due within those n steps "
           "all show the state after them). Releases the GIL.")
      .def(
          "close", [](PyRecorder& recorder) { Close(recorder, false); },
          "Finishes the video and renames it to `path`; a second close() does nothing. Raises "
          "RuntimeError with ffmpeg's message if encoding failed.")
      .def("__enter__", [](py::object recorder) { return recorder; })
      .def(
          "__exit__",
          [](PyRecorder& recorder, const py::object& type, const py::object&, const py::object&) {
            Close(recorder, !type.is_none());
            return false;
          },
          py::arg("exc_type"), py::arg("exc_value"), py::arg("traceback"))
      .def_property_readonly(
          "frames", [](const PyRecorder& recorder) { return recorder.frames; },
          "Frames captured so far.")
      .def_property_readonly(
          "path", [](const PyRecorder& recorder) { return recorder.path; }, "Where the video goes.")
      .def_property_readonly(
          "closed", [](const PyRecorder& recorder) { return !recorder.recording; },
          "Whether close() (or the end of the `with` block) has finished the video.");

  const render::CompareTolerance defaults;
  m.def("compare_images", &CompareImages, py::arg("expected"), py::arg("actual"),
        py::arg("threshold") = defaults.channel_threshold,
        py::arg("max_fraction") = defaults.max_fraction, py::arg("diff") = py::none(),
        "Compares two images as `ecpsim compare EXPECTED ACTUAL` does (render/image_compare.h): "
        "each a PNG path or a uint8 (height, width, 3) RGB array, top row first. A pixel differs "
        "when a channel differs by more than `threshold` levels (0–255); the images match when "
        "they have one size and at most `max_fraction` of the pixels differ. `diff`: a PNG path "
        "for the diff image (differing pixels red, within the threshold orange), as --diff.\n"
        "Returns {match, same_size, total_pixels, differing_pixels, differing_fraction, "
        "max_channel_difference, summary (the line the CLI prints after 'same: ' or "
        "'different: '), diff_image (uint8 array, None for different sizes), diff (the path "
        "written, or None)}. Raises InputError for an unreadable PNG, a bad array or tolerance.");
}

}  // namespace ecpsim::python
