"""A sensor's calibration as a JSON file (what ``angletrack track --calibrate`` writes and
``--calibration`` reads): offsets, amplitudes and quadrature angle of
``SensorCalibration``, in the capture's units, beside what produced them. The format is the
Rust crate's (``angletrack::CalibrationFile``), which reads and writes the text; this module
reads and writes the files.

The file is one JSON object::

    {"format": "angletrack-sensor-calibration", "version": 1,
     "calibration": {"offset_c": ..., "offset_s": ..., "amplitude_c": ...,
                     "amplitude_s": ..., "quadrature_rad": ...},
     "turns_learned": 42, "source": "capture.csv"}

Only ``calibration`` is needed to read it back; the other keys say where it came from.
"""

from __future__ import annotations

import pathlib
from typing import TYPE_CHECKING, Any, Optional, Union

from angletrack import SensorCalibration, _angletrack
from angletrack import capture as capture_io

if TYPE_CHECKING:
    from angletrack import harmonics

#: The ``format`` of the file :func:`to_json` writes (the Rust crate's
#: ``SensorCalibrationRecord``).
FORMAT = _angletrack.SENSOR_CALIBRATION_FORMAT


def to_json(calibration: SensorCalibration, *, turns_learned: Optional[int] = None,
            source: Optional[str] = None) -> str:
    """The calibration as the JSON text of this module's format, with ``turns_learned`` and
    ``source`` beside it when given."""
    return _angletrack.sensor_calibration_to_json(calibration, turns_learned=turns_learned, source=source)


def from_json(text: str, file: str = "calibration") -> SensorCalibration:
    """The calibration of JSON text of this module's format (or a bare object of the five
    fields); ``ValueError`` naming ``file`` and the field missing or refused."""
    return _angletrack.sensor_calibration_from_json(text, file)


def write(path: pathlib.Path, calibration: SensorCalibration, *, turns_learned: Optional[int] = None,
          source: Optional[str] = None) -> None:
    """Writes ``calibration`` (with ``turns_learned`` and ``source``) to ``path`` as JSON, all
    or nothing."""
    _angletrack.write_output(path, to_json(calibration, turns_learned=turns_learned, source=source))


def read(path: pathlib.Path) -> SensorCalibration:
    """Reads a calibration written by ``write`` (or by hand: the five fields)."""
    return from_json(pathlib.Path(path).read_text(), str(path))


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
    text = capture_io.read_text_file(path, "--calibration")
    stored = _angletrack.calibration_from_json(text, str(path))
    return stored if isinstance(stored, SensorCalibration) else harmonics.Calibration.from_learned(stored)


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


#: Why a calibrator in each ``calibration_status`` learned nothing.
_NOTHING_LEARNED = {
    "finding-centre": "the channels' centres were not found (the rotor turned less than a whole turn, "
                      "or stood still), so the angle of biased signals is wrong",
    "centred": "no whole turn at a steady speed above the minimum speed",
    "stalled": "the observer was not locked on the corrected signals (phase error within 0.29) over a "
               "whole turn at a steady speed",
}


def check_learned(observer: Any) -> None:
    """``ValueError`` (one line, naming ``--calibrate``) when ``observer``'s online calibration
    learned no turn, the status saying why: checked before the estimates are finalised, so
    that such a run leaves neither a calibration nor estimates."""
    turns, status = observer.calibration_turns_learned, observer.calibration_status
    if turns == 0:
        raise ValueError(f"calibration: --calibrate learned 0 turns (status {status}): "
                         f"{_NOTHING_LEARNED[status]}; no calibration written")


def write_learned(capture: pathlib.Path, output: Optional[pathlib.Path], observer: Any) -> str:
    """Writes what ``observer`` learned beside the estimates of ``capture`` (or to
    ``output``) and returns the line that says so. ``ValueError`` (one line, naming
    ``--calibrate``) when it learned no turn: nothing is written, and the status says why."""
    path = default_path(capture, output)
    check_learned(observer)
    learned = observer.calibration
    turns, status = observer.calibration_turns_learned, observer.calibration_status
    write(path, learned, turns_learned=turns, source=str(capture))
    stalled = ("; status stalled: no turn learned over the last 16 turns at speed"
               if status == "stalled" else "")
    return (
        f"calibration learned over {turns} turns -> {path}: offsets "
        f"{learned.offset_c:.6g}, {learned.offset_s:.6g}; amplitudes {learned.amplitude_c:.6g}, "
        f"{learned.amplitude_s:.6g}; quadrature {learned.quadrature_rad:.6g} rad{stalled}"
    )
