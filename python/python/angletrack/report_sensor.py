"""Section 5 of ``angletrack report``: a sensor with offsets, gain imbalance and quadrature
error, tracked without and with the online calibration (docs/theory.md §12), and the
harmonics of its angle error. ``report`` writes the section, ``report_plots`` its figure.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import angletrack as at

#: The sensor (docs/theory.md §12): raw counts of amplitude 1800 (a 12-bit ADC),
#: offsets 5 %, gain imbalance 10 %, quadrature 3 degrees, noise 1 % of the amplitude, at a
#: constant 10 Hz electrical (well below the loop's bandwidth: the angle error is the
#: sensor's own) for 60 turns; its statistics start after 20 turns (the calibration's).
AMPLITUDE = 1800.0
ELECTRICAL_HZ = 10.0
TURNS = 60
CONVERGED_TURNS = 20


@dataclasses.dataclass
class SensorResult:
    """Section 5: one imperfect sensor tracked by the Kalman ATO without and with the online
    calibration."""

    sensor: at.SensorModel
    scenario: at.Scenario
    uncorrected: at.Estimates
    corrected: at.Estimates
    learned: at.SensorCalibration
    turns_learned: int
    #: The first sample of the statistics (after ``CONVERGED_TURNS`` turns).
    first: int


def imperfect_sensor() -> at.SensorModel:
    """Section 5's sensor (see ``AMPLITUDE``)."""
    a = AMPLITUDE
    return at.SensorModel(
        amplitude=a, offset_cos=0.05 * a, offset_sin=-0.05 * a, amplitude_imbalance=0.1,
        quadrature_error_rad=math.radians(3.0), noise_std=0.01 * a,
    )


def run_sensor(design: at.Design, sample_period_s: float) -> SensorResult:
    """Tracks section 5's sensor with ``design``: the plain observer, then one learning the
    calibration (both with the diagnostics stated for the sensor's amplitude)."""
    speed = 2 * math.pi * ELECTRICAL_HZ
    profile = at.MotionProfile(0.3, speed).constant_speed(speed, TURNS / ELECTRICAL_HZ)
    sensor = imperfect_sensor()
    sc = at.Scenario.generate(profile, sensor, sample_period_s=sample_period_s, seed=5)
    thresholds = at.FaultThresholds(nominal_amplitude=AMPLITUDE)
    uncorrected = at.Observer(design.gains, fault_thresholds=thresholds).update(sc.y_c, sc.y_s)
    learning = at.Observer(design.gains, calibration="learn", fault_thresholds=thresholds)
    corrected = learning.update(sc.y_c, sc.y_s)
    first = round(CONVERGED_TURNS / ELECTRICAL_HZ / sample_period_s)
    return SensorResult(sensor, sc, uncorrected, corrected, learning.calibration,
                        learning.calibration_turns_learned, first)


def angle_error_harmonics(truth_rad, estimate_rad) -> tuple[float, float, float]:
    """The RMS of the wrapped angle error after removing its mean, and the amplitudes of its
    1x and 2x harmonics of the true angle (least squares on cos/sin of theta and 2 theta)."""
    error = np.angle(np.exp(1j * (truth_rad - estimate_rad)))
    error = error - error.mean()
    basis = np.column_stack([np.ones_like(truth_rad)] + [f(k * truth_rad) for k in (1, 2) for f in (np.cos, np.sin)])
    coef = np.linalg.lstsq(basis, error, rcond=None)[0]
    return float(np.sqrt(np.mean(error**2))), math.hypot(coef[1], coef[2]), math.hypot(coef[3], coef[4])
