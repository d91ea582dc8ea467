"""Shared fixtures of the Python module's tests (run by ctest: PYTHONPATH=build/python)."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ECPSIM_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def scenes():
    """The folder of the shipped scenes."""
    return SOURCE_DIR / "scenes"


@pytest.fixture
def fixtures():
    """tests/fixtures/meshes."""
    return SOURCE_DIR / "tests" / "fixtures" / "meshes"
