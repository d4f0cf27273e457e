"""Section 6 of ``angletrack report``: a sensor with angle-dependent errors (3rd and 4th
harmonics of its angle error, offsets, noise), calibrated as ``angletrack calibrate`` does
from a capture at constant speed, then a second capture of it with a speed ripple tracked
as ``angletrack track`` does, without and with ``--calibration``.

Every step goes through the files and functions of the command line: the captures are
written as CSV, the calibration is learned by :func:`angletrack.tracking.calibrate_capture`
(``angletrack calibrate``) and written as JSON, read back by
:func:`angletrack.calibration.read_stored` and applied by
:func:`angletrack.tracking.track_capture` (``angletrack track --calibration``), which
writes the estimates as ``.npy``. ``report`` writes the section, ``report_plots`` its
figure.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np

import angletrack as at
from angletrack import calibration, capture, export, harmonics, tracking
from angletrack.capture_analysis import AngleErrorBins, wrap
from angletrack.report_markdown import figure, khz, num, table

#: The sensor of the issue's target: 5 mrad of 3rd and 4th harmonic angle error (with phases),
#: 5 % offsets, white noise of 0.001 per channel (amplitude 1).
HARMONICS = ((3, 5e-3, 0.3), (4, 5e-3, 1.1))
OFFSET = 0.05
NOISE_STD = 1e-3
#: 20 kHz, the third-order Butterworth loop of time constant 2 ms: at 200 Hz electrical the
#: 3rd harmonic (600 Hz) lies well above its bandwidth, as the learning needs.
SAMPLE_PERIOD_S = 5e-5
TIME_CONSTANT_S = 2e-3
ELECTRICAL_HZ = 200.0
#: The learning capture (constant speed) and the tracked one (speed ripple of +-5 % at 2 Hz).
LEARNING_TURNS = 50
RIPPLE_FRACTION = 0.05
RIPPLE_HZ = 2.0
RIPPLE_S = 1.0
#: The tracked capture's statistics start after the observer's start-up from rest (20 time
#: constants).
SKIP_S = 0.04
#: The command line's file names, in the section's directory.
FILES = {
    "gains": "gains.json",
    "learning": "learning.csv",
    "ripple": "ripple.csv",
    "calibration": "calibration.json",
    "uncorrected": "ripple_uncorrected.npy",
    "calibrated": "ripple_calibrated.npy",
}


@dataclasses.dataclass
class HarmonicsResult:
    """Section 6: the learned calibration and the tracked capture's angle errors (truth -
    estimate, rad) without and with it."""

    sensor: at.SensorModel
    design: at.Design
    learned: harmonics.Calibration
    #: The tracked capture (speed ripple).
    scenario: at.Scenario
    #: Truth - estimate (rad, wrapped) of ``angletrack track`` without and with ``--calibration``.
    uncorrected_error_rad: np.ndarray
    calibrated_error_rad: np.ndarray
    #: The first sample of the statistics (after ``SKIP_S``).
    first: int
    #: The design's predicted RMS angle error for the sensor's noise (rad).
    predicted_noise_rad: float
    #: The files written (``FILES``' keys).
    paths: dict[str, pathlib.Path]
    #: Turns of the learning capture, duration (s) of the tracked one.
    learning_turns: int = LEARNING_TURNS
    ripple_s: float = RIPPLE_S

    def statistics(self, error_rad: np.ndarray) -> tuple[float, float]:
        """``(RMS after removing the mean, mean)`` (rad) of an error after ``SKIP_S``: the mean
        is a constant angle offset, which no calibration without a reference sees."""
        kept = error_rad[self.first:]
        mean = float(np.mean(kept))
        return float(np.sqrt(np.mean((kept - mean) ** 2))), mean

    def binned(self, error_rad: np.ndarray) -> AngleErrorBins:
        """The error after ``SKIP_S`` (mean removed) binned over the true electrical angle."""
        bins = AngleErrorBins()
        kept = error_rad[self.first:]
        bins.add(self.scenario.angle_rad[self.first:], kept - np.mean(kept))
        return bins


def harmonic_sensor() -> at.SensorModel:
    """The section's sensor (see ``HARMONICS``)."""
    return at.SensorModel(offset_cos=OFFSET, offset_sin=-OFFSET, angle_error_harmonics=list(HARMONICS),
                          noise_std=NOISE_STD)


def harmonic_phase(cos: float, sin: float) -> float:
    """The phase ``p`` (rad) of ``a sin(k theta + p)`` whose coefficients of ``cos(k theta)``
    and ``sin(k theta)`` are ``cos`` and ``sin`` (the sensor model's form of a harmonic)."""
    return math.atan2(cos, sin)


def _write_capture(path: pathlib.Path, sc: at.Scenario) -> None:
    capture.write_capture(path, {"time": sc.time_s, "y_c": sc.y_c, "y_s": sc.y_s, "reference": sc.angle_rad})


def _error_rad(estimates_path: pathlib.Path, sc: at.Scenario) -> np.ndarray:
    return wrap(sc.angle_rad - np.load(estimates_path)["angle_rad"])


def run_harmonics(out_dir: pathlib.Path, *, learning_turns: int = LEARNING_TURNS,
                  ripple_s: float = RIPPLE_S) -> HarmonicsResult:
    """Writes the section's files into ``out_dir`` and runs the command line's steps:
    ``angletrack calibrate learning.csv --gains-file gains.json -o calibration.json``, then
    ``angletrack track ripple.csv --gains-file gains.json`` without and with ``--calibration
    calibration.json``."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {key: out_dir / name for key, name in FILES.items()}
    sensor = harmonic_sensor()
    design = at.third_order_butterworth(TIME_CONSTANT_S, SAMPLE_PERIOD_S)
    paths["gains"].write_text(export.to_json(design.gains))
    speed = 2 * math.pi * ELECTRICAL_HZ
    learning = at.MotionProfile(0.0, speed).constant_speed(speed, learning_turns / ELECTRICAL_HZ)
    _write_capture(paths["learning"], at.Scenario.generate(learning, sensor, sample_period_s=SAMPLE_PERIOD_S, seed=1))
    ripple = at.MotionProfile(0.0, speed).speed_ripple(RIPPLE_FRACTION * speed, RIPPLE_HZ, ripple_s)
    sc = at.Scenario.generate(ripple, sensor, sample_period_s=SAMPLE_PERIOD_S, seed=2)
    _write_capture(paths["ripple"], sc)

    learned = tracking.calibrate_capture(
        tracking.TrackSettings(capture=paths["learning"], output=paths["calibration"], gains_file=paths["gains"]))
    paths["calibration"].write_text(learned.to_json())
    # As `angletrack track` builds its settings from `--calibration FILE` (none, then the file).
    for key, stored in (("uncorrected", None), ("calibrated", calibration.read_stored(paths["calibration"]))):
        tracking.track_capture(tracking.TrackSettings(
            capture=paths["ripple"], output=paths[key], gains_file=paths["gains"],
            observer_arguments=calibration.observer_arguments(False, stored),
            calibration=calibration.angle_calibration(stored),
        ))
    return HarmonicsResult(
        sensor=sensor, design=design, learned=learned, scenario=sc,
        uncorrected_error_rad=_error_rad(paths["uncorrected"], sc),
        calibrated_error_rad=_error_rad(paths["calibrated"], sc),
        first=round(SKIP_S / SAMPLE_PERIOD_S),
        predicted_noise_rad=design.report(sensor_noise_std=NOISE_STD).angle_error_rms_rad,
        paths=paths, learning_turns=learning_turns, ripple_s=ripple_s,
    )


def harmonic_rows(result: HarmonicsResult) -> list[tuple[int, float, float, float, float]]:
    """``(order, true amplitude, learned amplitude, true phase, learned phase)`` (rad) of the
    orders the calibration learns (``NaN`` phase for a true amplitude of 0)."""
    truth = {k: (a, p) for k, a, p in HARMONICS}
    rows = []
    for k in range(1, harmonics.MAX_ORDER + 1):
        a, p = truth.get(k, (0.0, math.nan))
        learned = result.learned
        rows.append((k, a, learned.harmonic_amplitude(k), p, harmonic_phase(learned.cos[k - 1], learned.sin[k - 1])))
    return rows


def section_harmonics(result: HarmonicsResult, plots: bool) -> list[str]:
    """Section 6's Markdown: the set-up and the command line's steps, the angle errors before
    and after beside the design's predicted noise floor, learned against true harmonics."""
    before, before_mean = result.statistics(result.uncorrected_error_rad)
    after, after_mean = result.statistics(result.calibrated_error_rad)
    learned = result.learned
    files = {key: path.name for key, path in result.paths.items()}
    errors = [
        ["`angletrack track` (uncorrected)", num(before, ".3g", 1e3), num(before_mean, ".3g", 1e3)],
        ["`angletrack track --calibration`", num(after, ".3g", 1e3), num(after_mean, ".3g", 1e3)],
        [f"predicted noise floor (white noise {NOISE_STD} per channel)", num(result.predicted_noise_rad, ".3g", 1e3),
         "-"],
    ]
    harmonic_table = [
        [str(k), num(a, ".3f", 1e3), num(b, ".3f", 1e3), num(b - a, "+.3f", 1e3),
         "-" if a == 0 else num(p, ".3f"), "-" if a == 0 else num(q, ".3f"),
         "-" if a == 0 else num(float(wrap(q - p)), "+.4f")]
        for k, a, b, p, q in harmonic_rows(result)
    ]
    o_c, o_s, a_c, a_s, phi = learned.sensor
    sensor_table = [
        ["offset_c", num(OFFSET, ".4f"), num(o_c, ".4f")],
        ["offset_s", num(-OFFSET, ".4f"), num(o_s, ".4f")],
        ["amplitude_s / amplitude_c", "1", num(a_s / a_c, ".5f")],
        ["quadrature (mrad)", "0", num(phi, ".3f", 1e3)],
    ]
    bandwidth_hz = result.design.report().bandwidth_hz
    tracked = result.binned(result.uncorrected_error_rad).harmonics_rad(orders=[k for k, _, _ in HARMONICS])
    return [
        "",
        "## 6. Angle-dependent errors: `angletrack calibrate`, then `track --calibration`",
        "",
        "A sensor whose angle error has a 3rd and a 4th harmonic, "
        + " and ".join(f"{1e3 * a:.0f} mrad sin({k} theta + {p})" for k, a, p in HARMONICS)
        + f", with offsets {OFFSET:+} and {-OFFSET:+} (5 % of the amplitude) and white noise of {NOISE_STD} per "
        f"channel. The observer: {result.design.method} ({TIME_CONSTANT_S * 1e3:g} ms) at {khz(SAMPLE_PERIOD_S)}, "
        f"-3 dB bandwidth {num(bandwidth_hz, '.0f')} Hz. The steps are the command line's, on the files "
        "beside this report (`harmonics/`):",
        "",
        "```sh",
        f"angletrack calibrate {files['learning']} --gains-file {files['gains']} -o {files['calibration']}",
        f"angletrack track {files['ripple']} --gains-file {files['gains']} -o {files['uncorrected']}",
        f"angletrack track {files['ripple']} --gains-file {files['gains']} --calibration {files['calibration']} "
        f"-o {files['calibrated']}",
        "```",
        "",
        f"The calibration is learned from {result.learning_turns} turns at a constant {ELECTRICAL_HZ:.0f} Hz electrical "
        f"(the observer's own angle as the reference: {learned.turns:.0f} turns used, angle error "
        f"{num(learned.error_rms_rad, '.3g', 1e3)} mrad RMS, {num(learned.residual_rms_rad, '.3g', 1e3)} mrad "
        f"left by the fit), then applied to another capture of the same sensor whose speed ripples by "
        f"+-{100 * RIPPLE_FRACTION:.0f} % at {RIPPLE_HZ:g} Hz for {result.ripple_s:g} s. Errors are truth - estimate "
        f"against the capture's reference, from {SKIP_S * 1e3:.0f} ms on (the start-up from rest); the mean is "
        "a constant angle offset, which no calibration without a reference can see, and is removed from the RMS.",
        "",
        table(["tracked", "RMS angle error, mean removed (mrad)", "mean (mrad)"], errors),
        "",
        "The harmonics of the angle error, `a sin(k theta + p)`, learned against the sensor's (amplitudes in mrad, "
        "phases in rad). Orders 1 and 2 take up what the learned offsets, imbalance and quadrature (below) leave.",
        "",
        table(["order k", "true a", "learned a", "learned - true", "true p", "learned p", "learned - true"],
              harmonic_table),
        "",
        table(["sensor parameter", "true", "learned"], sensor_table),
        "",
        "In the figure, the uncorrected estimate's 3rd and 4th harmonics ("
        + " and ".join(f"{1e3 * a:.2g}" for a in tracked)
        + " mrad) are smaller than the sensor's (5 mrad): the loop follows its sensor's reading only within "
        "its bandwidth, and these lie above it.",
        *figure(plots, "angle error against angle and its harmonics, without and with the calibration",
                "harmonics.png"),
    ]
