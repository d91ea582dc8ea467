"""Atomic outputs of the examples: a file is written under a temporary name in its own folder and
renamed over the target, so a reader (or an interrupted run) sees the old file or the new one,
never half of one."""

import os
import pathlib
import tempfile


def write_atomically(path, write):
    """Calls write(file) on a new binary file beside `path`, then renames it to `path`.

    The temporary file is removed if write raises; the exception propagates."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(handle, 0o644)  # mkstemp's 0600 would survive the rename
        with os.fdopen(handle, "wb") as file:
            write(file)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise
    return path


def write_bytes_atomically(path, data):
    """`data` (bytes) into `path`, atomically."""
    return write_atomically(path, lambda file: file.write(data))


def save_figure_atomically(figure, path):
    """A matplotlib Figure as a PNG at `path`, atomically (the format named, since the temporary
    name has no .png)."""
    return write_atomically(path, lambda file: figure.savefig(file, format="png", dpi=110))
