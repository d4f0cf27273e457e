"""``angletrack track --dtype fixed``: a capture of integer counts streamed through the
fixed-point chain (:class:`angletrack.FixedObserver` with its stages: the mid-scale removed
and the counts shifted to 16 bits, a stored calibration in integers, the angle correction
as a table), as a firmware computes it. The mid-scale is the capture's (stated, or read from
the whole capture: ``tracking.counts_mid_scale``); the shift and the monitor's amplitude are
measured from its first samples by the Rust crate (``angletrack::fixed_input``); the calibration is learned in float (``angletrack calibrate``
or ``track --calibrate``) and applied here in integers.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Optional, Union

import numpy as np

import angletrack
from angletrack import clipping
from angletrack._angletrack import fixed_input

if TYPE_CHECKING:
    from angletrack import harmonics
    from angletrack.tracking import TrackSettings

#: The columns ``track --dtype fixed`` writes and their dtypes: the estimates in physical
#: units beside the firmware's binary angle (2^32 per turn).
COLUMNS = [("time_s", np.float64), ("angle_rad", np.float64), ("position_rad", np.float64),
           ("speed_rad_s", np.float64), ("acceleration_rad_s2", np.float64), ("phase_error", np.float64),
           ("faults", np.uint8), ("angle_binary", np.int32)]


def refusal(s: "TrackSettings") -> Optional[str]:
    """The one-line refusal of a combination of options ``--dtype fixed`` cannot run, naming
    both flags and why; ``None`` when it can."""
    if s.carrier_hz is not None:
        return ("dtype: --dtype fixed with --carrier-hz: the demodulator's pairs are float64; track them "
                "with --dtype float32 or float64")
    if s.sin_cos is not None:
        return "dtype: --dtype fixed with --sin-cos: the fixed-point observer has its own Q15 sin/cos table"
    if s.observer_arguments.get("calibration") == "learn":
        return ("dtype: --dtype fixed with --calibrate: the online calibration learns in float; learn it "
                "with --calibrate (float64) or `angletrack calibrate`, then apply it with --dtype fixed "
                "--calibration FILE")
    return None


def _counts(values: np.ndarray, capture: object) -> np.ndarray:
    if values.size and (np.min(values) < -32768 or np.max(values) > 32767):
        raise ValueError(f"{capture}: --dtype fixed takes counts within int16 (-32768 to 32767); the capture "
                         f"holds {np.min(values):g} to {np.max(values):g}")
    return values.astype(np.int16)


def track_fixed(s: "TrackSettings", gains: angletrack.Gains, reader: angletrack.CaptureReader, first,
                stats) -> tuple[list[str], angletrack.FixedObserver]:
    """Runs the capture of ``reader`` (its first chunk ``first`` read already) through the
    fixed-point chain with ``gains``, writes the estimates to ``s.output`` (``COLUMNS``; CSV,
    ``.npy`` or ``.npz``) and adds the errors to ``stats``; returns the summary's lines (the
    statistics' last) and the observer."""
    from angletrack.tracking import finishing_checks

    message = refusal(s)
    if message is not None:
        raise ValueError(message)
    if not reader.sample_dtype.startswith(("int", "uint")):
        raise ValueError(f"dtype: --dtype fixed takes integer ADC counts; {s.capture} holds {reader.sample_dtype} "
                         "samples (use --dtype float32 or float64)")
    calibration: Union[None, angletrack.SensorCalibration, "harmonics.Calibration"] = (
        s.calibration if s.calibration is not None else s.observer_arguments.get("initial_calibration"))
    from angletrack.tracking import _mid_scale

    # A tracker file's stated mid-scale, else the capture's by the crate's rule.
    mid, shift, amplitude, monitor = fixed_input(first.y_c, first.y_s, int(_mid_scale(s, reader.sample_dtype)))
    adc_range = s.adc_range if s.adc_range is not None else clipping.measured_range(first.y_c, first.y_s)
    counts_range = clipping.integer_range(
        adc_range, "the stated --adc-range" if s.adc_range is not None else "the range measured")
    # No range stated or found on the first chunk: the rails measured as the samples come.
    observer = angletrack.FixedObserver(gains, nominal_amplitude=monitor, calibration=calibration,
                                        mid_scale_counts=mid, input_shift=shift, adc_range=counts_range,
                                        measure_adc_range=counts_range is None)
    s.output.parent.mkdir(parents=True, exist_ok=True)
    rejected = flagged = 0
    bad, front_end = int(angletrack.Faults.BAD_SAMPLE), int(angletrack.Faults.FRONT_END)
    # All or nothing: written beside the output and renamed when complete; a fault part
    # way (a malformed row, an interrupt) leaves the output as it was.
    with angletrack.TableWriter(s.output, COLUMNS) as out:
        chunk = first
        while chunk is not None:
            est = observer.update(_counts(chunk.y_c, s.capture), _counts(chunk.y_s, s.capture))
            time_s = chunk.time_s
            if time_s is None:
                time_s = (chunk.first_sample + np.arange(len(chunk), dtype=np.float64)) * gains.sample_period_s
            faults = np.asarray(est.faults)
            flagged += int(np.count_nonzero(faults & front_end))
            angle = np.asarray(est.angle, dtype=np.float64) * (math.pi / 2**31)
            values = [time_s, angle, est.position_rad, est.speed_rad_s, est.acceleration_rad_s2,
                      np.asarray(est.phase_error) / 2**15, faults, est.angle]
            out.write([np.ascontiguousarray(v, dtype=dtype) for v, (_, dtype) in zip(values, COLUMNS)])
            rejected += int(np.count_nonzero(np.asarray(est.faults) & bad))
            if stats is not None:
                stats.add(time_s, angle, chunk.reference_rad)
            chunk = next(iter(reader), None)
        statistics = finishing_checks(s, observer, stats)  # inside the block: no estimates left behind
    latched = angletrack.Faults(observer.latched_faults)
    stages = "no stored calibration" if calibration is None else (
        "stored calibration (FixedCalibration)" if isinstance(calibration, angletrack.SensorCalibration)
        else "stored calibration (FixedCalibration) and angle correction (FixedAngleCorrectionTable, 256 entries)")
    lines = [
        repr(observer),
        f"fixed-point chain: counts of amplitude {amplitude:.6g}, mid-scale {mid} removed, shifted left by "
        f"{shift} bits, monitor amplitude {monitor:.6g}; {stages}",
        f"{reader.rows} samples ({reader.format}, {reader.sample_dtype}) -> {s.output}",
        f"faults latched: {latched.name if latched else 'none'}; {rejected} samples rejected",
    ]
    lines.append(f"{clipping.describe(adc_range, s.adc_range is not None)}: {flagged} samples clipped "
                 "(flagged FRONT_END; those clipped in both channels coasted through)")
    return lines + statistics, observer
