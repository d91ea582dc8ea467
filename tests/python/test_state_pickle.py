"""State pickles: a round trip, in this process or through another one, continues bit for bit
under every contact model's warm start; a pickle not of this form, or of other sizes than the
scene's contacts, is an InputError."""

import concurrent.futures
import json
import multiprocessing
import pickle

import numpy as np
import pytest

import ecpsim

# (scene, overrides): every kind of warm start a State holds — the hull model's against a fixed
# obstacle (tbar) and against a kinematic body (push_box: G's window too), the multi-patch
# model's parts, and none (planar, point)
CASES = [("tbar.yaml", {}), ("push_box.yaml", {}), ("dumbbell.yaml", {"model": "multipatch"}),
         ("slide.yaml", {"model": "planar"}), ("tbar.yaml", {"model": "point"})]
SAVE_AT, CONTINUE = 30, 20  # steps: well into contact, then on


def trajectory(sim, steps):
    """Every step's poses, velocities, contact impulses and solver iterations."""
    out = []
    for _ in range(steps):
        sim.step()
        out.append((sim.positions, sim.quaternions, sim.velocities, sim.angular_velocities,
                    np.array([[c["p_n"], c["p_t"], c["p_o"], c["p_r"], c["sigma"]]
                              for c in sim.contacts()]),
                    sim.last_report["iterations"]))
    return out


def assert_identical(a, b):
    assert len(a) == len(b)
    for step_a, step_b in zip(a, b):
        for x, y in zip(step_a, step_b):
            np.testing.assert_array_equal(x, y)


def continue_in_this_process(path, overrides, state, steps):
    """A new Simulation of the scene, set to `state` and stepped: run in another process."""
    sim = ecpsim.Simulation(ecpsim.load_scene(path, overrides))
    sim.set_state(state)
    return trajectory(sim, steps)


@pytest.mark.parametrize("name, overrides", CASES)
def test_a_pickled_state_continues_bit_for_bit(scenes, name, overrides):
    scene = ecpsim.load_scene(str(scenes / name), overrides)
    sim = ecpsim.Simulation(scene)
    sim.step(SAVE_AT)
    data = pickle.dumps(sim.get_state())
    expected = trajectory(sim, CONTINUE)

    restored = pickle.loads(data)
    assert restored.time == SAVE_AT * scene.h and restored.steps == SAVE_AT
    other = ecpsim.Simulation(scene)
    other.set_state(restored)
    assert_identical(trajectory(other, CONTINUE), expected)
    # the pickle of a restored state is the same bytes
    assert pickle.dumps(restored) == data


def test_a_state_crosses_processes(scenes):
    path, overrides = str(scenes / "push_box.yaml"), {}
    sim = ecpsim.Simulation(ecpsim.load_scene(path, overrides))
    sim.step(SAVE_AT)
    state = sim.get_state()
    expected = trajectory(sim, CONTINUE)
    # a fresh interpreter (spawn), as a Dask worker process receives it
    with concurrent.futures.ProcessPoolExecutor(
            1, mp_context=multiprocessing.get_context("spawn")) as pool:
        there = pool.submit(continue_in_this_process, path, overrides, state, CONTINUE).result()
    assert_identical(there, expected)


def test_a_pickle_of_another_form_is_an_input_error(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    sim.step(SAVE_AT)
    tag, version, text = sim.get_state().__getstate__()
    blank = ecpsim.State.__new__(ecpsim.State)
    with pytest.raises(ecpsim.InputError, match=r"State pickle 'ecpsim.State': expected "
                                                r"\('ecpsim.State', 3, record\)"):
        blank.__setstate__((tag, version + 1, text))
    with pytest.raises(ecpsim.InputError, match=r"State pickle: the record is no JSON"):
        blank.__setstate__((tag, version, text[:-1]))
    record = json.loads(text)
    record["bodies"][1]["p_WB"] = record["bodies"][1]["p_WB"][:2]
    with pytest.raises(ecpsim.InputError, match=r"state\.bodies\[1\]\.p_WB: expected a list "
                                                r"of 3 hexadecimal floats"):
        blank.__setstate__((tag, version, json.dumps(record)))
    record = json.loads(text)
    record["contacts"][0]["warm_start"]["model"] = "nosuch"
    with pytest.raises(ecpsim.InputError, match=r'state\.contacts\[0\]\.warm_start\.model = '
                                                r'"nosuch": expected "hull" or "multipatch"'):
        blank.__setstate__((tag, version, json.dumps(record)))


def test_a_warm_start_of_other_sizes_is_refused_by_set_state(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    sim.step(SAVE_AT)
    tag, version, text = sim.get_state().__getstate__()
    record = json.loads(text)
    # one multiplier of G's constraints too many: the engine would read past the ground's one
    warm = record["contacts"][0]["warm_start"]
    warm["l_g"] = warm["l_g"] + warm["l_g"][-1:]
    state = ecpsim.State.__new__(ecpsim.State)
    state.__setstate__((tag, version, json.dumps(record)))
    with pytest.raises(ecpsim.InputError, match=r"set_state: contact 0 \(box.ground\): a hull "
                                                r"warm start of \d+ multipliers for \d+ hull"):
        sim.set_state(state)
    # the simulation keeps its state
    assert sim.steps == SAVE_AT
