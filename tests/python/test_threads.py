"""Separate Simulations in several threads (step() releases the GIL) give the results of one
thread, also for scenes whose muparser load expressions the copies share."""

import threading

import numpy as np
import pytest

import ecpsim

THREADS = 4
STEPS = 30


def run_in_threads(scene):
    sims = [ecpsim.Simulation(scene) for _ in range(THREADS)]
    errors = []

    def work(sim):
        try:
            for _ in range(STEPS):
                sim.step()
        except Exception as e:  # reported below, with the thread's error
            errors.append(e)

    threads = [threading.Thread(target=work, args=(sim,)) for sim in sims]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    return sims


def test_threads_match_one_thread(scenes):
    # the desk: loads as expressions of t; the T-bar: several contacts
    for name in ("desk.yaml", "tbar.yaml"):
        scene = ecpsim.load_scene(str(scenes / name))
        alone = ecpsim.Simulation(scene)
        alone.step(STEPS)
        for sim in run_in_threads(scene):
            np.testing.assert_array_equal(sim.positions, alone.positions, err_msg=name)
            np.testing.assert_array_equal(sim.quaternions, alone.quaternions, err_msg=name)


def test_one_simulation_shared_by_threads_steps_one_at_a_time(scenes):
    # a Simulation is locked while it steps: two threads sharing one take all their steps
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    threads = [threading.Thread(target=lambda: [sim.step() for _ in range(10)]) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sim.steps == 20


def test_islands_on_threads_match_one_thread(scenes):
    # the dominoes: nine blocks, each an island until the one before it falls on it; solved on
    # one, two and three threads (a third thread waits its turn for one of the two cores)
    scene = ecpsim.load_scene(str(scenes / "dominoes.yaml"))
    sims = [ecpsim.Simulation(scene, threads=n) for n in (1, 2, 3)]
    for sim, n in zip(sims, (1, 2, 3)):
        assert sim.threads == n
        sim.step(STEPS)
    for sim in sims[1:]:
        np.testing.assert_array_equal(sim.positions, sims[0].positions)
        np.testing.assert_array_equal(sim.quaternions, sims[0].quaternions)
        np.testing.assert_array_equal(sim.get_state().velocities, sims[0].get_state().velocities)
    # changed between steps, as ever the same steps
    sims[0].threads = 2
    sims[1].threads = 1
    sims[0].step(5)
    sims[1].step(5)
    np.testing.assert_array_equal(sims[0].positions, sims[1].positions)


def test_threads_below_one_are_refused(scenes):
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"))
    with pytest.raises(ecpsim.InputError, match="threads = 0: expected"):
        ecpsim.Simulation(scene, threads=0)
    sim = ecpsim.Simulation(scene)
    with pytest.raises(ecpsim.InputError, match="threads = -2"):
        sim.threads = -2
    assert sim.threads == 1
