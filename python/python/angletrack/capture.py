"""Captures: reading any capture is the extension's (:func:`angletrack.read_capture`,
:class:`angletrack.CaptureReader`, parsed in Rust); this module writes small captures as CSV
for examples and tests, holds the rule that no output replaces an input
(:func:`check_outputs`, the Rust crate's ``angletrack::capture::check_outputs``), and reads
the small text files a run takes beside its capture (:func:`read_text_file`).
"""

from __future__ import annotations

import os
import pathlib
from typing import Mapping, Optional, Union

import numpy as np

from angletrack._angletrack import Estimates, OutputFile, TableWriter, estimate_columns, read_capture, write_output
from angletrack._angletrack import check_outputs as _check_outputs

__all__ = ["EstimatesWriter", "OutputFile", "check_outputs", "read_capture", "read_text_file", "write_capture",
           "write_output"]

_Path = Union[str, "os.PathLike[str]"]


def check_outputs(outputs: Mapping[str, Optional[_Path]], inputs: Mapping[str, Optional[_Path]]) -> None:
    """Refuses (``CaptureError``) an output that is one of the inputs or another output,
    however it is spelled (symbolic link, hard link, ``out/../capture.csv``), before anything
    is written. Keys are the names the user knows (``"--output"``, ``"capture"``); ``None``
    paths (an option not given) are left out.
    """
    _check_outputs({k: v for k, v in outputs.items() if v is not None},
                   {k: v for k, v in inputs.items() if v is not None})


class EstimatesWriter:
    """Writes estimates chunk by chunk in constant memory: ``.npy`` (a structured array with
    fields ``time_s``, ``angle_rad``, ``position_rad``, ``speed_rad_s``,
    ``acceleration_rad_s2``, ``phase_error``, ``faults``) for a path ending in ``.npy``,
    ``.npz`` (one array per field) for ``.npz``, CSV with a header line of those names for
    ``.csv`` (each number the shortest decimal that reads back to the same float of its
    type); another extension is refused. ``dtype`` is the observer's (float32 or float64).
    The rows go to a temporary file beside ``path``, renamed to it by ``close()`` (or at the
    end of a ``with`` block; after an exception in the block the file is discarded and
    ``path`` left as it was). A :class:`TableWriter` of the crate's estimate columns
    (``estimate_columns``)."""

    def __init__(self, path: _Path, *, dtype: object = None) -> None:
        self._table = TableWriter(path, estimate_columns(dtype))

    def write(self, time_s: np.ndarray, estimates: Estimates) -> None:
        """Appends the estimates of a chunk, with their time stamps ``time_s`` (float64 array
        of the same length)."""
        e = estimates
        self._table.write([time_s, e.angle, e.position, e.speed, e.acceleration, e.phase_error, e.faults])

    def close(self) -> int:
        """Finishes the file; returns the number of rows written (0 if already closed)."""
        return self._table.close()

    def __enter__(self) -> "EstimatesWriter":
        return self

    def __exit__(self, exc_type: object, exc_value: object, traceback: object) -> bool:
        return self._table.__exit__(exc_type, exc_value, traceback)


def read_text_file(path: _Path, option: str) -> str:
    """The text of a gains or calibration file given by ``option`` (``"--gains-file"``): UTF-8,
    with or without a byte-order mark. A file that cannot be read, or is not UTF-8, is a
    ``ValueError`` naming the option and the file."""
    try:
        data = pathlib.Path(path).read_bytes()
    except OSError as e:
        raise ValueError(f"{option}: {path}: {e.strerror or e}") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise ValueError(f"{option}: {path}: not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start}); "
                         "save it as UTF-8") from None


def write_capture(path: str | pathlib.Path, columns: dict[str, np.ndarray]) -> None:
    """Writes equal-length columns as a comma-separated file with a header line, each number
    the shortest decimal that reads back to the same float64."""
    names = list(columns)
    data = [np.asarray(columns[n], dtype=np.float64) for n in names]
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for row in zip(*(c.tolist() for c in data)):
            f.write(",".join(map(repr, row)) + "\n")
