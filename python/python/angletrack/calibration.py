"""A sensor's calibration as a JSON file (what ``angletrack track --calibrate`` writes and
``--calibration`` reads): offsets, amplitudes and quadrature angle of
``SensorCalibration``, in the capture's units, beside what produced them.

The file is one JSON object::

    {"format": "angletrack-sensor-calibration", "version": 1,
     "calibration": {"offset_c": ..., "offset_s": ..., "amplitude_c": ...,
                     "amplitude_s": ..., "quadrature_rad": ...},
     "turns_learned": 42, "source": "capture.csv"}

Only ``calibration`` is needed to read it back; the other keys say where it came from.
"""

from __future__ import annotations

import json
import pathlib
from typing import Any, Optional

from angletrack import SensorCalibration

FORMAT = "angletrack-sensor-calibration"
VERSION = 1


def to_json(calibration: SensorCalibration, **metadata: Any) -> str:
    """The calibration as the JSON text of this module's format, with ``metadata`` keys
    (``turns_learned``, ``source``) beside it."""
    doc = {"format": FORMAT, "version": VERSION, "calibration": calibration.to_dict(), **metadata}
    return json.dumps(doc, indent=2) + "\n"


def from_json(text: str) -> SensorCalibration:
    """The calibration of JSON text of this module's format (or a bare object of the five
    fields); ``ValueError`` naming what is missing or refused."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise ValueError(f"calibration: not JSON ({e})") from None
    if not isinstance(doc, dict):
        raise ValueError("calibration: expected a JSON object")
    fields = doc.get("calibration", doc)
    if not isinstance(fields, dict):
        raise ValueError("calibration: the 'calibration' key must hold an object")
    return SensorCalibration.from_dict(fields)


def write(path: pathlib.Path, calibration: SensorCalibration, **metadata: Any) -> None:
    """Writes ``calibration`` (and ``metadata``) to ``path`` as JSON."""
    pathlib.Path(path).write_text(to_json(calibration, **metadata))


def read(path: pathlib.Path) -> SensorCalibration:
    """Reads a calibration written by ``write`` (or by hand: the five fields)."""
    return from_json(pathlib.Path(path).read_text())


def default_path(capture: pathlib.Path, output: Optional[pathlib.Path] = None) -> pathlib.Path:
    """Where ``--calibrate`` writes without ``--calibration-out``: ``CAPTURE_calibration.json``
    beside the capture."""
    return output or capture.with_name(capture.stem + "_calibration.json")
