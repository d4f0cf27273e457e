"""The chain ``angletrack track`` runs: the tracker file its options describe (``--tracker``,
or the flags, gains and calibration file written as one), run by the Rust crate's
``TrackerRun``, which builds the core's ``Tracker`` once by the rules of the firmware's
export. This module only turns the options into that document and moves the capture's
chunks through it; the mid-scale, the rails, the thresholds, the fixed-point shift and the
stages are the crate's.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Optional

import numpy as np

import angletrack
from angletrack import _angletrack, harmonics
from angletrack._angletrack import TRACKER_FILE_FORMAT, TRACKER_FILE_VERSION

if TYPE_CHECKING:
    from angletrack.tracking import TrackSettings

#: The tracker file's number type of each ``--dtype``.
NUMBER_TYPES = {"float32": "f32", "float64": "f64", "fixed": "fixed"}

#: The fault thresholds' fields, as the tracker file and ``FaultThresholds`` name them.
THRESHOLD_FIELDS = ("nominal_amplitude", "max_input_amplitude", "loss_of_signal", "degradation_low",
                    "degradation_high", "loss_of_tracking", "tracking_error", "max_speed_rad_s", "filter_factor", "false_lock",
                    "monitor", "re_acquire")

#: The sensor calibration's fields, in ``SensorCalibration``'s order.
SENSOR_FIELDS = ("offset_c", "offset_s", "amplitude_c", "amplitude_s", "quadrature_rad")


def _sensor(values) -> dict:
    return dict(zip(SENSOR_FIELDS, (float(v) for v in values)))


def _calibration(s: "TrackSettings") -> tuple[dict, dict]:
    """The ``calibration`` and ``correction`` of the options: ``--calibrate`` (online, from a
    stored calibration if one is given), ``--calibration`` (stored; an angle calibration's
    harmonics as the correction)."""
    arguments = s.observer_arguments
    initial = arguments.get("initial_calibration")
    if s.calibration is not None:
        c: harmonics.Calibration = s.calibration
        return ({"kind": "stored", "sensor": _sensor(c.sensor)},
                {"kind": "harmonics", "cos": [float(v) for v in c.cos], "sin": [float(v) for v in c.sin]})
    if arguments.get("calibration") == "learn":
        return ({"kind": "online", "initial": None if initial is None else _sensor(_parameters(initial))},
                {"kind": "none"})
    if initial is not None:
        return {"kind": "stored", "sensor": _sensor(_parameters(initial))}, {"kind": "none"}
    return {"kind": "none"}, {"kind": "none"}


def _parameters(c: angletrack.SensorCalibration) -> tuple:
    return tuple(getattr(c, name) for name in SENSOR_FIELDS)


def document(s: "TrackSettings", gains: angletrack.Gains, integer: bool) -> dict:
    """The tracker file of ``s`` at the gains ``gains`` (at the capture's rate): the
    ``--tracker`` file's own, or the one its flags describe. ``integer``: the capture holds
    whole counts."""
    rate = {"sample_period_s": gains.sample_period_s, "gains": [float(g) for g in gains.gains]}
    if s.tracker_document is not None:
        return {**s.tracker_document, **rate}
    if not integer:
        source = {"kind": "units"}
    elif s.adc_bits is not None and s.adc_signed is not None:
        source = {"kind": "counts", "bits": s.adc_bits, "signed": s.adc_signed}
    else:
        source = {"kind": "counts"}
    rails = {"rule": "measured"} if s.adc_range is None else {
        "rule": "stated", "min": float(s.adc_range[0]), "max": float(s.adc_range[1])}
    calibration, correction = _calibration(s)
    winding = s.observer_arguments.get("winding_amplitude")
    thresholds = s.observer_arguments.get("fault_thresholds")
    return {
        "format": TRACKER_FILE_FORMAT, "version": TRACKER_FILE_VERSION, **rate,
        "number_type": NUMBER_TYPES[s.dtype], "sin_cos": s.sin_cos, "input": source, "adc_range": rails,
        "winding_check": None if winding is None else {"amplitude": float(winding)},
        "fault_thresholds": None if thresholds is None else {f: getattr(thresholds, f) for f in THRESHOLD_FIELDS},
        "calibration": calibration, "correction": correction, "pole_pairs": None,
    }


def _float64(y: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(y, dtype=np.float64)


class Run:
    """A capture's chain and its state, fed chunk by chunk (``track``); what ``--calibrate``
    learned and the faults latched, as an observer shows them."""

    def __init__(self, s: "TrackSettings", gains: angletrack.Gains, sample_dtype: str, first,
                 mid_scale: Optional[float]):
        integer = sample_dtype.startswith(("int", "uint"))
        self.document = document(s, gains, integer)
        counts = integer and self.document["input"]["kind"] == "counts" and set(self.document["input"]) == {"kind"}
        self.file = str(s.tracker_file or "the options")
        self._run = _angletrack.TrackerRun(json.dumps(self.document), self.file, _float64(first.y_c),
                                           _float64(first.y_s),
                                           mid_scale=int(mid_scale) if counts and mid_scale is not None else None)

    def track(self, y_c: np.ndarray, y_s: np.ndarray) -> dict:
        """The estimates of the next samples, one array a column (``TrackerRun.track``)."""
        return self._run.track(_float64(y_c), _float64(y_s))

    def __repr__(self) -> str:
        return repr(self._run)

    @property
    def latched_faults(self) -> int:
        """The observer's faults latched since the start (``Faults`` bits)."""
        return self._run.latched_faults[0]

    @property
    def latched_front_end_faults(self) -> int:
        """The front end's faults latched since the start (``FrontEndFaults`` bits)."""
        return self._run.latched_faults[1]

    def _learning(self) -> tuple:
        learning = self._run.learning
        if learning is None:
            raise ValueError("calibration: the chain has no online calibration (--calibrate)")
        return learning

    @property
    def calibration(self) -> angletrack.SensorCalibration:
        """The calibration the online calibration applies now."""
        return angletrack.SensorCalibration(**dict(zip(SENSOR_FIELDS, self._learning()[0])))

    @property
    def calibration_turns_learned(self) -> int:
        """The turns the online calibration learned."""
        return self._learning()[1]

    @property
    def calibration_status(self) -> str:
        """The online calibration's status (``"finding-centre"``, ``"centred"``, ``"stalled"``)."""
        return self._learning()[2]


class Samples:
    """Arrays in the shape of a capture's chunk (``y_c``, ``y_s``)."""

    def __init__(self, y_c: np.ndarray, y_s: np.ndarray):
        self.y_c, self.y_s = y_c, y_s


class TrackedRows:
    """The estimates of :meth:`angletrack.Tracker.track`, one array a column: ``angle``
    (rad, the number type's float; float64 for fixed point), ``position`` (rad),
    ``speed`` (rad/s), ``acceleration`` (rad/s^2), ``phase_error``, ``faults`` and
    ``front_end_faults`` (bits)."""

    def __init__(self, rows: dict, dtype: str):
        float_type = np.float64 if dtype == "fixed" else np.dtype(dtype)
        self.angle = rows["angle_rad"].astype(float_type)
        self.position = rows["position_rad"]
        self.speed = rows["speed_rad_s"].astype(float_type)
        self.acceleration = rows["acceleration_rad_s2"].astype(float_type)
        self.phase_error = rows["phase_error"].astype(float_type)
        self.faults = rows["faults"]
        self.front_end_faults = rows["front_end_faults"]

    def __len__(self) -> int:
        return len(self.faults)
