"""Reading and writing captures as CSV files (the ``track`` command's input and output).

A capture has a header line and one row per sample. Required columns: ``y_c`` and ``y_s``
(the demodulated cosine and sine signals). Optional: ``time`` (or ``t``, seconds) and a
reference angle ``reference`` (or ``theta``, ``angle``; rad, unwrapped or wrapped).
"""

from __future__ import annotations

import dataclasses
import pathlib
from typing import Optional

import numpy as np

TIME_COLUMNS = ("time", "t", "time_s")
REFERENCE_COLUMNS = ("reference", "theta", "angle", "angle_rad", "reference_rad")


@dataclasses.dataclass
class Capture:
    """Samples of a capture, as float64 arrays of one length."""

    y_c: np.ndarray
    y_s: np.ndarray
    time_s: Optional[np.ndarray] = None
    reference_rad: Optional[np.ndarray] = None

    def sample_period_from_time(self) -> Optional[float]:
        """The mean step of the evenly spaced time column (s), or ``None`` without one."""
        if self.time_s is None or len(self.time_s) < 2:
            return None
        t = self.time_s
        step = float(t[-1] - t[0]) / (len(t) - 1)
        if not step > 0.0:
            raise ValueError("time: the time column must increase")
        if np.max(np.abs(np.diff(t) - step)) > 0.01 * step:
            raise ValueError("time: the samples are not evenly spaced (1 % tolerance)")
        return step


def _column(names: list[str], wanted: tuple[str, ...]) -> Optional[int]:
    for i, name in enumerate(names):
        if name in wanted:
            return i
    return None


def read_capture(path: str | pathlib.Path) -> Capture:
    """Reads a CSV capture; raises ``ValueError`` naming what is missing or malformed."""
    path = pathlib.Path(path)
    with path.open() as f:
        header = f.readline()
    names = [n.strip().lower() for n in header.strip().split(",")]
    if "y_c" not in names or "y_s" not in names:
        raise ValueError(f"{path}: the header must name columns y_c and y_s, got {header.strip()!r}")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, dtype=np.float64)
    except ValueError as e:
        raise ValueError(f"{path}: not a CSV of numbers after the header ({e})") from None
    if data.shape[0] == 0:
        raise ValueError(f"{path}: no samples after the header")
    if data.shape[1] != len(names):
        raise ValueError(f"{path}: {data.shape[1]} columns of numbers but {len(names)} names in the header")

    def col(i: Optional[int]) -> Optional[np.ndarray]:
        return None if i is None else np.ascontiguousarray(data[:, i])

    return Capture(
        y_c=col(names.index("y_c")),
        y_s=col(names.index("y_s")),
        time_s=col(_column(names, TIME_COLUMNS)),
        reference_rad=col(_column(names, REFERENCE_COLUMNS)),
    )


def write_capture(path: str | pathlib.Path, columns: dict[str, np.ndarray]) -> None:
    """Writes equal-length columns as a CSV file with a header line (full float precision)."""
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=np.float64) for n in names])
    np.savetxt(path, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
