"""hull(): mass properties and half-spaces of a mesh against the closed forms of a box."""

import numpy as np
import pytest

import ecpsim

# relative: CGAL's exact hull and the mass integrals of a box are exact up to round-off
REL_TOL = 1e-12


def test_box_mesh(fixtures):
    # tests/fixtures/meshes/box.obj: [0, 1] × [0, 2] × [0, 3] m
    result = ecpsim.hull(str(fixtures / "box.obj"))
    a, b, c = 1.0, 2.0, 3.0
    assert result["volume"] == pytest.approx(a * b * c, rel=REL_TOL)
    m = 1000 * a * b * c  # kg at the default density, 1000 kg/m³
    assert result["mass"] == pytest.approx(m, rel=REL_TOL)
    np.testing.assert_allclose(result["center_of_mass"], [a / 2, b / 2, c / 2], rtol=REL_TOL)
    expected_inertia = np.diag([m * (b**2 + c**2), m * (a**2 + c**2), m * (a**2 + b**2)]) / 12
    np.testing.assert_allclose(result["inertia"], expected_inertia, rtol=REL_TOL, atol=REL_TOL * m)
    # the hull in the CM frame: six faces ±e_i · y ≤ half extent
    A, offsets = result["A"], result["b"]
    assert A.shape == (6, 3) and offsets.shape == (6,)
    for axis, half in enumerate([a / 2, b / 2, c / 2]):
        for sign in (1, -1):
            row = np.flatnonzero(np.isclose(A[:, axis], sign, rtol=0, atol=REL_TOL))
            assert len(row) == 1
            assert offsets[row[0]] == pytest.approx(half, rel=REL_TOL)
    assert result["vertices"].shape == (8, 3)
    assert result["closed"] and result["oriented"] and result["mass_source"] == "mesh"


def test_scale_and_mass(fixtures):
    result = ecpsim.hull(str(fixtures / "box.obj"), units="cm", mass=2.0)
    assert result["scale"] == 0.01
    assert result["volume"] == pytest.approx(6e-6, rel=REL_TOL)
    assert result["mass"] == pytest.approx(2.0, rel=REL_TOL)
    assert result["warnings"] == []  # 3.7 cm across: a plausible size
    # 374 m across: the size warning of the CLI
    large = ecpsim.hull(str(fixtures / "box.obj"), scale=100)
    assert any("across" in w for w in large["warnings"])


def test_open_mesh_uses_its_hull(fixtures):
    result = ecpsim.hull(str(fixtures / "open_box.obj"))
    assert result["mass_source"] == "convex hull (mesh is open)"
    assert any("boundary edges" in w for w in result["warnings"])


def test_errors(fixtures):
    with pytest.raises(ecpsim.InputError, match="coplanar"):
        ecpsim.hull(str(fixtures / "flat_tetrahedron.obj"))
    with pytest.raises(ecpsim.InputError, match="mass = 1 and density = 2"):
        ecpsim.hull(str(fixtures / "box.obj"), mass=1, density=2)
    with pytest.raises(ecpsim.InputError, match="units"):
        ecpsim.hull(str(fixtures / "box.obj"), units="furlong")
