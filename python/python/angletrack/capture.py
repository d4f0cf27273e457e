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

from angletrack._angletrack import OutputFile, read_capture, write_output
from angletrack._angletrack import check_outputs as _check_outputs

__all__ = ["OutputFile", "check_outputs", "read_capture", "read_text_file", "write_capture", "write_output"]

_Path = Union[str, "os.PathLike[str]"]


def check_outputs(outputs: Mapping[str, Optional[_Path]], inputs: Mapping[str, Optional[_Path]]) -> None:
    """Refuses (``CaptureError``) an output that is one of the inputs or another output,
    however it is spelled (symbolic link, hard link, ``out/../capture.csv``), before anything
    is written. Keys are the names the user knows (``"--output"``, ``"capture"``); ``None``
    paths (an option not given) are left out.
    """
    _check_outputs({k: v for k, v in outputs.items() if v is not None},
                   {k: v for k, v in inputs.items() if v is not None})


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
