"""Ctrl-C during Simulation.step (python/step_interrupt.h): the step in progress stops within a
solver iteration, undone, and Python's SIGINT handler runs. Each case runs in a child process that
sends itself SIGINT 0.1 s into the pyramid's first step (ten boxes at rest on each other solved from
a cold start, the longest step of the shipped scenes: about 1.4 s on the 2-core EPYC), so that the
signal cannot reach pytest."""

import subprocess
import sys
import textwrap

# s: when the child sends itself SIGINT, well inside the first step even on a machine several
# times faster
POKE_AFTER = 0.1

# a child's start: the pyramid's simulation, the program's own SIGINT handler where asked (one that
# counts its calls and raises nothing), and start_poke(), a thread that sends SIGINT after argv[3] s.
# Each child starts it right before its `try`: a signal that came while the child was still setting
# up (importing numpy takes longer than POKE_AFTER on a loaded machine) would end it outside the try
PRELUDE = textwrap.dedent("""
    import json, os, signal, subprocess, sys, threading, time
    import ecpsim
    scene = ecpsim.load_scene(sys.argv[1])
    sim = ecpsim.Simulation(scene)
    calls = []
    if sys.argv[2] == "handler":
        signal.signal(signal.SIGINT, lambda signum, frame: calls.append(signum))
    def poke():
        time.sleep(float(sys.argv[3]))
        os.kill(os.getpid(), signal.SIGINT)
    def start_poke():
        threading.Thread(target=poke).start()
""")

CHILD = PRELUDE + textwrap.dedent("""
    start_poke()
    try:
        sim.step()
        print("returned", sim.time, len(calls))
    except KeyboardInterrupt:
        print("KeyboardInterrupt", sim.time, len(calls))
        sim.step()
        fresh = ecpsim.Simulation(scene)
        fresh.step()
        same = all((getattr(sim, a) == getattr(fresh, a)).all()
                   for a in ("positions", "quaternions", "velocities", "angular_velocities"))
        print("stepped on", sim.time, same)
""")


def run_child(scenes, mode, child=CHILD, *more_args):
    """The lines a child script printed, run on the pyramid with `mode` ("default" or "handler")."""
    done = subprocess.run(
        [sys.executable, "-c", child, str(scenes / "pyramid.yaml"), mode, str(POKE_AFTER),
         *map(str, more_args)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout.split("\n")


def test_ctrl_c_stops_the_step_in_progress_and_leaves_it_undone(scenes):
    lines = run_child(scenes, "default")
    # KeyboardInterrupt with the state still at t = 0: the first step was stopped, not
    # finished; stepping on then gives the uninterrupted step, bit for bit
    assert lines[0] == "KeyboardInterrupt 0.0 0", lines
    assert lines[1] == "stepped on 0.01 True", lines


def test_a_handler_that_raises_nothing_lets_the_step_be_taken(scenes):
    lines = run_child(scenes, "handler")
    # the program's handler ran once, and the stopped step was taken again to its end
    assert lines[0] == "returned 0.01 1", lines


# the same for Simulation.record: the pyramid's first 0.05 s at 20 frames/s, frames at 0 and 0.05 s
RECORD_CHILD = PRELUDE + textwrap.dedent("""
    path = sys.argv[4]
    start_poke()
    try:
        result = sim.record(path, duration=0.05, fps=20, width=64, height=48)
        print("returned", result["frames"], result["steps"], sim.time, len(calls))
    except KeyboardInterrupt:
        print("KeyboardInterrupt", sim.time, len(calls))
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                            "stream=nb_frames", "-of", "json", path],
                           capture_output=True, text=True, check=True).stdout
    print("video", json.loads(probe)["streams"][0]["nb_frames"])
""")


def test_ctrl_c_ends_a_recording_at_the_last_step_taken(scenes, tmp_path):
    lines = run_child(scenes, "default", RECORD_CHILD, tmp_path / "pyramid.mp4")
    # the first step stopped, undone; the video holds the frame at t = 0 and is a valid MP4
    assert lines[0] == "KeyboardInterrupt 0.0 0", lines
    assert lines[1] == "video 1", lines


def test_a_handler_that_raises_nothing_lets_the_recording_go_on(scenes, tmp_path):
    lines = run_child(scenes, "handler", RECORD_CHILD, tmp_path / "pyramid.mp4")
    assert lines[0] == "returned 2 5 0.05 1", lines
    assert lines[1] == "video 2", lines


# the same for ecpsim.rollout: two copies of the pyramid stepped 3 steps each on two threads, a
# push on the first's CM in its first step (a control that must act once, however often the step
# is stopped and taken again)
ROLLOUT_CHILD = PRELUDE + textwrap.dedent("""
    import numpy as np
    def fresh():
        return [ecpsim.Simulation(scene), ecpsim.Simulation(scene)]
    controls = np.zeros((2, 3, len(scene.body_names), 6))
    controls[0, 0, scene.body_names.index("b1"), 0] = 1.0
    sims = fresh()
    start_poke()
    try:
        rows = ecpsim.rollout(sims, 3, threads=2, controls=controls)
        reference = ecpsim.rollout(fresh(), 3, threads=2, controls=controls)
        same = all((rows[k] == reference[k]).all() for k in reference)
        print("returned", [s.time for s in sims], len(calls), same)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", [s.time for s in sims], len(calls))
""")


def test_ctrl_c_stops_a_rollout_with_every_step_in_progress_undone(scenes):
    lines = run_child(scenes, "default", ROLLOUT_CHILD)
    assert lines[0] == "KeyboardInterrupt [0.0, 0.0] 0", lines


def test_a_handler_that_raises_nothing_lets_the_rollout_go_on(scenes):
    lines = run_child(scenes, "handler", ROLLOUT_CHILD)
    # every step taken once, the push applied once: the rows of an uninterrupted rollout
    assert lines[0] == "returned [0.03, 0.03] 1 True", lines
