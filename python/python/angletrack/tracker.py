"""Tracker files: one JSON document of a whole sensor setup (``docs/guide/tracker-file.md``),
what ``angletrack track --tracker`` runs and ``angletrack calibrate --tracker`` completes.

The format is the Rust crate's (``angletrack::tracker_file``), which reads, checks and
writes the text; a :class:`Tracker` holds the document as a dict (``document``) and turns
it into what the track code paths take (:meth:`Tracker.track_settings`).

>>> import numpy as np, angletrack
>>> tracker = angletrack.Tracker({"format": "angletrack-tracker", "version": 1,
...                               "sample_period_s": 1e-4, "gains": [0.06, 0.001]})
>>> theta = np.linspace(0.0, 20.0, 10_000)
>>> round(float(tracker.track(np.cos(theta), np.sin(theta)).position[-1]), 3)
20.0
"""

from __future__ import annotations

import json
import pathlib
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy as np

from angletrack import _angletrack
from angletrack._angletrack import FaultThresholds, Gains, SensorCalibration

if TYPE_CHECKING:
    from angletrack import tracker_run

#: The ``format`` of a tracker file.
FORMAT = _angletrack.TRACKER_FILE_FORMAT
#: The ``version`` written, and the only one read.
VERSION = _angletrack.TRACKER_FILE_VERSION

#: The number types of the file as ``angletrack track --dtype`` names them.
DTYPES = {"f32": "float32", "f64": "float64", "fixed": "fixed"}

#: The sensor calibration's fields, in ``SensorCalibration``'s order.
SENSOR_FIELDS = ("offset_c", "offset_s", "amplitude_c", "amplitude_s", "quadrature_rad")


def _sensor(fields: dict) -> SensorCalibration:
    return SensorCalibration(*(fields[name] for name in SENSOR_FIELDS))


def _default_online_settings() -> dict:
    """The online calibration's default settings, as the crate writes them."""
    text = _angletrack.checked_tracker_file(json.dumps({
        "format": FORMAT, "version": VERSION, "sample_period_s": 1e-4, "gains": [0.06, 0.001],
        "calibration": {"kind": "online"}}), "defaults")
    return json.loads(text)["calibration"]


class Tracker:
    """A tracker file's setup, checked by the Rust crate (``ValueError`` naming ``file``
    and the field as written). ``document`` is the file as a dict, every setting present."""

    def __init__(self, document: dict, file: str = "tracker"):
        self._read(json.dumps(document), file)

    def _read(self, text: str, file: str) -> None:
        self.file = file
        self.document: dict = json.loads(_angletrack.checked_tracker_file(text, file))
        #: The observer of the last :meth:`track`, at its end (``None`` before).
        self.observer: Any = None

    @classmethod
    def from_json(cls, text: str, file: str = "tracker") -> "Tracker":
        """The tracker of JSON ``text`` (``file`` names it in errors)."""
        tracker = cls.__new__(cls)
        tracker._read(text, file)
        return tracker

    @classmethod
    def from_file(cls, path: Union[str, pathlib.Path]) -> "Tracker":
        """Reads the tracker file at ``path``."""
        return cls.from_json(pathlib.Path(path).read_text(), str(path))

    @classmethod
    def from_files(cls, gains_file: Union[str, pathlib.Path],
                   calibration_file: Union[None, str, pathlib.Path] = None, **settings: Any) -> "Tracker":
        """The tracker of a gains file (``angletrack design --format json``) and a
        calibration file of either kind, if given (:meth:`with_calibration`), with
        ``settings`` (top-level fields of the tracker file, e.g. ``number_type="f32"``)
        replacing the defaults."""
        tracker = cls.from_gains_json(pathlib.Path(gains_file).read_text(), str(gains_file)).replaced(**settings)
        if calibration_file is not None:
            tracker = tracker.with_calibration(pathlib.Path(calibration_file).read_text(), str(calibration_file))
        return tracker

    @classmethod
    def from_gains_json(cls, text: str, file: str = "gains file") -> "Tracker":
        """The tracker of a gains file's JSON ``text`` (``file`` names it in errors), the other
        settings at their defaults: ``f64``, samples in units, the ADC range measured, no
        calibration or correction."""
        return cls.from_json(_angletrack.tracker_file_from_gains(text, file), file)

    def with_calibration(self, text: str, file: str = "calibration") -> "Tracker":
        """The same setup with the calibration of the calibration file's JSON ``text``
        (either kind; ``file`` names it in errors) in place of its own: stored, and an
        angle calibration's harmonics as the correction."""
        return Tracker.from_json(_angletrack.tracker_file_with_calibration(self.to_json(), self.file, text, file),
                                 self.file)

    def to_json(self) -> str:
        """The file's JSON text, as the crate writes it."""
        return _angletrack.checked_tracker_file(json.dumps(self.document), self.file)

    def firmware_constants(self, language: str = "c", *, name: str = "angletrack") -> str:
        """The setup's firmware constants (``language`` ``"c"`` or ``"rust"``): the gains in
        the number type (or the fixed-point constants) and a stored calibration with its
        harmonics, every identifier prefixed by ``name``."""
        return _angletrack.tracker_firmware_constants(self.to_json(), self.file, language, name)

    def write(self, path: Union[str, pathlib.Path]) -> None:
        """Writes the file to ``path``, all or nothing."""
        _angletrack.write_output(pathlib.Path(path), self.to_json())

    def replaced(self, **fields: Any) -> "Tracker":
        """The same setup with top-level ``fields`` replaced (checked again)."""
        return Tracker({**self.document, **fields}, self.file)

    @property
    def gains(self) -> Gains:
        """The gains at their sample period."""
        return Gains(self.document["gains"], sample_period_s=self.document["sample_period_s"])

    @property
    def dtype(self) -> str:
        """The number type as ``--dtype`` names it."""
        return DTYPES[self.document["number_type"]]

    @property
    def adc_range(self) -> Optional[tuple[float, float]]:
        """The ADC range in the samples' units (``None``: measured)."""
        rule = self.document["adc_range"]
        if rule["rule"] == "stated":
            return float(rule["min"]), float(rule["max"])
        if rule["rule"] == "full_scale":
            bits, signed = self.document["input"]["bits"], self.document["input"]["signed"]
            return (-(2.0 ** (bits - 1)), 2.0 ** (bits - 1) - 1.0) if signed else (0.0, 2.0**bits - 1.0)
        return None

    @property
    def mid_scale(self) -> Optional[float]:
        """The mid-scale removed from the samples (``None``: measured on the capture's
        first samples, the ``track`` rule for counts)."""
        source = self.document["input"]
        if source["kind"] == "units":
            return 0.0
        if "bits" in source:
            return 0.0 if source["signed"] else 2.0 ** (source["bits"] - 1)
        return float(source["mid_scale"]) if "mid_scale" in source else None

    @property
    def counts_per_unit(self) -> float:
        """What the samples are divided by after the mid-scale (1: counts tracked as such)."""
        return float(self.document["input"].get("counts_per_unit", 1.0))

    def _refuse(self, field: str, why: str) -> None:
        raise ValueError(f"{self.file}: {field}: {why}")

    def calibration_arguments(self, strict: bool = True) -> tuple[dict, Optional[Any]]:
        """The ``Observer`` arguments of the calibration (``calibration``,
        ``initial_calibration``) and the angle calibration (a ``harmonics.Calibration``,
        ``None`` without harmonics), as the observers of ``calibrate`` and of the resolver
        path take them; ``strict``: refuse what those observers cannot run (a table, harmonics
        without a stored calibration, an online calibration's own settings), which the
        tracker file's chain (``track``, :meth:`track`) runs."""
        from angletrack import harmonics

        calibration, correction = self.document["calibration"], self.document["correction"]
        if not strict and (correction["kind"] == "table"
                           or (correction["kind"] == "harmonics" and calibration["kind"] != "stored")):
            correction = {"kind": "none"}
        if correction["kind"] == "table":
            self._refuse("correction.kind", '"table" is a firmware\'s (AngleCorrectionTable); the Python package '
                         'applies "harmonics"')
        if correction["kind"] == "harmonics":
            if calibration["kind"] != "stored":
                self._refuse("correction.kind", '"harmonics" are applied after a stored sensor calibration: '
                             'give calibration.kind "stored" (angletrack calibrate --tracker writes both)')
            sensor = tuple(calibration["sensor"][name] for name in SENSOR_FIELDS)
            return {}, harmonics.Calibration(sensor=sensor, cos=tuple(correction["cos"]), sin=tuple(correction["sin"]))
        if calibration["kind"] == "stored":
            return {"calibration": "frozen", "initial_calibration": _sensor(calibration["sensor"])}, None
        if calibration["kind"] == "online":
            defaults = _default_online_settings()
            for name, value in calibration.items():
                if strict and name not in ("kind", "initial") and value != defaults[name]:
                    self._refuse(f"calibration.{name}", f"{value}: the Python package's online calibration runs with "
                                 f"the default settings ({defaults[name]}); a firmware takes others")
            initial = calibration["initial"]
            return {"calibration": "learn", "initial_calibration": None if initial is None else _sensor(initial)}, None
        return {}, None

    def front_end_arguments(self) -> dict:
        """The ``Observer`` arguments of the fault thresholds and the winding check."""
        out: dict = {}
        thresholds = self.document["fault_thresholds"]
        if thresholds is not None:
            # The package's Observer has no roundness check (its FaultThresholds has no field
            # for it); the crate's chain of the file (``track``) runs it.
            fields = {name: value for name, value in thresholds.items() if name != "magnitude_tolerance"}
            out["fault_thresholds"] = FaultThresholds(**fields)
        if self.document["winding_check"] is not None:
            out["winding_amplitude"] = float(self.document["winding_check"]["amplitude"])
        return out

    def track_settings(self, strict: bool = True) -> dict:
        """The :class:`angletrack.tracking.TrackSettings` fields of the setup: what
        ``track`` and ``calibrate`` run it with; ``strict``: as for
        :meth:`calibration_arguments`, and thresholds or a winding check beside harmonics or
        fixed point refused."""
        observer_arguments, calibration = self.calibration_arguments(strict)
        front_end = self.front_end_arguments()
        if strict and front_end and (calibration is not None or self.dtype == "fixed"):
            field = "fault_thresholds" if "fault_thresholds" in front_end else "winding_check"
            why = "the harmonics' corrected observer" if calibration is not None else 'number_type "fixed"'
            self._refuse(field, f"not run by the Python package with {why} (its thresholds are scaled to the "
                         "signal); leave it null")
        if strict and self.dtype == "fixed" and self.counts_per_unit != 1.0:
            self._refuse("input.counts_per_unit", 'number_type "fixed" shifts the counts itself: give 1')
        return dict(
            tracker_gains=self.gains, dtype=self.dtype, sin_cos=self.document["sin_cos"],
            observer_arguments={**observer_arguments, **front_end}, calibration=calibration,
            adc_range=self.adc_range, mid_scale=self.mid_scale, counts_per_unit=self.counts_per_unit,
            pole_pairs=self.document["pole_pairs"], tracker_document=self.document, tracker_file=self.file,
        )

    def track(self, y_c: Any, y_s: Any) -> "tracker_run.TrackedRows":
        """The estimates of the samples ``(y_c, y_s)`` (1-D arrays of one capture), as
        ``angletrack track --tracker`` computes them over a capture of those samples: the
        crate's chain of this file (``angletrack::tracker_file::TrackerRun``); the chain at
        the end is ``self.observer`` (its faults latched, what an online calibration
        learned)."""
        from angletrack import tracker_run, tracking

        y_c, y_s = np.asarray(y_c), np.asarray(y_s)
        settings = tracking.TrackSettings(capture=pathlib.Path(self.file), output=pathlib.Path(self.file),
                                          **self.track_settings(strict=False))
        integer = y_c.dtype.kind in "iu"
        mid = tracking._mid_scale(settings, y_c.dtype.name, (y_c, y_s)) if integer else 0.0
        self.observer = tracker_run.Run(settings, self.gains, y_c.dtype.name, tracker_run.Samples(y_c, y_s), mid)
        return tracker_run.TrackedRows(self.observer.track(y_c, y_s), self.dtype)

    def __repr__(self) -> str:
        d = self.document
        return (f"Tracker({self.file!r}: order {len(d['gains'])} at {1.0 / d['sample_period_s']:.6g} Hz, "
                f"{d['number_type']}, input {d['input']['kind']}, calibration {d['calibration']['kind']}, "
                f"correction {d['correction']['kind']})")

