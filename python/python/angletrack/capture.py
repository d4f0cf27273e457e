"""Captures: reading any capture is the extension's (:func:`angletrack.read_capture`,
:class:`angletrack.CaptureReader`, parsed in Rust); this module writes small captures as CSV
for examples and tests.
"""

from __future__ import annotations

import pathlib

import numpy as np

from angletrack._angletrack import read_capture

__all__ = ["read_capture", "write_capture"]


def write_capture(path: str | pathlib.Path, columns: dict[str, np.ndarray]) -> None:
    """Writes equal-length columns as a comma-separated file with a header line, each number
    the shortest decimal that reads back to the same float64."""
    names = list(columns)
    data = [np.asarray(columns[n], dtype=np.float64) for n in names]
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for row in zip(*(c.tolist() for c in data)):
            f.write(",".join(map(repr, row)) + "\n")
