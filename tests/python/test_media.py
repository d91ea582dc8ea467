"""Simulation.record, Simulation.recorder and compare_images against the CLI's video and compare."""

import json
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import ecpsim

BINARY_DIR = pathlib.Path(os.environ.get("ECPSIM_BINARY_DIR", "build"))
CLI = str(BINARY_DIR / "app" / "ecpsim")

# the slide at 20 frames/s, 64×48, as tests/app/frames_command_test.cpp runs it: 0.5 s at
# h = 0.01 s, frames at t = 0, 0.05, ..., 0.5
VIDEO = {"fps": 20, "width": 64, "height": 48}
SLIDE_FRAMES = 11

# a tilted box falling onto the ground with one Newton iteration per start: its first contact
# step (from t = 0.19 s) fails after every retry, so a run stops there (exit code 3 of the CLI)
FAILING_FALL = """\
h: 0.01
duration: 1.0
solver: {max_iterations: 1}
ground:
  friction: {mu: 0.22, e_t: 1, e_o: 1, e_r: 0.1}
bodies:
  - name: box
    shape: {box: {size: [0.4, 0.3, 0.1]}}
    mass: 5
    rpy: [25, 0, 0]
    position: [0, 0, 0.3]
"""


def probe(path):
    """The video's first stream as ffprobe reads it: frame count, size, frame rate."""
    out = subprocess.run(
        ["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
         "stream=nb_frames,width,height,r_frame_rate,codec_name,pix_fmt", "-of", "json",
         str(path)], check=True, capture_output=True, text=True).stdout
    stream = json.loads(out)["streams"][0]
    return {"frames": int(stream["nb_frames"]), "width": stream["width"],
            "height": stream["height"], "fps": stream["r_frame_rate"],
            "codec": stream["codec_name"], "pix_fmt": stream["pix_fmt"]}


def cli_video(scene, out, *options):
    """`ecpsim run SCENE --video` at VIDEO's rate and size; its exit code and video path."""
    result = subprocess.run(
        [CLI, "run", str(scene), "-o", str(out), "--video", "--fps", str(VIDEO["fps"]),
         "--width", str(VIDEO["width"]), "--height", str(VIDEO["height"]), *options],
        capture_output=True, text=True)
    return result.returncode, out / "video.mp4"


def test_record_writes_the_clis_video(scenes, tmp_path):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    path = tmp_path / "slide.mp4"
    result = sim.record(path, **VIDEO)
    assert result == {"path": str(path), "frames": SLIDE_FRAMES, "steps": 50, "time": 0.5}
    assert sim.steps == 50
    # what the CLI's tests check of its video: an MP4 of 11 frames of 64×48 at 20 frames/s
    assert path.read_bytes()[4:8] == b"ftyp"
    assert probe(path) == {"frames": SLIDE_FRAMES, "width": 64, "height": 48, "fps": "20/1",
                           "codec": "h264", "pix_fmt": "yuv420p"}
    # and the CLI's video itself, byte for byte (same frames, same encoder and options)
    code, cli = cli_video(scenes / "slide.yaml", tmp_path / "cli")
    assert code == 0
    assert path.read_bytes() == cli.read_bytes()
    # nothing but the video: the temporary name is gone
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cli", "slide.mp4"]


def test_a_recorder_in_a_control_loop_writes_the_same_video(scenes, tmp_path):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    path = tmp_path / "loop.mp4"
    with sim.recorder(path, **VIDEO) as rec:
        assert rec.frames == 1  # the state now is frame 0
        for _ in range(50):
            sim.apply_wrench("box", force=[0, 0, 0])
            sim.step()
            rec.capture()
        assert not path.exists()  # written under a temporary name until closed
    assert rec.closed and rec.frames == SLIDE_FRAMES
    recorded = tmp_path / "record.mp4"
    ecpsim.Simulation(sim.scene).record(recorded, **VIDEO)
    assert path.read_bytes() == recorded.read_bytes()
    with pytest.raises(ecpsim.InputError, match="closed"):
        rec.capture()
    # a recording that starts later counts its frames from its own first one: 0.2 s at
    # 20 frames/s are frames at 0, 0.05, ..., 0.2 after the start
    with sim.recorder(tmp_path / "later.mp4", **VIDEO) as rec:
        for _ in range(20):
            sim.step()
            rec.capture()
    assert rec.frames == 5 and probe(tmp_path / "later.mp4")["frames"] == 5


def test_a_solver_failure_leaves_the_frames_so_far_as_the_cli(tmp_path):
    scene_path = tmp_path / "fall.yaml"
    scene_path.write_text(FAILING_FALL)
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scene_path)))
    path = tmp_path / "fall.mp4"
    with pytest.raises(ecpsim.SolverFailure, match="t = 0.19 s"):
        sim.record(path, **VIDEO)
    # frames at t = 0, 0.05, 0.1, 0.15 up to the last good state, t = 0.19 s
    assert sim.steps == 19
    assert probe(path)["frames"] == 4
    code, cli = cli_video(scene_path, tmp_path / "cli")
    assert code == 3
    assert path.read_bytes() == cli.read_bytes()
    # a recorder's `with` block that raised closes the video with its frames too
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scene_path)))
    with pytest.raises(ecpsim.SolverFailure):
        with sim.recorder(tmp_path / "loop.mp4", **VIDEO) as rec:
            while True:
                sim.step()
                rec.capture()
    assert (tmp_path / "loop.mp4").read_bytes() == cli.read_bytes()


def test_bad_arguments_are_input_errors_before_any_step(scenes, tmp_path, monkeypatch):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    with pytest.raises(ecpsim.InputError, match=r"record: fps = 0: expected a finite frame rate"):
        sim.record(tmp_path / "a.mp4", fps=0)
    with pytest.raises(ecpsim.InputError, match="fps = nan"):
        sim.recorder(tmp_path / "a.mp4", fps=float("nan"))
    with pytest.raises(ecpsim.InputError, match="width × height = 8 × 48"):
        sim.record(tmp_path / "a.mp4", fps=20, width=8, height=48)
    with pytest.raises(ecpsim.InputError, match="duration = -1"):
        sim.record(tmp_path / "a.mp4", duration=-1)
    with pytest.raises(ecpsim.InputError, match="the folder '.*missing' does not exist"):
        sim.record(tmp_path / "missing" / "a.mp4", **VIDEO)
    with pytest.raises(ecpsim.InputError, match="camera.zoom: unknown key"):
        sim.record(tmp_path / "a.mp4", camera={"zoom": 2})
    monkeypatch.setenv("PATH", "/nonexistent")
    with pytest.raises(ecpsim.InputError,
                       match="the program 'ffmpeg' is not on PATH; install the Debian package"):
        sim.record(tmp_path / "a.mp4", **VIDEO)
    assert sim.steps == 0 and not any(tmp_path.iterdir())


# ---- compare_images -------------------------------------------------------------------------

def cli_compare(expected, actual, *options):
    """`ecpsim compare`'s exit code and its line after 'same: ' or 'different: '."""
    result = subprocess.run([CLI, "compare", str(expected), str(actual), *options],
                            capture_output=True, text=True)
    match = re.match(r"(same|different): (.*)", result.stdout)
    return result.returncode, match.group(2) if match else result.stdout + result.stderr


@pytest.fixture
def frames(scenes, tmp_path):
    """A 96×64 frame of the slide as a PNG and an array, and a copy with 6 pixels changed."""
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    image = sim.render(96, 64)
    changed = image.copy()
    changed[10, 20:23] = 255 - changed[10, 20:23]        # 3 pixels inverted: > 24 levels
    row = changed[30, 40:43].astype(int)                  # 3 pixels 10 levels off: within 24
    changed[30, 40:43] = np.where(row >= 128, row - 10, row + 10)
    changed[50, 5:8] = 255 - changed[50, 5:8]            # 3 more inverted
    paths = tmp_path / "expected.png", tmp_path / "actual.png"
    for path, pixels in zip(paths, (image, changed)):
        write_png(path, pixels)
    return {"image": image, "changed": changed, "paths": paths}


def write_png(path, pixels):
    """`pixels` (uint8 (H, W, 3)) as an 8-bit RGB PNG, written independently of ecpsim."""
    import struct
    import zlib
    height, width, _ = pixels.shape
    raw = b"".join(b"\x00" + pixels[y].tobytes() for y in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                     + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))


def test_equal_images_match(frames):
    expected, _ = frames["paths"]
    for a, b in [(expected, expected), (frames["image"], frames["image"]),
                 (expected, frames["image"])]:
        result = ecpsim.compare_images(a, b)
        assert result["match"] and result["same_size"]
        assert result["differing_pixels"] == 0 and result["max_channel_difference"] == 0
        assert result["total_pixels"] == 96 * 64
    code, summary = cli_compare(expected, expected)
    assert code == 0 and summary == ecpsim.compare_images(expected, expected)["summary"]


def test_a_few_pixels_differ_as_the_cli_reports(frames, tmp_path):
    expected, actual = frames["paths"]
    diff = tmp_path / "diff.png"
    for options, kwargs in [((), {}), (("--max-fraction", "0.001"), {"max_fraction": 0.001}),
                            (("--threshold", "5"), {"threshold": 5})]:
        code, summary = cli_compare(expected, actual, *options)
        for a, b in [(expected, actual), (frames["image"], frames["changed"])]:
            result = ecpsim.compare_images(a, b, **kwargs)
            assert result["summary"] == summary
            assert result["match"] == (code == 0)
    # 6 of 6144 pixels differ by more than 24 levels (0.098% > the default 0.05%); at threshold 5
    # the 3 pixels raised by 10 levels count too
    result = ecpsim.compare_images(expected, actual, diff=diff)
    assert not result["match"] and result["differing_pixels"] == 6
    assert result["differing_fraction"] == 6 / 6144
    assert ecpsim.compare_images(expected, actual, threshold=5)["differing_pixels"] == 9
    assert ecpsim.compare_images(expected, actual, max_fraction=0.001)["match"]
    # the diff image, in the file as --diff writes it and as an array: red where they differ
    assert result["diff"] == str(diff) and diff.exists()
    assert tuple(result["diff_image"][10, 20]) == (230, 0, 0)
    cli_diff = tmp_path / "cli_diff.png"
    subprocess.run([CLI, "compare", str(expected), str(actual), "--diff", str(cli_diff)],
                   capture_output=True)
    assert ecpsim.compare_images(diff, cli_diff, threshold=0, max_fraction=0)["match"]


def test_compare_images_bad_input(frames, tmp_path):
    image = frames["image"]
    with pytest.raises(ecpsim.InputError, match="missing.png"):
        ecpsim.compare_images(tmp_path / "missing.png", image)
    with pytest.raises(ecpsim.InputError, match=r"expected uint8 \(height, width, 3\)"):
        ecpsim.compare_images(image.astype(np.float32), image)
    with pytest.raises(ecpsim.InputError, match=r"expected uint8 \(height, width, 3\)"):
        ecpsim.compare_images(image[:, :, :2], image)
    with pytest.raises(ecpsim.InputError, match="threshold"):
        ecpsim.compare_images(image, image, threshold=300)
    # different sizes: no match, as the CLI (its line names the two)
    result = ecpsim.compare_images(image, image[:32])
    assert not result["match"] and not result["same_size"] and result["diff_image"] is None
    assert result["summary"] == ("sizes differ: the expected array is 96x64, the actual array "
                                 "is 96x32")
