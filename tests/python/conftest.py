"""Shared fixtures of the Python module's tests (run by ctest: PYTHONPATH=build/python)."""

import os
import pathlib
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ECPSIM_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))

# examples/ as importable modules (tests/python/test_<example>.py import them by name)
sys.path.insert(0, str(SOURCE_DIR / "examples"))


@pytest.fixture
def scenes():
    """The folder of the shipped scenes."""
    return SOURCE_DIR / "scenes"


@pytest.fixture
def fixtures():
    """tests/fixtures/meshes."""
    return SOURCE_DIR / "tests" / "fixtures" / "meshes"
