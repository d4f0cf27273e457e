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
from typing import TYPE_CHECKING, Any, Optional, Union

from angletrack import SensorCalibration

if TYPE_CHECKING:
    from angletrack import harmonics

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


def read_stored(path: Optional[pathlib.Path]) -> Union[None, SensorCalibration, "harmonics.Calibration"]:
    """The calibration in the file ``--calibration FILE``, read once; its type says its kind:
    a ``harmonics.Calibration`` for an angle calibration written by ``angletrack calibrate``
    (the sensor's offsets, imbalance and quadrature with its angle-dependent error), else the
    ``SensorCalibration`` that ``track --calibrate`` writes (``None`` for ``None``)."""
    from angletrack import harmonics

    if path is None:
        return None
    text = pathlib.Path(path).read_text(encoding="utf-8")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError:
        doc = None
    if isinstance(doc, dict) and doc.get("format") == harmonics.JSON_FORMAT:
        return harmonics.Calibration.from_json(text)
    return from_json(text)


def observer_arguments(calibrate: bool, stored: Union[None, SensorCalibration, "harmonics.Calibration"]) -> dict:
    """The ``Observer`` arguments of ``--calibrate`` (learn while tracking, from the stored
    calibration if one is given) and ``--calibration FILE`` (apply ``stored``, what
    :func:`read_stored` read from it, frozen). An angle calibration from ``angletrack
    calibrate`` goes to the calibrated observer instead: no arguments, and ``--calibrate`` is
    refused with it (that calibration already holds the offsets, imbalance and quadrature;
    learning them again would leave its harmonics fitted to other ones)."""
    if stored is not None and not isinstance(stored, SensorCalibration):
        if calibrate:
            raise ValueError("calibration: --calibrate learns offsets, imbalance and quadrature; an angle "
                             "calibration from `angletrack calibrate` already holds them")
        return {}
    if calibrate:
        return {"calibration": "learn", "initial_calibration": stored}
    if stored is not None:
        return {"calibration": "frozen", "initial_calibration": stored}
    return {}


def angle_calibration(stored: Union[None, SensorCalibration, "harmonics.Calibration"]) -> Optional["harmonics.Calibration"]:
    """``stored`` if it is an angle calibration from ``angletrack calibrate``, else ``None``."""
    return None if stored is None or isinstance(stored, SensorCalibration) else stored


def write_learned(capture: pathlib.Path, output: Optional[pathlib.Path], observer: Any) -> str:
    """Writes what ``observer`` learned beside the estimates of ``capture`` (or to
    ``output``) and returns the line that says so."""
    path = default_path(capture, output)
    learned = observer.calibration
    write(path, learned, turns_learned=observer.calibration_turns_learned, source=str(capture))
    return (
        f"calibration learned over {observer.calibration_turns_learned} turns -> {path}: offsets "
        f"{learned.offset_c:.6g}, {learned.offset_s:.6g}; amplitudes {learned.amplitude_c:.6g}, "
        f"{learned.amplitude_s:.6g}; quadrature {learned.quadrature_rad:.6g} rad"
    )
