"""The Python examples of docs/python.md and README.md run as written (from the repository root,
where ctest runs them)."""

import os
import re

import pytest

from conftest import SOURCE_DIR


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", (SOURCE_DIR / path).read_text(), re.S)


@pytest.mark.parametrize("path", ["docs/python.md", "README.md"])
def test_examples_run(path, capsys):
    blocks = python_blocks(path)
    assert blocks, f"{path}: no ```python block"
    os.chdir(SOURCE_DIR)
    for block in blocks:
        exec(compile(block, path, "exec"), {})
    # the docs' example prints where the box stopped: within μ m g / kp of the goal
    if path == "docs/python.md":
        x = float(re.search(r"x = ([0-9.]+) m", capsys.readouterr().out).group(1))
        assert abs(x - 0.3) <= 0.22 * 15 * 9.8 / 400.0
