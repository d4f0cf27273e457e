"""The resolver front end in Python and ``angletrack track --carrier-hz`` (``docs/theory.md §13``).

A capture whose ``y_c``, ``y_s`` columns are the raw windings of a carrier-excited resolver
(ADC counts at the capture's rate, any rate of at least 4 samples per carrier period) is
demodulated by :class:`angletrack.Demodulator`, which tracks the carrier's phase and
frequency, into one ``(y_c, y_s)`` pair per carrier period, each holding at the centroid of
its demodulation window; the pairs feed an
:class:`angletrack.Observer` whose gains run at the carrier frequency. The estimates are
time-stamped with those window centres, and a reference column is compared there
(interpolated, unwrapped).

Output columns (CSV): ``time_s`` (the window centre: the time at which the row's angle
holds), ``angle_rad``, ``position_rad``, ``speed_rad_s``, ``acceleration_rad_s2``,
``phase_error``, ``faults`` (the observer's; ``FRONT_END`` on a pair with a front-end fault,
through which the observer coasts on its prediction when the fault invalidates the pair: loss
of excitation, a winding open or shorted), ``front_end_faults`` (the demodulator's and the
winding check's: 1 loss of excitation, 2 carrier phase drift, 4 clipping, 8 weak excitation,
16 winding, 32 excitation reference), ``half_turn_unresolved`` (1 where the carrier's half
turn rests on nothing stated: no ``--expected-delay-deg``, or the excitation column unusable
in the row's window; not a fault: the angle is right or exactly half a turn off, but under a
``--calibration`` learned on the other half turn, whose offsets then add), ``y_c``,
``y_s`` (the demodulated pair); with
``--pole-pairs`` or ``--latency`` also ``electrical_angle_rad`` (pole pairs times the
mechanical angle at ``time_s + latency``, wrapped to [-pi, pi)) and
``electrical_speed_rad_s``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from typing import Optional

import numpy as np

import angletrack
from angletrack._angletrack import plan_windings
from angletrack.cli_args import any_finite_number, non_negative_number, positive_number


def demodulate(raw_c, raw_s, *, carrier_hz: float, carrier_amplitude_counts: float, excitation=None,
               **settings):
    """Demodulates whole arrays of raw winding samples (and of the excitation, if given):
    returns ``(pairs, demodulator)``, the :class:`angletrack.DemodulatedPairs` (time stamps at
    the window centroids, ``y_c``, ``y_s``, front-end faults) and the
    :class:`angletrack.Demodulator` after the last sample (its ``carrier_delay_rad`` is the
    carrier delay chosen, ``tracked_carrier_hz`` the carrier's frequency). ``settings``: the
    other keyword arguments of :class:`angletrack.Demodulator` (``adc_rate_hz`` or
    ``samples_per_period``, ...)."""
    demodulator = angletrack.Demodulator(
        carrier_hz=carrier_hz, carrier_amplitude_counts=carrier_amplitude_counts, **settings,
    )
    return demodulator.push(raw_c, raw_s, excitation), demodulator


def drive_outputs(estimates, *, sample_period_s: float, pole_pairs: int = 1, speed_ratio: int = 1,
                  latency_s: float = 0.0, speed_cutoff_hz: Optional[float] = None) -> "angletrack.DriveAngles":
    """The :class:`angletrack.DriveAngles` of an observer's ``estimates`` (one run, from its
    start): the electrical angle for ``pole_pairs`` and ``speed_ratio`` extrapolated by
    ``latency_s``, and the speed low-passed at ``speed_cutoff_hz`` if given."""
    outputs = angletrack.DriveOutputs(
        sample_period_s=sample_period_s, pole_pairs=pole_pairs, speed_ratio=speed_ratio,
        latency_s=latency_s, speed_cutoff_hz=speed_cutoff_hz,
    )
    return outputs.update(estimates)


def add_track_arguments(track: argparse.ArgumentParser) -> None:
    """The ``track`` options of the demodulating path (one group)."""
    g = track.add_argument_group(
        "resolver windings (--carrier-hz)",
        "y_c, y_s are the raw windings (ADC counts) sampled at least 4 times per carrier period (any "
        "ratio); the carrier's phase and frequency are tracked; the estimates come once per carrier "
        "period, stamped with the centroid of their demodulation window; the gains must be designed "
        "at the carrier frequency",
    )
    g.add_argument("--carrier-hz", type=float, metavar="HZ",
                   help="the excitation carrier frequency (Hz), tracked within 3 %%; refused if more than 2 %% from "
                   "the carrier measured in the capture (the windings' tone at twice the carrier); with --columns "
                   "excitation=COL (or a column named excitation) the recorded excitation resolves the carrier's "
                   "half-turn ambiguity")
    g.add_argument("--samples-per-period", type=float, metavar="N",
                   help="ADC samples per carrier period, at least 4, any ratio such as 9.6 (default: the "
                   "capture's rate / the carrier frequency; refused if the time column says otherwise)")
    g.add_argument("--carrier-amplitude", type=positive_number, metavar="COUNTS",
                   help="a winding's carrier amplitude at envelope 1 (counts, peak); default: "
                   "measured on the first chunk")
    g.add_argument("--expected-delay-deg", type=any_finite_number, metavar="DEG",
                   help="the carrier delay (degrees, positive when the windings lag) the carrier's half-turn "
                   "ambiguity is resolved around: with an excitation column the windings' delay after it (a scope's "
                   "reading; 180 for an inverted excitation probe), else their delay after a carrier of phase 0 at "
                   "the first sample; without it the half turn is taken around 0 and "
                   "every row is marked half_turn_unresolved (the windings cannot tell a delay from the one 180 "
                   "degrees away)")
    g.add_argument("--pole-pairs", type=pole_pairs_count, metavar="P",
                   help="write electrical_angle_rad for a motor of P pole pairs (1 to 65536; default 1)")
    g.add_argument("--latency", type=non_negative_number, metavar="S",
                   help="extrapolate electrical_angle_rad by S seconds from each row's time_s (the PWM "
                   "update instant; default 0)")


def pole_pairs_count(text: str) -> int:
    """A pole-pair count the drive outputs take (:class:`angletrack.DriveOutputs`' rule: a
    whole number from 1 to 2^16); argparse names the option in its message."""
    try:
        value = int(text)
        angletrack.DriveOutputs(sample_period_s=1.0, pole_pairs=value)
    except (ValueError, OverflowError):
        # ConfigError is a ValueError; OverflowError: beyond the binding's u32.
        raise argparse.ArgumentTypeError(f"expected a whole number of pole pairs from 1 to 65536, got {text}") from None
    return value


def track_options(args: argparse.Namespace) -> dict:
    """The :class:`angletrack.tracking.TrackSettings` fields of the options above; those of
    the windings given without ``--carrier-hz`` are refused in one line naming them."""
    given = [flag for flag, value in (
        ("--samples-per-period", args.samples_per_period), ("--carrier-amplitude", args.carrier_amplitude),
        ("--expected-delay-deg", args.expected_delay_deg), ("--pole-pairs", args.pole_pairs),
        ("--latency", args.latency)) if value is not None]
    if args.carrier_hz is None and given:
        raise ValueError(f"carrier_hz: {', '.join(given)} need{'s' if len(given) == 1 else ''} --carrier-hz "
                         "(the resolver path: raw windings demodulated)")
    return {
        "carrier_hz": args.carrier_hz,
        "samples_per_period": args.samples_per_period,
        "carrier_amplitude_counts": args.carrier_amplitude,
        "expected_delay_deg": args.expected_delay_deg,
        "pole_pairs": args.pole_pairs,
        "latency_s": args.latency,
    }


def _gains(s, carrier_hz: float) -> angletrack.Gains:
    from angletrack.tracking import RATE_TOLERANCE

    gains = s.designed_gains
    if gains is None:
        return angletrack.Gains(s.gains, sample_period_s=1.0 / carrier_hz)
    if abs(gains.sample_rate_hz / carrier_hz - 1.0) > RATE_TOLERANCE:
        raise ValueError(
            f"sample_rate: the gains in {s.gains_file} are designed for {gains.sample_rate_hz:.6g} Hz but "
            f"the carrier (--carrier-hz) is {carrier_hz:.6g} Hz: the estimates come once per carrier period, "
            f"so design the gains at {carrier_hz:.6g} Hz"
        )
    return gains


@dataclasses.dataclass
class _Reference:
    """The reference angle, unwrapped across chunks, with the last samples kept so that a
    window centre in the previous chunk is interpolated too."""

    time_s: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    angle_rad: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))

    def add(self, time_s: np.ndarray, reference: np.ndarray, keep: int) -> None:
        if len(self.angle_rad):
            unwrapped = np.unwrap(np.concatenate(([self.angle_rad[-1]], reference)))[1:]
        else:
            unwrapped = np.unwrap(reference)
        self.time_s = np.concatenate((self.time_s[-keep:], time_s))
        self.angle_rad = np.concatenate((self.angle_rad[-keep:], unwrapped))

    def at(self, time_s: np.ndarray) -> np.ndarray:
        return np.interp(time_s, self.time_s, self.angle_rad)


def pairs_observer(s, gains: angletrack.Gains, first_pairs):
    """The observer of the demodulated pairs: the same front-end stages as for y_c, y_s
    samples (``s.observer_arguments``: the online calibration of ``--calibrate``, a stored
    ``SensorCalibration`` of ``--calibration``; an angle calibration from ``angletrack
    calibrate`` through a :class:`harmonics.CalibratedObserver`), in ``s.dtype``. Without a
    calibration its thresholds are measured on ``first_pairs`` as on a capture's first
    samples (``capture_fault_thresholds``: the roundness check on the circle they show; the
    angle-error levels divided by ``--pole-pairs``)."""
    from angletrack import harmonics

    if s.calibration is not None:
        return harmonics.CalibratedObserver(gains, s.calibration, dtype=np.dtype(s.dtype), sin_cos=s.sin_cos)
    # The pairs' envelope is 1 at the carrier amplitude: a winding open or shorted is
    # checked against it, and coasted through as the demodulator's loss of excitation.
    arguments = {"winding_amplitude": 1.0, **s.observer_arguments}
    if not s.observer_arguments:
        arguments["fault_thresholds"] = angletrack.capture_fault_thresholds(
            first_pairs.y_c, first_pairs.y_s, pole_pairs=s.pole_pairs or 1)
    return angletrack.Observer(gains, dtype=np.dtype(s.dtype), sin_cos=s.sin_cos, **arguments)


def update_on_pairs(observer, pairs, dtype):
    """The observer's estimates of the demodulated ``pairs``, their front-end faults given
    to it so that it coasts through those that invalidate a pair (an
    :class:`angletrack.Observer`; an angle-calibrated observer takes the pairs alone)."""
    y_c, y_s = pairs.y_c.astype(dtype), pairs.y_s.astype(dtype)
    if isinstance(observer, angletrack.Observer):
        return observer.update(y_c, y_s, front_end_faults=pairs.faults)
    return observer.update(y_c, y_s)


def track_windings(s) -> tuple:
    """``angletrack track --carrier-hz``: demodulates, tracks, writes the estimates (CSV,
    ``.npy`` or ``.npz``, by the crate's ``TableWriter``); returns the
    summary and the observer of the pairs after the last one (its learned calibration)
    (``s`` a :class:`angletrack.tracking.TrackSettings`)."""
    from angletrack.tracking import _ErrorStatistics, finishing_checks

    reader = angletrack.CaptureReader(
        s.capture, **s.reader_options(), chunk_rows=s.chunk_rows,
    )
    chunks = iter(reader)
    first = next(chunks)
    capture_hz = reader.sample_rate_hz
    carrier_hz = s.carrier_hz
    # The rate, amplitude and ADC range as stated or measured on the first chunk, and the
    # contradictions refused: the crate's rules (angletrack::WindingsPlan).
    plan = plan_windings(
        np.asarray(first.y_c, dtype=np.float64), np.asarray(first.y_s, dtype=np.float64), carrier_hz=carrier_hz,
        capture_hz=capture_hz, samples_per_period=s.samples_per_period,
        carrier_amplitude_counts=s.carrier_amplitude_counts, adc_range=s.adc_range,
    )
    adc_hz, n, amplitude = plan.adc_rate_hz, plan.samples_per_period, plan.carrier_amplitude_counts
    adc_min, adc_max, adc_how = plan.adc_min_code, plan.adc_max_code, plan.adc_range_source
    gains = _gains(s, carrier_hz)
    demodulator = angletrack.Demodulator(
        carrier_hz=carrier_hz, adc_rate_hz=adc_hz, carrier_amplitude_counts=amplitude,
        adc_min_code=adc_min, adc_max_code=adc_max,
        expected_delay_rad=None if s.expected_delay_deg is None else math.radians(s.expected_delay_deg),
        # A guessed range may lie beyond rails that only later samples reach: they are
        # measured as the samples come.
        measure_adc_range=adc_how == "guessed",
    )
    dtype = np.dtype(s.dtype)
    observer = None
    drive = None
    if s.pole_pairs is not None or s.latency_s is not None:
        drive = angletrack.DriveOutputs(
            sample_period_s=gains.sample_period_s, pole_pairs=1 if s.pole_pairs is None else s.pole_pairs, latency_s=s.latency_s or 0.0,
        )
    t0 = float(first.time_s[0]) if first.time_s is not None else 0.0
    stats = _ErrorStatistics(s.skip_s, s.lock_tolerance_rad) if first.reference_rad is not None else None
    reference = _Reference()
    columns = [(name, np.float64) for name in ("time_s", "angle_rad", "position_rad", "speed_rad_s",
                                                "acceleration_rad_s2", "phase_error")]
    columns += [("faults", np.uint8), ("front_end_faults", np.uint8), ("half_turn_unresolved", np.uint8),
                ("y_c", np.float64), ("y_s", np.float64)]
    if drive is not None:
        columns += [("electrical_angle_rad", np.float64), ("electrical_speed_rad_s", np.float64)]
    pairs_total = unresolved_total = 0
    s.output.parent.mkdir(parents=True, exist_ok=True)
    # All or nothing: written beside the output and renamed when complete; a fault part
    # way (a malformed row, an interrupt) leaves the output as it was.
    with angletrack.TableWriter(s.output, columns) as out:
        chunk = first
        while chunk is not None:
            if stats is not None:
                t = chunk.time_s
                if t is None:
                    t = t0 + (chunk.first_sample + np.arange(len(chunk), dtype=np.float64)) / adc_hz
                reference.add(t, chunk.reference_rad, keep=2 * math.ceil(n))
            pairs = demodulator.push(chunk.y_c, chunk.y_s, chunk.excitation)
            if len(pairs):
                # The capture's clock when it has one (the demodulator counts samples at
                # the declared rate).
                time_s = t0 + pairs.time_s * (adc_hz / (capture_hz or adc_hz))
                if observer is None:
                    observer = pairs_observer(s, gains, pairs)
                est = update_on_pairs(observer, pairs, dtype)
                # The observer runs at its gains' rate, the pairs come at the tracked
                # carrier's: its speed and acceleration are rescaled to the latter.
                scale = demodulator.tracked_carrier_hz * gains.sample_period_s
                speed = np.asarray(est.speed, dtype=np.float64) * scale
                acceleration = np.asarray(est.acceleration, dtype=np.float64) * scale**2
                values = [time_s, est.angle, est.position, speed, acceleration, est.phase_error,
                          est.faults, pairs.faults, pairs.half_turn_unresolved, pairs.y_c, pairs.y_s]
                if drive is not None:
                    angles = drive.update(est)
                    values += [angles.electrical_angle_rad,
                               np.asarray(angles.electrical_speed_rad_s, dtype=np.float64) * scale]
                out.write([np.ascontiguousarray(v, dtype=dtype) for v, (_, dtype) in zip(values, columns)])
                pairs_total += len(pairs)
                unresolved_total += int(np.count_nonzero(pairs.half_turn_unresolved))
                if stats is not None:
                    stats.add(time_s, est.angle, reference.at(time_s))
            chunk = next(chunks, None)
        if pairs_total == 0:  # inside the block: no output is left behind
            raise ValueError(f"{s.capture}: too short: no pair left the demodulator's start-up "
                             f"({reader.rows} samples)")
        statistics = finishing_checks(s, observer, stats)
    latched = angletrack.Faults(observer.latched_faults)
    lines = [
        repr(observer),
        f"{reader.rows} ADC samples at {adc_hz:.6g} Hz ({n:.6g} per {carrier_hz:.6g} Hz carrier period; amplitude "
        f"{amplitude:.6g} counts, ADC codes {adc_min:.6g} to {adc_max:.6g}, {adc_how}{_rails_note(demodulator, adc_how)}) -> "
        f"{pairs_total} estimates -> {s.output}",
        _delay_line(demodulator, s.expected_delay_deg, unresolved_total, pairs_total),
        f"front-end faults latched: {_front_end_names(_latched_front_end(demodulator, observer))}; "
        f"observer faults latched: {latched.name if latched else 'none'}",
    ]
    return "\n".join(lines + statistics), observer


def _rails_note(demodulator, adc_how: str) -> str:
    """After a guessed range: the rails measured as the samples come and what they found."""
    if adc_how != "guessed":
        return ""
    if demodulator.measured_adc_range is None:
        return "; rails measured as the samples come: none found"
    low, high = demodulator.measured_adc_range
    return (f"; rails measured as the samples come: {low:.6g} to {high:.6g}, "
            f"{demodulator.clipped_samples} samples clipped")


def _latched_front_end(demodulator, observer) -> int:
    """The front-end faults latched by the demodulator and by the observer's checks (a
    winding open or shorted)."""
    return demodulator.latched_faults | getattr(observer, "latched_front_end_faults", 0)


def _delay_line(demodulator, expected_delay_deg: Optional[float], unresolved: int, pairs: int) -> str:
    """The summary's line on the carrier: its tracked frequency, the delay chosen, and what the
    half-turn ambiguity was resolved from (or that it was not)."""
    delay = math.degrees(demodulator.carrier_delay_rad) % 360.0
    other = (delay + 180.0) % 360.0
    line = f"carrier tracked at {demodulator.tracked_carrier_hz:.6g} Hz at the end; "
    where = ("after the excitation column" if demodulator.has_excitation
             else "after phase 0 at the first sample (no excitation column)")
    if expected_delay_deg is None:
        return line + (f"carrier delay {where}: {delay:.3f} or {other:.3f} deg, the windings cannot tell which "
                       f"(half a turn of the shaft apart); taken within 90 deg of 0, so every angle is right or "
                       f"half a turn off: all {pairs} rows marked half_turn_unresolved; state the delay with "
                       f"--expected-delay-deg")
    line += (f"carrier delay {where}: {delay:.3f} deg, the half turn taken within 90 deg of "
             f"--expected-delay-deg {expected_delay_deg:g}")
    if unresolved:
        line += (f"; {unresolved} of {pairs} rows marked half_turn_unresolved (the excitation column unusable "
                 f"before it resolved the half turn)")
    return line


def _front_end_names(bits: int) -> str:
    names = [flag.name for flag in angletrack.FrontEndFaults if bits & flag]
    return "|".join(names) if names else "none"
