"""Angle-dependent error calibration: learn a sensor's offsets, imbalance and quadrature (the
least-squares Lissajous ellipse) and the harmonics of its angle error (against a reference
angle when given, else against an observer's angle at roughly constant speed) from a
capture, with each harmonic's uncertainty, and track with them removed inside the phase
detector.

    >>> import angletrack, numpy as np
    >>> g = angletrack.third_order_butterworth(2e-3, 5e-5).gains
    >>> theta = 2 * np.pi * 200 * np.arange(5000) * 5e-5
    >>> read = theta + 5e-3 * np.sin(3 * theta + 0.3)
    >>> cal = angletrack.calibrate(np.cos(read) + 0.05, np.sin(read), g)
    >>> abs(cal.harmonic_amplitude(3) - 5e-3) < 3e-4
    True
    >>> est = angletrack.track_calibrated(g, np.cos(read) + 0.05, np.sin(read), cal)

Without a reference, the self-calibration runs a loop of its own designed from the capture's
speed (or the gains' loop with ``own_loop=False``, whose bandwidth then sets the lowest
learnable order) and learns orders 3 and up: an angle-synchronous speed ripple and a sensor
error cannot be told apart without a reference, and orders 1 and 2 are the ellipse's. An
order below ``min_significance`` times its uncertainty is not learned. The correction is
applied at any speed.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, Callable, Iterable, Optional

import numpy as np

from angletrack import _angletrack
from angletrack._angletrack import (Estimates, FaultThresholds, Gains, _CaptureCalibrator, _corrected_observer,
                                   capture_fault_thresholds)

if TYPE_CHECKING:
    from angletrack._angletrack import _LearnedCalibration as LearnedCalibration

#: The ``format`` of the file :meth:`Calibration.to_json` writes.
JSON_FORMAT = _angletrack.ANGLE_CALIBRATION_FORMAT
#: The highest harmonic order a calibration holds (the core's ``MAX_CORRECTION_ORDER``).
MAX_ORDER = 8


@dataclasses.dataclass(frozen=True)
class Calibration:
    """A sensor's calibration: ``sensor`` = ``(offset_c, offset_s, amplitude_c, amplitude_s,
    quadrature_rad)`` (the core's ``SensorCalibration::new`` arguments) and the angle error
    ``d(theta) = sum_k cos[k-1] cos(k theta) + sin[k-1] sin(k theta)`` (rad, k = 1..8, the
    core's ``AngleCorrection::new`` arguments), with what the learning saw: ``method``
    (``"reference"``, ``"self, own loop"``, ``"self, the gains' loop"``, ``"unknown"`` for an
    older file) and ``orders``, one dict per order 1..12 of the angle error (``order``,
    ``amplitude_rad``, ``uncertainty_rad``: the standard deviation of each coefficient from
    the residual's noise, ``status``: ``"learned"``, ``"not significant"``, ``"within the
    loop's bandwidth"``, ``"not requested"``, ``"not resolved"``); those not learned are the
    residual's spectrum."""

    sensor: tuple
    cos: tuple
    sin: tuple
    speed_rad_s: float = float("nan")
    turns: float = float("nan")
    error_rms_rad: float = float("nan")
    residual_rms_rad: float = float("nan")
    method: str = "unknown"
    orders: tuple = ()
    warnings: tuple = ()

    def harmonic_amplitude(self, order: int) -> float:
        """The amplitude (rad) of the angle error's harmonic ``order``."""
        return float(np.hypot(self.cos[order - 1], self.sin[order - 1]))

    def angle_error(self, theta: Any) -> np.ndarray:
        """``d(theta)`` (rad) on an array of angles."""
        theta = np.asarray(theta, dtype=np.float64)
        k = np.arange(1, MAX_ORDER + 1)[:, None]
        return np.asarray(self.cos) @ np.cos(k * theta[None, :]) + np.asarray(self.sin) @ np.sin(k * theta[None, :])

    def to_json(self) -> str:
        """JSON in float64 (exact round trip through :meth:`from_json`), as the Rust crate's
        ``CaptureCalibration::to_json`` writes it; the calibration is checked first."""
        return _angletrack.angle_calibration_to_json(
            self.sensor, self.cos, self.sin, self.speed_rad_s, self.turns, self.error_rms_rad,
            self.residual_rms_rad, method=self.method,
            orders=[(o["order"], o["amplitude_rad"], o["uncertainty_rad"], o["status"]) for o in self.orders],
        )

    @classmethod
    def from_json(cls, text: str, file: str = "calibration file") -> "Calibration":
        """The calibration of a document written by :meth:`to_json`, checked (``ValueError``
        naming ``file`` and the field at fault)."""
        return cls.from_learned(_angletrack.angle_calibration_from_json(text, file))

    @classmethod
    def from_learned(cls, learned: LearnedCalibration) -> "Calibration":
        """The calibration of the dict ``_CaptureCalibrator.finish`` and the calibration files give."""
        return cls(
            sensor=tuple(learned["sensor"]), cos=tuple(learned["cos"]), sin=tuple(learned["sin"]),
            speed_rad_s=learned["speed_rad_s"], turns=learned["turns"],
            error_rms_rad=learned["error_rms_rad"], residual_rms_rad=learned["residual_rms_rad"],
            method=learned.get("method", "unknown"), orders=tuple(dict(o) for o in learned.get("orders", ())),
            warnings=tuple(learned.get("warnings", ())),
        )

    def describe(self) -> str:
        """The summary ``angletrack calibrate`` prints: the method, the fit, each order's
        amplitude, uncertainty and status, and the warnings."""
        lines = [
            f"calibrated {'against the reference' if self.method == 'reference' else f'by {self.method}'}: "
            f"{self.turns:.0f} turns at {self.speed_rad_s:.6g} rad/s; angle error {self.error_rms_rad * 1e3:.3g} "
            f"mrad RMS, {self.residual_rms_rad * 1e3:.3g} mrad left by the learned orders",
            f"sensor: offsets {self.sensor[0]:.6g}, {self.sensor[1]:.6g}; amplitudes {self.sensor[2]:.6g}, "
            f"{self.sensor[3]:.6g}; quadrature {self.sensor[4]:.6g} rad",
            "order  amplitude (mrad)  uncertainty (mrad)  status",
        ]
        for o in self.orders:
            lines.append(f"{o['order']:5d}  {o['amplitude_rad'] * 1e3:16.4f}  {o['uncertainty_rad'] * 1e3:18.4f}  "
                         f"{o['status']}")
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def to_c_header(self, *, name: str = "angletrack", dtype: str = "float32") -> str:
        """A C header with the sensor calibration and the correction's coefficients
        (``angletrack::export::calibration_c_header``)."""
        return _angletrack.calibration_source(self.sensor, self.cos, self.sin, "c", name=name, dtype=dtype)

    def to_rust(self, *, name: str = "angletrack", dtype: str = "float32") -> str:
        """A Rust ``const`` block for ``SensorCalibration::new`` and ``AngleCorrection::new``
        (``angletrack::export::calibration_rust``)."""
        return _angletrack.calibration_source(self.sensor, self.cos, self.sin, "rust", name=name, dtype=dtype)


def calibrate(y_c: Any, y_s: Any, gains: Gains, *, reference: Any = None, lowest_order: Optional[int] = None,
              highest_order: int = MAX_ORDER, settle_fraction: float = 0.2, self_calibration: bool = False,
              own_loop: bool = True, min_significance: float = 3.0) -> Calibration:
    """Learns the :class:`Calibration` of a capture ``(y_c, y_s)`` held in memory: the
    offsets, imbalance and quadrature of its Lissajous ellipse, then the harmonics of the
    angle error against ``reference`` (rad, electrical) when given and ``self_calibration``
    is off, else against the angle of the calibration's own loop (``own_loop``) or of
    ``gains``, past the first ``settle_fraction`` of the capture. ``lowest_order`` (default:
    1 against a reference, 3 in a self-calibration) to ``highest_order``; an order below
    ``min_significance`` times its uncertainty is not learned. ``ConfigError`` naming the
    option at fault (a capture shorter than 5 turns, an order the loop follows, ...); the
    samples are float64 arrays or sequences of real numbers (``TypeError`` otherwise)."""
    calibrator = _CaptureCalibrator(gains, lowest_order=lowest_order, highest_order=highest_order,
                                    settle_fraction=settle_fraction, self_calibration=self_calibration,
                                    own_loop=own_loop, min_significance=min_significance)
    # The extension checks the samples' dtype (TypeError, no silent conversion) and shape.
    calibrator.add_geometry(y_c, y_s)
    calibrator.start_fit(reference is not None)
    calibrator.add_fit(y_c, y_s, reference)
    return Calibration.from_learned(calibrator.finish())


def calibrate_chunks(chunks: Callable[[], Iterable[tuple]], gains: Gains, **options: Any) -> Calibration:
    """:func:`calibrate` on a capture read twice in chunks, in constant memory: ``chunks()``
    gives a fresh iterator of ``(y_c, y_s, reference)`` arrays (``reference`` ``None``
    without a reference column) on each call; ``options`` are :func:`calibrate`'s."""
    calibrator = _CaptureCalibrator(gains, **options)
    has_reference = False
    for y_c, y_s, reference in chunks():
        calibrator.add_geometry(np.ascontiguousarray(y_c, dtype=np.float64),
                                np.ascontiguousarray(y_s, dtype=np.float64))
        has_reference = has_reference or reference is not None
    calibrator.start_fit(has_reference)
    for y_c, y_s, reference in chunks():
        calibrator.add_fit(np.ascontiguousarray(y_c, dtype=np.float64), np.ascontiguousarray(y_s, dtype=np.float64),
                           None if reference is None else np.ascontiguousarray(reference, dtype=np.float64))
    return Calibration.from_learned(calibrator.finish())


class CalibratedObserver:
    """An observer whose samples are corrected by ``calibration`` before its phase detector
    (the core's chain of the stored sensor calibration and the angle correction), in
    ``dtype`` (float32 or float64) with ``sin_cos`` (default: the dtype's); ``update`` may be
    called chunk by chunk. The raw samples are checked for clipping as ``Observer`` checks
    them: against ``adc_range``, or with ``measure_adc_range`` against the rails measured.
    ``update`` takes samples as ``Observer.update`` does: arrays of ``dtype`` (``TypeError``
    for another dtype, no silent conversion) or sequences of real numbers, 1-D (a
    ``ConfigError`` naming ``y_c`` or ``y_s`` for ``None`` or a scalar). The diagnostics'
    thresholds are ``fault_thresholds``, else those of amplitude 1 (as ``Observer``'s for
    floats: never measured on a chunk)."""

    def __init__(self, gains: Gains, calibration: Calibration, *, dtype: Any = np.float64,
                 sin_cos: Optional[str] = None, adc_range: Optional[tuple[float, float]] = None,
                 measure_adc_range: bool = False, fault_thresholds: Optional[FaultThresholds] = None):
        self.dtype = np.dtype(dtype)
        self._inner = _corrected_observer(gains, tuple(calibration.sensor), list(calibration.cos),
                                          list(calibration.sin), dtype=self.dtype, sin_cos=sin_cos,
                                          adc_range=adc_range, measure_adc_range=measure_adc_range,
                                          fault_thresholds=fault_thresholds)
        self.gains = gains
        self.calibration = calibration
        self.latched_faults = 0

    def update(self, y_c: Any, y_s: Any) -> Estimates:
        """The estimates of the samples ``(y_c, y_s)`` (an ``Estimates``)."""
        est = self._inner.update(y_c, y_s)
        self.latched_faults |= int(np.bitwise_or.reduce(est.faults)) if len(est) else 0
        return est

    def __repr__(self) -> str:
        orders = [k + 1 for k in range(MAX_ORDER) if self.calibration.cos[k] or self.calibration.sin[k]]
        return f"CalibratedObserver({self.gains!r}, dtype={self.dtype.name}, angle error orders {orders})"


def track_calibrated(gains: Gains, y_c: Any, y_s: Any, calibration: Calibration) -> Estimates:
    """The estimates of the whole capture ``(y_c, y_s)`` tracked by a
    :class:`CalibratedObserver`, its diagnostics scaled to the capture's amplitude
    (``capture_fault_thresholds``, as ``track`` scales them)."""
    thresholds = capture_fault_thresholds(y_c, y_s)
    return CalibratedObserver(gains, calibration, fault_thresholds=thresholds).update(y_c, y_s)

