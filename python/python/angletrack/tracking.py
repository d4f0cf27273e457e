"""``angletrack track``: a capture streamed through an observer in constant memory.

The capture is parsed in Rust (:class:`angletrack.CaptureReader`), each chunk is tracked by
one :class:`angletrack.Observer` whose state carries over, and the estimates are written by
:class:`angletrack.EstimatesWriter` (CSV or ``.npy``) chunk by chunk. Before anything is
written, the capture's sample rate is checked against the gains'; after the last chunk, a
run whose samples were mostly rejected is an error, not a file of zeros.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import pathlib
import sys
import time
from typing import Optional, Union

import numpy as np

import angletrack
from angletrack import capture as capture_io
from angletrack import clipping, export, harmonics, tracker_run
from angletrack._angletrack import CountsExtremes, capture_counts

#: Relative difference of two sample rates taken as the same rate (the time column's
#: spacing check uses the same 1 %).
RATE_TOLERANCE = 0.01
#: The lowest sample rate taken as plausible for a time column: anything slower is a time
#: column in another unit (ms, us, ns) read as seconds.
LOWEST_PLAUSIBLE_RATE_HZ = 1.0


@dataclasses.dataclass
class TrackSettings:
    """What ``angletrack track`` was asked to do (the CLI's arguments, checked)."""

    capture: pathlib.Path
    output: pathlib.Path
    gains_file: Optional[pathlib.Path] = None
    gains: Optional[list] = None
    sample_rate_hz: Optional[float] = None
    columns: Optional[str] = None
    delimiter: Optional[str] = None
    decimal: Optional[str] = None
    skip_rows: int = 0
    time_unit: str = "s"
    dtype: str = "float64"
    sin_cos: Optional[str] = None
    skip_s: float = 0.0
    lock_tolerance_rad: float = 0.01
    progress: bool = False
    chunk_rows: int = 1 << 16
    #: Further ``Observer`` arguments (the online calibration of ``--calibrate``/``--calibration``).
    observer_arguments: dict = dataclasses.field(default_factory=dict)
    # The demodulating path (angletrack.resolver), taken when carrier_hz is given.
    carrier_hz: Optional[float] = None
    samples_per_period: Optional[float] = None
    carrier_amplitude_counts: Optional[float] = None
    expected_delay_deg: Optional[float] = None
    pole_pairs: Optional[int] = None
    latency_s: Optional[float] = None
    #: The angle calibration of ``--calibration`` (from ``angletrack calibrate``), applied by a
    #: ``harmonics.CalibratedObserver``.
    calibration: Optional[harmonics.Calibration] = None
    #: The ADC's range stated by ``--adc-range``/``--adc-bits`` (the capture's units), against
    #: which clipping is flagged (``angletrack.clipping``); ``None``: measured.
    adc_range: Optional[tuple] = None
    #: The counts' signedness stated (``--adc-signed``: ``True``, ``--adc-unsigned``: ``False``,
    #: or by ``--adc-range``; ``clipping.stated_counts``); ``None``: read from the capture.
    adc_signed: Optional[bool] = None
    #: The ADC's resolution stated (``--adc-bits``, or an unsigned ``--adc-range``).
    adc_bits: Optional[int] = None
    #: The gains of a tracker file (``--tracker``), in place of ``gains_file``.
    tracker_gains: Optional[angletrack.Gains] = None
    #: The mid-scale removed from the samples as a tracker file states it; ``None``: the
    #: capture's (:func:`counts_mid_scale`).
    mid_scale: Optional[float] = None
    #: What the samples are divided by after the mid-scale (a tracker file's
    #: ``input.counts_per_unit``).
    counts_per_unit: float = 1.0
    #: The ``--tracker`` file's document and path (``None``: the flags describe the setup).
    tracker_document: Optional[dict] = None
    tracker_file: Optional[str] = None

    def reader_options(self) -> dict:
        """The capture reader's keyword arguments (the capture's layout and rate)."""
        return dict(columns=self.columns, delimiter=self.delimiter, decimal=self.decimal,
                    skip_rows=self.skip_rows, time_unit=self.time_unit, sample_rate_hz=self.sample_rate_hz)

    @functools.cached_property
    def designed_gains(self) -> Optional[angletrack.Gains]:
        """The gains in ``gains_file`` (or the tracker file's) at their designed rate
        (``None`` without one), read once however many steps ask for them."""
        if self.tracker_gains is not None:
            return self.tracker_gains
        if self.gains_file is None:
            return None
        text = capture_io.read_text_file(self.gains_file, "--gains-file")
        # Errors name the file and the field: "g.json: sample_period_s: must be a number, got "x"".
        return export.gains_from_json(text, str(self.gains_file))


def _rate_error(capture_hz: float, gains_hz: float, time_unit: str) -> str:
    ratio = capture_hz / gains_hz
    hint = ""
    for unit, factor in (("ms", 1e3), ("us", 1e6), ("ns", 1e9)):
        if abs(ratio * factor - 1.0) <= RATE_TOLERANCE and time_unit == "s":
            hint = f" (the time column looks like it is in {unit}: give --time-unit {unit})"
    return (
        f"sample_rate: the capture's time column says {capture_hz:.6g} Hz but the gains are "
        f"designed for {gains_hz:.6g} Hz{hint}; design gains for the capture's rate, or state the "
        "true rate with --sample-rate"
    )


def gains_for_capture(s: TrackSettings, capture_rate_hz: Optional[float]) -> angletrack.Gains:
    """The gains to run at the capture's sample rate, refusing a rate that contradicts them."""
    gains = s.designed_gains
    if gains is not None:
        if s.sample_rate_hz is not None:
            return angletrack.Gains(gains.gains, sample_period_s=1.0 / s.sample_rate_hz)
        if capture_rate_hz is not None and abs(capture_rate_hz / gains.sample_rate_hz - 1.0) > RATE_TOLERANCE:
            raise ValueError(_rate_error(capture_rate_hz, gains.sample_rate_hz, s.time_unit))
        return gains
    rate = s.sample_rate_hz if s.sample_rate_hz is not None else capture_rate_hz
    if rate is None:
        raise ValueError("sample_rate: give --sample-rate (the capture has no time column)")
    if s.sample_rate_hz is None and rate < LOWEST_PLAUSIBLE_RATE_HZ:
        raise ValueError(
            f"sample_rate: the capture's time column says {rate:.6g} Hz, too slow for a sensor "
            "capture: is the time column in ms, us or ns? give --time-unit, or --sample-rate"
        )
    return angletrack.Gains(s.gains, sample_period_s=1.0 / rate)


#: A reference column in another unit, as the factor from radians to it: (unit, how to convert).
REFERENCE_UNITS = (("degrees", 180.0 / math.pi, "multiply it by pi/180"),
                   ("turns", 1.0 / (2.0 * math.pi), "multiply it by 2 pi"))


class _ErrorStatistics:
    """Running statistics of the wrapped angle error against a reference, chunk by chunk;
    and the same against the reference read in degrees and in turns, for a hint."""

    def __init__(self, skip_s: float, tolerance_rad: float):
        self.skip_s, self.tolerance_rad = skip_s, tolerance_rad
        self.count, self.total, self.squares, self.largest = 0, 0.0, 0.0, 0.0
        self.start_s: Optional[float] = None
        self.lock_s: Optional[float] = None
        #: (sum, sum of squares) of the error against the reference read in each unit.
        self.in_units = [[0.0, 0.0] for _ in REFERENCE_UNITS]

    def add(self, time_s: np.ndarray, angle: np.ndarray, reference: np.ndarray) -> None:
        if self.start_s is None:
            self.start_s = float(time_s[0])
        error = _wrapped(angle.astype(np.float64) - reference)
        outside = np.flatnonzero(np.abs(error) > self.tolerance_rad)
        if len(outside):
            # Locked from the sample after the last one outside the tolerance, if any.
            after = outside[-1] + 1
            self.lock_s = float(time_s[after]) - self.start_s if after < len(error) else None
        elif self.lock_s is None:
            self.lock_s = float(time_s[0]) - self.start_s
        keep = time_s - self.start_s >= self.skip_s
        kept = error[keep]
        self.count += len(kept)
        self.total += float(np.sum(kept))
        self.squares += float(np.dot(kept, kept))
        self.largest = max(self.largest, float(np.max(np.abs(kept)))) if len(kept) else self.largest
        for sums, (_, per_rad, _) in zip(self.in_units, REFERENCE_UNITS):
            other = _wrapped(angle[keep].astype(np.float64) - reference[keep] / per_rad)
            sums[0] += float(np.sum(other))
            sums[1] += float(np.dot(other, other))

    def _spread(self, total: float, squares: float) -> float:
        """The RMS after removing the mean."""
        return math.sqrt(max(squares / self.count - (total / self.count) ** 2, 0.0))

    def unit_hint(self) -> Optional[str]:
        """A line naming the unit the reference column seems to be in, when the error
        against it read in that unit is a tenth of the error against it read in radians
        and below 0.05 rad; ``None`` otherwise."""
        spread = self._spread(self.total, self.squares)
        for (total, squares), (unit, _, how) in zip(self.in_units, REFERENCE_UNITS):
            other = self._spread(total, squares)
            if other < 0.05 and other < spread / 10:
                return (f"  hint: the reference column looks like {unit}, not radians: read in {unit} it "
                        f"differs from the estimate by {other:.3e} rad RMS after removing the mean; "
                        f"{how} (or convert the column)")
        return None

    def report(self) -> str:
        if self.count == 0:
            raise ValueError(f"skip: --skip {self.skip_s} s leaves no sample of the capture for the statistics")
        rms = math.sqrt(self.squares / self.count)
        lock = "not locked at the end" if self.lock_s is None else f"{self.lock_s:.6g} s"
        hint = self.unit_hint()
        return (
            f"angle error against the reference (after {self.skip_s} s, {self.count} samples):\n"
            f"  RMS {rms:.6e} rad   max {self.largest:.6e} rad   mean {self.total / self.count:+.6e} rad\n"
            f"  RMS after removing the mean {self._spread(self.total, self.squares):.6e} rad\n"
            f"  locked (within {self.tolerance_rad} rad) from: {lock}"
            + ("" if hint is None else "\n" + hint)
        )


def _wrapped(angle: np.ndarray) -> np.ndarray:
    """``angle`` wrapped to [-pi, pi)."""
    return np.remainder(angle + math.pi, 2 * math.pi) - math.pi


class _Progress:
    """A one-line progress report on stderr, refreshed at most twice a second."""

    def __init__(self, enabled: bool):
        self.enabled, self.started, self.shown = enabled, time.monotonic(), 0.0

    def update(self, reader: angletrack.CaptureReader, final: bool = False) -> None:
        now = time.monotonic()
        if not self.enabled or (not final and now - self.shown < 0.5):
            return
        self.shown = now
        done, total = reader.progress_bytes
        percent = f"{100.0 * done / total:5.1f} %" if total and done else "      "
        rate = reader.rows / max(now - self.started, 1e-9)
        end = "\n" if final else ""
        sys.stderr.write(f"\rangletrack track: {percent} {reader.rows:,} samples, {rate / 1e6:.2f} M samples/s{end}")
        sys.stderr.flush()


def _rejections_error(s: TrackSettings, rejected: int, total: int, reader, y_c_mean: float) -> str:
    dtype = reader.sample_dtype
    cause = (
        f"the samples are {dtype} with y_c averaging {y_c_mean:.6g}: raw ADC counts? scale them to "
        "about +-1 (subtract the mid-scale, divide by the amplitude)"
        if dtype.startswith(("int", "uint")) or abs(y_c_mean) > 10
        else "the signals' amplitude is far from 1, or the samples are not finite"
    )
    return (
        f"{s.capture}: {rejected} of {total} samples ({100.0 * rejected / total:.3g} %) were rejected "
        f"as bad samples (fault BAD_SAMPLE), so the estimates in {s.output} mean nothing; {cause}"
    )


def _stated_rate_note(s: TrackSettings) -> list[str]:
    """A line saying that gains designed for another rate run at the stated one."""
    if s.designed_gains is None or s.sample_rate_hz is None:
        return []
    designed_hz = s.designed_gains.sample_rate_hz
    if abs(s.sample_rate_hz / designed_hz - 1.0) <= RATE_TOLERANCE:
        return []
    return [
        f"note: the gains designed for {designed_hz:.6g} Hz run at the stated {s.sample_rate_hz:.6g} Hz: "
        f"the loop's bandwidth scales by {s.sample_rate_hz / designed_hz:.6g}"
    ]


#: A channel whose range's middle is further than this fraction of its half-range from zero
#: is noted as off-centre by a plain ``track`` (the online calibration finds the centre).
OFF_CENTRE_FRACTION = 0.25


class _Ranges:
    """Running ranges of the two channels as tracked (after the mid-scale), chunk by chunk."""

    def __init__(self):
        self.low = [math.inf, math.inf]
        self.high = [-math.inf, -math.inf]

    def add(self, y_c: np.ndarray, y_s: np.ndarray) -> None:
        for k, y in enumerate((y_c, y_s)):
            finite = y[np.isfinite(y)]
            if len(finite):
                self.low[k] = min(self.low[k], float(np.min(finite)))
                self.high[k] = max(self.high[k], float(np.max(finite)))

    def off_centre_note(self) -> list[str]:
        """A note when either channel's range is centred off zero by more than
        :data:`OFF_CENTRE_FRACTION` of its half-range: signals on a bias, which the loop
        (centred on zero) tracks wrongly if the capture holds a whole turn."""
        centres = [(lo + hi) / 2 for lo, hi in zip(self.low, self.high)]
        halves = [(hi - lo) / 2 for lo, hi in zip(self.low, self.high)]
        if not all(math.isfinite(h) and h > 0 for h in halves):
            return []
        if all(abs(c) <= OFF_CENTRE_FRACTION * h for c, h in zip(centres, halves)):
            return []
        return [
            f"note: the signals' ranges are centred at ({centres[0]:.6g}, {centres[1]:.6g}), half-ranges "
            f"({halves[0]:.6g}, {halves[1]:.6g}): if the capture holds a whole turn the signals are biased and "
            "the angle is wrong; --calibrate finds each channel's centre"
        ]


def counts_mid_scale(s: TrackSettings, sample_dtype: str, whole: Optional[tuple] = None) -> float:
    """The mid-scale removed from the capture ``s.capture`` of ``sample_dtype``: 0 for floats;
    for whole counts, the crate's rule (``angletrack::capture_counts``): the signedness and
    resolution stated (``s.adc_signed``, ``s.adc_bits``), else read from the whole capture,
    which is then read once more, chunk by chunk, for its extremes (``whole``: the arrays of a
    capture held in memory, read instead); a capture that does not
    show its signedness is refused, naming ``--adc-signed`` and ``--adc-unsigned``. The loop
    needs the signal centred on zero, not scaled (it is amplitude-invariant)."""
    if not sample_dtype.startswith(("int", "uint")):
        return 0.0
    extremes = CountsExtremes()
    if s.adc_signed is None or (not s.adc_signed and s.adc_bits is None):
        blocks = [whole] if whole is not None else (
            (chunk.y_c, chunk.y_s)
            for chunk in angletrack.CaptureReader(s.capture, **s.reader_options(), chunk_rows=s.chunk_rows))
        for y_c, y_s in blocks:
            extremes.add(np.ascontiguousarray(y_c, dtype=np.float64), np.ascontiguousarray(y_s, dtype=np.float64))
    _, mid = capture_counts(extremes, signed=s.adc_signed, bits=s.adc_bits,
                            unsigned_type=sample_dtype.startswith("uint"),
                            state_with="give --adc-signed or --adc-unsigned")
    return float(mid)


def finishing_checks(s: TrackSettings, observer, stats: Optional[_ErrorStatistics]) -> list[str]:
    """The checks at the end of the capture, made inside the writer's block so that a run
    they refuse leaves no estimates (the writer discards its temporary file): ``--calibrate``
    learned a turn, ``--skip`` leaves samples for the statistics. Returns the statistics'
    lines (none without a reference)."""
    if s.observer_arguments.get("calibration") == "learn":
        from angletrack import calibration as calibration_io

        calibration_io.check_learned(observer)
    return [] if stats is None else [stats.report()]


def track_capture(s: TrackSettings) -> tuple[str, Union[angletrack.Observer, angletrack.FixedObserver, harmonics.CalibratedObserver]]:
    """Runs ``s``: writes the estimates to ``s.output`` and returns the summary to print and
    the observer at the end of the capture (its learned calibration, its faults; for
    carrier-modulated windings the observer of the demodulated pairs, which go through the
    same calibration stages as y_c, y_s samples).
    Raises ``ValueError`` (``CaptureError``, ``ConfigError``) on a capture that cannot be
    tracked, before anything is written where it can be told before, else leaving no
    estimates (:func:`finishing_checks`)."""
    if s.dtype == "fixed":
        from angletrack import fixed_tracking

        refused = fixed_tracking.refusal(s)
        if refused is not None:
            raise ValueError(refused)
    if s.carrier_hz is not None or s.pole_pairs is not None or s.latency_s is not None:
        from angletrack import resolver

        if s.carrier_hz is None:
            raise ValueError("pole_pairs: --pole-pairs and --latency need --carrier-hz (the resolver path)")
        if s.tracker_document is not None:
            from angletrack.tracker import Tracker

            # The resolver path's observers run a part of what a tracker file holds.
            Tracker(s.tracker_document, s.tracker_file or "tracker").track_settings(strict=True)
        if s.tracker_gains is not None and (s.mid_scale or s.counts_per_unit != 1.0):
            raise ValueError("input: with --carrier-hz the capture holds raw windings, demodulated into pairs "
                             "of amplitude 1: the tracker file's input mid_scale, bits or counts_per_unit do not "
                             'apply; give input {"kind": "counts"} or {"kind": "units"}')
        if s.observer_arguments.get("winding_amplitude", 1.0) != 1.0:
            raise ValueError("winding_check: with --carrier-hz the windings are checked on the demodulated pairs, "
                             "whose envelope is 1: give {\"amplitude\": 1.0} or null")
        return resolver.track_windings(s)
    reader = angletrack.CaptureReader(
        s.capture, **s.reader_options(), chunk_rows=s.chunk_rows,
    )
    chunks = iter(reader)
    first = next(chunks)
    gains = gains_for_capture(s, reader.sample_rate_hz if first.time_s is not None else None)
    stats = _ErrorStatistics(s.skip_s, s.lock_tolerance_rad) if first.reference_rad is not None else None
    integer = reader.sample_dtype.startswith(("int", "uint"))
    if s.dtype == "fixed" and not integer:
        raise ValueError(f"dtype: --dtype fixed takes integer ADC counts; {s.capture} holds {reader.sample_dtype} "
                         "samples (use --dtype float32 or float64)")
    mid = _mid_scale(s, reader.sample_dtype) if integer else 0.0
    run = tracker_run.Run(s, gains, reader.sample_dtype, first, mid)
    if s.dtype == "fixed":
        from angletrack import fixed_tracking

        columns = fixed_tracking.COLUMNS
    else:
        columns = capture_io.estimate_columns(np.dtype(s.dtype))
    progress = _Progress(s.progress)
    rejected, y_c_sum, flagged = 0, 0.0, 0
    ranges = _Ranges()
    bad, front_end = int(angletrack.Faults.BAD_SAMPLE), int(angletrack.Faults.FRONT_END)
    s.output.parent.mkdir(parents=True, exist_ok=True)
    # A fault found part way (a malformed row, an interrupt) leaves no partial file that could
    # pass for the estimates of the whole capture: the writer discards its temporary file.
    with angletrack.TableWriter(s.output, columns) as writer:
        chunk = first
        while chunk is not None:
            rows = run.track(chunk.y_c, chunk.y_s)
            time_s = chunk.time_s
            if time_s is None:
                time_s = (chunk.first_sample + np.arange(len(chunk), dtype=np.float64)) * gains.sample_period_s
            rows["time_s"] = time_s
            writer.write([np.ascontiguousarray(rows[name], dtype=dtype) for name, dtype in columns])
            faults = rows["faults"]
            rejected += int(np.count_nonzero(faults & bad))
            flagged += int(np.count_nonzero(faults & front_end))
            y_c_sum += float(np.sum(chunk.y_c))
            # The samples the observer used: a rejected outlier says nothing of a bias.
            used = (faults & bad) == 0
            ranges.add(chunk.y_c[used] - mid, chunk.y_s[used] - mid)
            if stats is not None:
                stats.add(time_s, rows["angle_rad"], chunk.reference_rad)
            progress.update(reader)
            chunk = next(chunks, None)
        progress.update(reader, final=True)
        total = reader.rows
        # Refused inside the block: no estimates are left behind.
        if 2 * rejected > total:
            raise ValueError(_rejections_error(s, rejected, total, reader, y_c_sum / total))
        statistics = finishing_checks(s, run, stats)
    latched = angletrack.Faults(run.latched_faults)
    lines = [
        f"{run!r} ({run.file})",
        *_stated_rate_note(s),
        f"{total} samples ({reader.format}, {reader.sample_dtype}; columns "
        + ", ".join(f"{k}={v}" for k, v in reader.columns.items())
        + f") -> {s.output}",
        f"faults latched: {latched.name if latched else 'none'}; {rejected} samples rejected",
    ]
    lines.append(f"{clipping.describe(s.adc_range, s.adc_range is not None)}: {flagged} samples clipped "
                 "(flagged FRONT_END; those clipped in both channels coasted through)")
    if run.document["calibration"]["kind"] == "none":
        lines += ranges.off_centre_note()
    return "\n".join(lines + statistics), run


def _scaled(s: TrackSettings, y: np.ndarray, mid: float) -> np.ndarray:
    """Samples as the observer takes them: minus the mid-scale, over ``counts_per_unit``."""
    return y - mid if s.counts_per_unit == 1.0 else (y - mid) / s.counts_per_unit


def _mid_scale(s: TrackSettings, sample_dtype: str, whole: Optional[tuple] = None) -> float:
    """The mid-scale removed: the tracker file's, else the capture's by the crate's rule
    (:func:`counts_mid_scale`; ``whole``: the arrays of a capture held in memory, else the
    file ``s.capture`` is read). Unsigned counts tracked as units or signed counts by a
    tracker file are refused: their mid-scale would be left in."""
    if s.mid_scale is None:
        return counts_mid_scale(s, sample_dtype, whole)
    if s.tracker_gains is not None and s.mid_scale == 0.0 and _shows_unsigned(s, sample_dtype, whole):
        raise ValueError(f"input: the tracker file says units or signed counts, but {s.capture} holds unsigned "
                         f"{sample_dtype} counts: set its input to {{\"kind\": \"counts\"}} (the mid-scale "
                         "measured) or state bits or mid_scale")
    return s.mid_scale


def _shows_unsigned(s: TrackSettings, sample_dtype: str, whole: Optional[tuple]) -> bool:
    """Whether the capture's whole counts are offset binary by the crate's rule read from
    the capture alone (an unsigned dtype, or both channels swinging across one mid-scale
    with no negative sample); a capture that shows neither is taken as the tracker file
    states it."""
    if not sample_dtype.startswith(("int", "uint")):
        return False
    try:
        unstated = dataclasses.replace(s, adc_signed=None, adc_bits=None)
        return counts_mid_scale(unstated, sample_dtype, whole) != 0.0
    except ValueError:
        return False


def calibrate_capture(s: TrackSettings, reference_ratio: int = 1, **options) -> harmonics.Calibration:
    """``angletrack calibrate``: the :class:`harmonics.Calibration` learned from the capture
    ``s.capture`` (``s.columns``, ``s.delimiter``, ``s.time_unit``), read twice in chunks in
    constant memory (:func:`harmonics.calibrate_chunks`, whose ``options`` these are), the
    reference column in the sensor's turns (times ``reference_ratio``, a whole number: the
    pole pairs of a mechanical reference, negative for one counting the other way), with
    the gains of ``s`` at its sample rate (checked as for :func:`track_capture`). Unsigned
    counts are centred first (:func:`counts_mid_scale`), as ``track`` centres them, so that
    the offsets learned are the ones ``track --calibration`` (float or fixed) sees; the
    amplitude is the capture's own (counts, volts or normalised)."""

    def reader() -> angletrack.CaptureReader:
        return angletrack.CaptureReader(s.capture, **s.reader_options(), chunk_rows=s.chunk_rows)

    first_reader = reader()
    first = next(iter(first_reader))
    gains = gains_for_capture(s, first_reader.sample_rate_hz if first.time_s is not None else None)
    mid = _mid_scale(s, first_reader.sample_dtype)
    del first_reader, first

    def chunks():
        for chunk in reader():
            reference = chunk.reference_rad
            # A whole ratio keeps a wrapped reference's jumps whole turns.
            if reference is not None and reference_ratio != 1:
                reference = reference * float(reference_ratio)
            yield _scaled(s, chunk.y_c, mid), _scaled(s, chunk.y_s, mid), reference

    return harmonics.calibrate_chunks(chunks, gains, **options)
