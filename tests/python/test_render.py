"""render(): frames as numpy images."""

import numpy as np
import pytest

import ecpsim


def test_frame_shape_and_content(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "tbar.yaml")))
    image = sim.render(96, 64)
    assert image.shape == (64, 96, 3) and image.dtype == np.uint8
    # the T-bar, the ground and the background differ: far from one flat colour
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 10
    # the same state renders the same pixels; a camera from elsewhere renders others
    np.testing.assert_array_equal(sim.render(96, 64), image)
    side = sim.render(96, 64, camera={"position": [0, -2, 0.3], "target": [0, 0, 0], "fov": 30})
    assert not np.array_equal(side, image)
    sim.step(5)
    assert sim.render(96, 64, overlays=False).shape == (64, 96, 3)


def test_bad_arguments(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    with pytest.raises(ecpsim.InputError, match="16 … 8192"):
        sim.render(8, 64)
    with pytest.raises(ecpsim.InputError, match="camera.zoom: unknown key"):
        sim.render(32, 32, camera={"zoom": 2})
