"""Angle tracking observers (software resolver-to-digital conversion) on numpy arrays.

A resolver (after demodulation), a sin/cos magnetic encoder or high-frequency injection gives
two noisy signals ``y_c ~ cos(theta)`` and ``y_s ~ sin(theta)``. An angle tracking observer
(ATO) turns them into angle (rad), speed (rad/s) and acceleration (rad/s^2), sample by sample.
The observers run in Rust (the ``angletrack-core`` crate) with the GIL released; float32
input stays float32 and float64 stays float64.

>>> import numpy as np, angletrack
>>> gains = angletrack.Gains([0.06, 0.001], sample_period_s=1e-4)   # 2nd-order ATO, 10 kHz
>>> theta = np.linspace(0.0, 20.0, 10_000)                        # rad
>>> est = angletrack.track(gains, np.cos(theta), np.sin(theta))
>>> round(float(est.position[-1]), 3)
20.0

Every argument the package refuses (a value out of range, an unstable gain set, a wrong
array shape, an unknown name) raises ``angletrack.ConfigError``, a ``ValueError`` whose
``parameter`` attribute is the argument's name as the caller spelled it:

>>> try:
...     angletrack.Gains([0.06, 0.001], sample_period_s=0.0)
... except angletrack.ConfigError as e:
...     print(e.parameter)
sample_period_s
"""

import enum as _enum

from angletrack._angletrack import (
    Capture,
    CaptureChunk,
    CaptureError,
    CaptureReader,
    ConfigError,
    DemodulatedPairs,
    Demodulator,
    Design,
    DesignReport,
    DriveAngles,
    DriveOutputs,
    ErrorStatistics,
    Estimate,
    Estimates,
    FAULT_BITS,
    FRONT_END_FAULT_BITS,
    FaultThresholds,
    FixedEstimate,
    FixedEstimates,
    FixedObserver,
    Gains,
    KalmanSolution,
    LARGE_STEP_RAD,
    MAX_POLE_TIMES_PERIOD,
    Metrics,
    MotionProfile,
    Observer,
    OutputFile,
    ObserverBatch,
    PAPER_BUTTERWORTH_DAMPING,
    PAPER_COMPARISON_BANDWIDTH_HZ,
    PAPER_COMPARISON_SAMPLE_PERIOD_S,
    PAPER_COMPARISON_SENSOR_NOISE_STD,
    PAPER_FIVE_PERCENT_DAMPING,
    PAPER_OVERSHOOT_SAMPLE_PERIOD_S,
    PAPER_POLE_FREQUENCY_RATIO,
    PAPER_POLE_RATIO,
    PaperSetting,
    PredictedError,
    ResolverModel,
    SETTLING_BAND,
    Scenario,
    SensorCalibration,
    SensorModel,
    StepResponse,
    TableWriter,
    __version__,
    closed_loop_response,
    design_from_capture,
    kalman,
    kalman_from_jerk_density,
    kalman_from_jerk_std,
    max_trackable_speed_rad_s,
    metrics,
    paper_benchmark_gains,
    paper_compared_observers,
    paper_settings,
    predicted_error,
    predicted_error_on_kalman_model,
    check_outputs,
    read_capture,
    resolver_windings,
    second_order_bandwidth_ratio,
    second_order_butterworth,
    second_order_from_bandwidth,
    second_order_from_tracking_error,
    second_order_from_tracking_error_sampled,
    third_order_butterworth,
    third_order_from_overshoot,
    third_order_from_poles,
    track,
    track_batch,
    write_output,
    capture_fault_thresholds,
)

__all__ = [
    "Capture",
    "CaptureChunk",
    "CaptureError",
    "CaptureReader",
    "ConfigError",
    "DemodulatedPairs",
    "Demodulator",
    "Design",
    "DesignReport",
    "DriveAngles",
    "DriveOutputs",
    "ErrorStatistics",
    "Estimate",
    "Estimates",
    "EstimatesWriter",
    "FaultThresholds",
    "Faults",
    "FrontEndFaults",
    "FixedEstimate",
    "FixedEstimates",
    "FixedObserver",
    "Gains",
    "KalmanSolution",
    "LARGE_STEP_RAD",
    "MAX_POLE_TIMES_PERIOD",
    "Metrics",
    "MotionProfile",
    "Observer",
    "ObserverBatch",
    "OutputFile",
    "PAPER_BUTTERWORTH_DAMPING",
    "PAPER_COMPARISON_BANDWIDTH_HZ",
    "PAPER_COMPARISON_SAMPLE_PERIOD_S",
    "PAPER_COMPARISON_SENSOR_NOISE_STD",
    "PAPER_FIVE_PERCENT_DAMPING",
    "PAPER_OVERSHOOT_SAMPLE_PERIOD_S",
    "PAPER_POLE_FREQUENCY_RATIO",
    "PAPER_POLE_RATIO",
    "PaperSetting",
    "PredictedError",
    "ResolverModel",
    "SETTLING_BAND",
    "Scenario",
    "SensorCalibration",
    "SensorModel",
    "StepResponse",
    "TableWriter",
    "__version__",
    "closed_loop_response",
    "design_from_capture",
    "kalman",
    "kalman_from_jerk_density",
    "kalman_from_jerk_std",
    "max_trackable_speed_rad_s",
    "metrics",
    "paper_benchmark_gains",
    "paper_compared_observers",
    "paper_settings",
    "predicted_error",
    "predicted_error_on_kalman_model",
    "check_outputs",
    "read_capture",
    "write_output",
    "demodulate",
    "drive_outputs",
    "resolver_windings",
    "second_order_bandwidth_ratio",
    "second_order_butterworth",
    "second_order_from_bandwidth",
    "second_order_from_tracking_error",
    "second_order_from_tracking_error_sampled",
    "third_order_butterworth",
    "third_order_from_overshoot",
    "third_order_from_poles",
    "track",
    "capture_fault_thresholds",
    "track_batch",
    "Calibration",
    "CalibratedObserver",
    "calibrate",
    "track_calibrated",
    "Tracker",
]

from angletrack.harmonics import (  # noqa: E402
    CalibratedObserver,
    Calibration,
    calibrate,
    track_calibrated,
)
from angletrack.tracker import Tracker  # noqa: E402
from angletrack.capture import EstimatesWriter  # noqa: E402


def _flags(name: str, bits, doc: str):
    """A flag type of this package named ``name`` from the crate's ``(name, bit)`` list."""
    flags = _enum.IntFlag(name, dict(bits))
    flags.__module__, flags.__doc__ = __name__, doc
    return flags


#: Fault flags of ``Estimates.faults`` (uint8 per sample), ``Estimate.faults`` and
#: ``Observer.latched_faults``, as in an RDC chip's fault register: ``Faults(bits)`` names
#: them, ``est.faults & Faults.BAD_SAMPLE`` selects one.
Faults = _flags("Faults", FAULT_BITS, (
    "Fault flags as in an RDC chip's fault register: LOSS_OF_SIGNAL, DEGRADATION_OF_SIGNAL, "
    "LOSS_OF_TRACKING, BAD_SAMPLE (the observer coasted), FALSE_LOCK (re-acquired), and with the "
    "online calibration AMPLITUDE_MISMATCH (channel gains apart) and OFFSET_OR_QUADRATURE (a "
    "learned offset or quadrature angle beyond its bound); FRONT_END: a front-end fault (clipping "
    "against adc_range, a demodulator's fault, a winding open or shorted), coasted through when it "
    "invalidates the sample."
))

#: The resolver front end's own fault flags, as ``Faults`` names the observer's.
FrontEndFaults = _flags("FrontEndFaults", FRONT_END_FAULT_BITS, (
    "The resolver front end's fault flags (``DemodulatedPairs.faults``, the resolver path's "
    "front_end_faults column, ``Demodulator.latched_faults``): LOSS_OF_EXCITATION, PHASE_DRIFT "
    "(the carrier loop out of lock or at its frequency bound), CLIPPING, WEAK_EXCITATION, WINDING (open or "
    "shorted), EXCITATION_REFERENCE (the recorded excitation flat or not a number: the half turn unchecked)."
))

# The resolver front end's whole-array helpers (pure Python over the extension's classes).
from angletrack.resolver import demodulate, drive_outputs  # noqa: E402
