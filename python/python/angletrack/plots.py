"""``angletrack plot`` (and ``angletrack track --plot``): one figure of what an engineer looks
at in a capture, computed chunk by chunk in constant memory (:mod:`angletrack.capture_analysis`):

* the Lissajous figure of (y_c, y_s) with the least-squares ellipse, its offsets, amplitude
  ratio and quadrature;
* the angle error ``atan2(y_s, y_c) - reference`` against the electrical angle and its
  harmonic spectrum (orders 1 to 10), against the capture's reference column, or against the
  observer's own angle when there is none (the sensor's angle-dependent errors lie above the
  loop's bandwidth, so the observer does not follow them), counted from the observer's lock:
  its start-up from rest is no error of the sensor (shaded on the time axes, and counted
  with ``include_start_up``);
* the speed over time (the observer's, else the reference's differences), min and max per
  point drawn;
* the observer's fault flags over time, one row per flag, each raised span at least
  :data:`MIN_FAULT_PX` wide.

Scatters are thinned to a uniform random subsample (every n-th point would alias with the
capture's samples per turn); every figure's number uses every sample.
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
from typing import Optional

import numpy as np

import angletrack
from angletrack import tracker_run, tracking
from angletrack.capture_analysis import (
    HARMONIC_ORDERS,
    WIDEST_GAP,
    AngleErrorBins,
    ConicMoments,
    EllipseFit,
    Envelope,
    LOCK_BLOCKS_PER_TIME_CONSTANT,
    LOCK_HOLD_TIME_CONSTANTS,
    LockDetector,
    RandomSample,
    slowest_time_constant_samples,
    wrap,
)

#: Most points drawn per series: a 1e7-row capture is decimated to this.
MAX_POINTS = 200_000
#: Size of the figure (inches) and its resolution (dots per inch).
FIGURE_SIZE_IN = (15.0, 10.5)
DPI = 100


#: Narrowest fault span drawn (pixels): a fault of one sample shows on any capture length.
MIN_FAULT_PX = 2.0
#: How the start-up is treated, in words for the figure and the terminal.
START_UP_WORDS = {
    "skipped": "the observer's start-up until lock left out",
    "included": "the observer's start-up included (--include-start-up)",
    "never locked": "the observer never locked: the start-up is included",
}


@dataclasses.dataclass
class CaptureAnalysis:
    """Everything the figure draws, accumulated over the whole capture. Times are seconds
    from the first sample (samples without a time column or a rate)."""

    path: str
    rows: int
    description: str
    fit: Optional[EllipseFit]
    lissajous: RandomSample
    #: What the error is measured against, in words; ``None`` when there is nothing to
    #: measure against (no reference column, no gains).
    reference: Optional[str]
    #: The angle error after ``--skip`` and, against the observer's angle, after its lock.
    errors_after_lock: AngleErrorBins
    #: The angle error after ``--skip``, the observer's start-up included.
    errors_with_start_up: AngleErrorBins
    #: (time, electrical angle, error) of a random subsample of the samples after ``--skip``.
    error_scatter: RandomSample
    #: Where the speed comes from, in words, or ``None``.
    speed_source: Optional[str]
    speed: Envelope
    #: ``{flag name: envelope of 0/1}``, empty without an observer.
    faults: dict[str, Envelope]
    #: The time axis' unit: ``s``, or ``sample`` without a time column or a rate.
    time_unit: str
    #: ``None`` (the error is against a reference column, or there is none), or a key of
    #: :data:`START_UP_WORDS`.
    start_up: Optional[str] = None
    #: Time of the observer's lock, ``None`` without one.
    lock_s: Optional[float] = None
    #: The lock's criterion: the error within ``lock_tolerance_rad`` for ``lock_hold_s``.
    lock_tolerance_rad: float = 0.0
    lock_hold_s: float = 0.0
    #: ``--skip``, and the last sample's time.
    skip_s: float = 0.0
    last_s: float = 0.0

    @property
    def errors(self) -> AngleErrorBins:
        """The error the figures count: after the lock unless the start-up is included."""
        return self.errors_after_lock if self.start_up == "skipped" else self.errors_with_start_up

    @property
    def statistics_from_s(self) -> float:
        """Where the counted error starts (the figure shades what is before)."""
        if self.start_up == "skipped" and self.lock_s is not None:
            return max(self.skip_s, self.lock_s)
        return self.skip_s

    def _counted(self) -> str:
        unit = "s" if self.time_unit == "s" else "samples"
        words = [f"from {self.statistics_from_s:.4g} {unit}" if self.statistics_from_s > 0 else "from the start"]
        if self.start_up is not None:
            words.append(START_UP_WORDS[self.start_up])
        return "; ".join(words)

    def summary(self) -> dict:
        """The figures as plain numbers (the ``--out`` directory's JSON)."""
        fit = dataclasses.asdict(self.fit) if self.fit else None
        if fit:
            fit["amplitude_ratio"] = self.fit.amplitude_ratio
        result = {"capture": self.path, "rows": self.rows, "ellipse": fit, "error_reference": self.reference,
                  "start_up": self.start_up, "lock_s": self.lock_s, "statistics_from_s": self.statistics_from_s}
        if self.reference is not None and self.errors.count:
            result["angle_error_rms_rad"] = self.errors.rms_rad()
        if self.reference is not None and self.errors.count and self.errors.widest_gap() <= WIDEST_GAP:
            result["harmonics_rad"] = dict(zip(map(str, HARMONIC_ORDERS), self.errors.harmonics_rad().tolist()))
        return result

    def describe(self) -> str:
        """A few lines for the terminal."""
        lines = [self.description, "ellipse: " + (self.fit.describe() if self.fit else "no ellipse fits the samples")]
        if self.reference is not None and self.errors.count and self.errors.widest_gap() <= WIDEST_GAP:
            harmonics = self.errors.harmonics_rad()
            top = sorted(zip(HARMONIC_ORDERS, harmonics), key=lambda kv: -kv[1])[:3]
            lines.append(
                f"angle error against {self.reference} ({self._counted()}): RMS {1e3 * self.errors.rms_rad():.4g} "
                "mrad; largest harmonics " + ", ".join(f"{k}: {1e3 * a:.3g} mrad" for k, a in top)
            )
        return "\n".join(lines)


def _lock_detector(gains: angletrack.Gains, tolerance_rad: float) -> LockDetector:
    """The lock of the observer of ``gains``: its error's block means within the tolerance
    for :data:`LOCK_HOLD_TIME_CONSTANTS` time constants of the loop."""
    tau = slowest_time_constant_samples(gains.loop_polynomial)
    if not math.isfinite(tau):
        return LockDetector(tolerance_rad, 1)
    block = int(tau / LOCK_BLOCKS_PER_TIME_CONSTANT)
    return LockDetector(tolerance_rad, int(math.ceil(LOCK_HOLD_TIME_CONSTANTS * tau)), block)


def analyse_capture(
    s: tracking.TrackSettings, max_points: int = MAX_POINTS, *, include_start_up: bool = False
) -> CaptureAnalysis:
    """Reads ``s.capture`` chunk by chunk, runs the observer when gains are given (checked
    against the capture's rate as ``angletrack track`` does) and accumulates the figure's
    data. Against the observer's angle, the error counts from the observer's lock (its error,
    averaged over blocks of an eighth of the loop's time constant, within
    ``s.lock_tolerance_rad`` for :data:`LOCK_HOLD_TIME_CONSTANTS` time constants) unless
    ``include_start_up``; ``s.skip_s`` leaves out the first seconds in
    every case. ``s.output`` is not used."""
    reader = angletrack.CaptureReader(
        s.capture, **s.reader_options(), chunk_rows=s.chunk_rows,
    )
    chunks = iter(reader)
    first = next(chunks)
    # Counts centred as `angletrack track` centres them (the same rule): the figure shows
    # what the observer sees.
    integer = reader.sample_dtype.startswith(("int", "uint"))
    mid = tracking._mid_scale(s, reader.sample_dtype) if integer else 0.0
    observer = None
    lock = None
    if s.gains_file is not None or s.gains is not None:
        gains = tracking.gains_for_capture(s, reader.sample_rate_hz if first.time_s is not None else None)
        # The chain `angletrack track` runs (the crate's TrackerRun), so that the figure draws
        # the estimates it writes, in fixed point too.
        observer = tracker_run.Run(s, gains, reader.sample_dtype, first, mid)
        rate_hz: Optional[float] = gains.sample_rate_hz
        if first.reference_rad is None:
            lock = _lock_detector(gains, s.lock_tolerance_rad)
    else:
        rate_hz = reader.sample_rate_hz
    reference = (
        "the reference column" if first.reference_rad is not None
        else "the observer's angle (no reference column)" if observer is not None else None
    )
    a = CaptureAnalysis(
        path=str(s.capture), rows=0, description="", fit=None, lissajous=RandomSample(max_points),
        reference=reference, errors_after_lock=AngleErrorBins(), errors_with_start_up=AngleErrorBins(),
        error_scatter=RandomSample(max_points),
        speed_source=("the observer" if observer is not None
                      else "the reference's differences" if first.reference_rad is not None else None),
        speed=Envelope(max_points),
        faults={name: Envelope(max_points) for name, _ in angletrack.FAULT_BITS} if observer else {},
        time_unit="s" if (first.time_s is not None or rate_hz) else "sample",
        skip_s=s.skip_s,
    )
    if lock is not None:
        a.lock_tolerance_rad, a.lock_hold_s = lock.tolerance_rad, lock.hold / rate_hz
    moments = ConicMoments()
    previous: Optional[tuple[float, float]] = None  # (time, reference) of the last sample
    start: Optional[float] = None
    chunk = first
    while chunk is not None:
        n = len(chunk)
        index = chunk.first_sample + np.arange(n, dtype=np.float64)
        time_s = chunk.time_s if chunk.time_s is not None else (index / rate_hz if rate_hz else index)
        start = float(time_s[0]) if start is None else start
        time_s = time_s - start
        y_c, y_s = chunk.y_c - mid, chunk.y_s - mid
        moments.add(y_c, y_s)
        a.lissajous.add(y_c, y_s)
        angle = chunk.reference_rad
        if observer is not None:
            est = observer.track(chunk.y_c, chunk.y_s)
            angle = est["angle_rad"] if angle is None else angle
            a.speed.add(time_s, est["speed_rad_s"])
            for name, bit in angletrack.FAULT_BITS:
                a.faults[name].add(time_s, (est["faults"] & bit) != 0)
        elif chunk.reference_rad is not None:
            t = np.concatenate([[previous[0]], time_s]) if previous else time_s
            r = np.concatenate([[previous[1]], chunk.reference_rad]) if previous else chunk.reference_rad
            if len(r) > 1:
                a.speed.add(t[1:], wrap(np.diff(r)) / np.diff(t))
            previous = (float(time_s[-1]), float(chunk.reference_rad[-1]))
        if angle is not None:
            error = wrap(np.arctan2(y_s, y_c) - angle)
            locked = np.ones(n, dtype=bool)
            if lock is not None:
                was_locked = lock.lock_index is not None
                locked = lock.add(chunk.first_sample, error)
                if not was_locked and lock.lock_index is not None:
                    a.lock_s = float(time_s[lock.lock_index - chunk.first_sample])
            kept = time_s >= s.skip_s
            electrical = np.remainder(angle, 2 * math.pi)
            a.errors_with_start_up.add(electrical[kept], error[kept])
            a.errors_after_lock.add(electrical[kept & locked], error[kept & locked])
            a.error_scatter.add(time_s[kept], electrical[kept], error[kept])
        a.rows += n
        a.last_s = float(time_s[-1])
        chunk = next(chunks, None)
    if lock is not None:
        a.start_up = "included" if include_start_up else "skipped" if a.lock_s is not None else "never locked"
    a.fit = moments.fit()
    a.description = (
        f"{a.rows} samples ({reader.format}, {reader.sample_dtype}; columns "
        + ", ".join(f"{k}={v}" for k, v in reader.columns.items()) + ")"
        + (f"; unsigned ADC counts: mid-scale {mid:g} removed" if mid else "")
    )
    return a


def _lissajous(ax, a: CaptureAnalysis) -> None:
    y_c, y_s = a.lissajous.points()
    ax.plot(y_c, y_s, ".", ms=1.5, color="tab:blue", alpha=0.3, rasterized=True,
            label=f"samples ({len(y_c):,} of {a.rows:,}, at random)")
    if a.fit is not None:
        f = a.fit
        ax.plot(*f.points(), color="tab:red", lw=1.5, label=(
            f"least-squares ellipse\noffsets y_c {f.offset_cos:+.4f}, y_s {f.offset_sin:+.4f}\n"
            f"amplitudes {f.amplitude_cos:.4g}, {f.amplitude_sin:.4g}\namplitude ratio a_s/a_c {f.amplitude_ratio:.4f}\n"
            f"quadrature {1e3 * f.quadrature_rad:+.2f} mrad"
        ))
        radius = 0.5 * (f.amplitude_cos + f.amplitude_sin)
        circle = np.linspace(0.0, 2 * math.pi, 361)
        ax.plot(radius * np.cos(circle), radius * np.sin(circle), color="0.4", ls="--", lw=0.8,
                label="circle of the mean amplitude\nabout the origin")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("y_c (the capture's units)")
    ax.set_ylabel("y_s (the capture's units)")
    ax.set_title("Lissajous of (y_c, y_s)")
    ax.grid(alpha=0.3)
    # The ring's inside is empty on any usable capture: the legend goes there.
    ax.legend(loc="center", fontsize=7.5, framealpha=0.85, markerscale=6)


def _no_data(ax, text: str) -> None:
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, fontsize=10, color="0.3", wrap=True)
    ax.set_xticks([]), ax.set_yticks([])


def _angle_error(ax_error, ax_spectrum, a: CaptureAnalysis) -> None:
    if a.reference is None or a.errors.count == 0:
        text = ("no reference column and no gains:\ngive --gains-file to measure the angle error\n"
                "against the observer's angle") if a.reference is None else "no sample left to measure\n(--skip)"
        for ax in (ax_error, ax_spectrum):
            _no_data(ax, text)
        return
    time_s, angle, error = a.error_scatter.points()
    # A bad sample (NaN) has no error to draw.
    counted = (time_s >= a.statistics_from_s) & np.isfinite(error)
    angle, error = angle[counted], error[counted]
    ax_error.plot(np.degrees(angle), 1e3 * error, ".", ms=1, color="0.6", alpha=0.3, rasterized=True,
                  label="samples (at random)")
    filled = a.errors.counts > 0
    mean = a.errors.mean_error_rad()[filled]
    # A line only where the gaps between the filled bins are narrow enough to bridge.
    style = {"lw": 0.9} if a.errors.widest_gap() <= WIDEST_GAP else {"ls": "none", "marker": "o", "ms": 3}
    ax_error.plot(np.degrees(a.errors.centres_rad()[filled]), 1e3 * mean, color="k", label="mean per 0.5 degree",
                  **style)
    lo, hi = np.percentile(1e3 * error, [0.5, 99.5]) if len(error) else (-1.0, 1.0)
    lo, hi = min(lo, 1e3 * mean.min()), max(hi, 1e3 * mean.max())
    pad = 0.15 * (hi - lo) + 1e-6
    ax_error.set_ylim(lo - pad, hi + pad)
    ax_error.set_xlim(0, 360)
    ax_error.set_xticks(range(0, 361, 45))
    ax_error.set_xlabel("electrical angle (deg)")
    ax_error.set_ylabel("angle error (mrad)")
    ax_error.set_title(f"atan2(y_s, y_c) - {a.reference}\nRMS {1e3 * a.errors.rms_rad():.3g} mrad, {a._counted()}",
                       fontsize=9)
    ax_error.grid(alpha=0.3)
    ax_error.legend(loc="upper right", fontsize=7.5, framealpha=0.85, markerscale=6)

    amplitudes = 1e3 * a.errors.harmonics_rad()
    if not np.isfinite(amplitudes).all():
        _no_data(ax_spectrum, f"no spectrum: {100 * a.errors.widest_gap():.0f} % of the\n"
                 "electrical turn has no sample\n(a capture of a whole turn has one)")
        return
    bars = ax_spectrum.bar(HARMONIC_ORDERS, amplitudes, color="tab:purple", width=0.6)
    # Every bar labelled, so that one too small to see still reads. Upright: ten of them
    # side by side would run into each other.
    ax_spectrum.bar_label(bars, fmt="%.2g", fontsize=7.5, padding=3, rotation=90)
    ax_spectrum.set_xticks(HARMONIC_ORDERS)
    ax_spectrum.set_ylim(0, 1.25 * max(float(np.nanmax(amplitudes)), 1e-6))
    ax_spectrum.set_xlabel("harmonic order of the electrical angle")
    ax_spectrum.set_ylabel("amplitude (mrad, peak)")
    ax_spectrum.set_title("Harmonics of the angle error", fontsize=10)
    ax_spectrum.grid(alpha=0.3, axis="y")


def _envelope_line(ax, env: Envelope, **style) -> None:
    """Draws a min/max envelope as one line through each block's low and high."""
    t, low, high = env.series()
    ax.plot(np.repeat(t, 2), np.column_stack([low, high]).ravel(), **style)


def _time_label(a: CaptureAnalysis) -> str:
    return "time from the first sample (" + ("s)" if a.time_unit == "s" else "samples)")


def fault_spans(env: Envelope, last_s: float, min_width: float) -> list[tuple[float, float]]:
    """The (start, width) of each run of raised blocks of a 0/1 envelope, each at least
    ``min_width`` wide (a run ends where the next block starts, the last at ``last_s``)."""
    t, _, high = env.series()
    ends = np.append(t[1:], max(last_s, t[-1])) if len(t) else t
    raised = np.flatnonzero(high > 0)
    if len(raised) == 0:
        return []
    # Runs of consecutive raised blocks.
    breaks = np.flatnonzero(np.diff(raised) > 1)
    firsts = np.concatenate([[raised[0]], raised[breaks + 1]])
    lasts = np.concatenate([raised[breaks], [raised[-1]]])
    return [(float(t[i]), max(float(ends[j] - t[i]), min_width)) for i, j in zip(firsts, lasts)]


def _shade_skipped(ax, a: CaptureAnalysis) -> None:
    if a.statistics_from_s > 0 and a.reference is not None:
        ax.axvspan(0.0, a.statistics_from_s, color="0.88", zorder=0, lw=0)


def _speed_and_faults(ax_speed, ax_faults, a: CaptureAnalysis) -> None:
    label = _time_label(a)
    for ax in (ax_speed, ax_faults):
        ax.set_xlim(0.0, max(a.last_s, 1e-12))
    if a.speed_source is None:
        _no_data(ax_speed, "no gains and no reference column: give --gains-file to see the speed")
    else:
        _envelope_line(ax_speed, a.speed, color="tab:blue", lw=0.8)
        unit = "rad/sample" if a.time_unit == "sample" else "rad/s"
        ax_speed.set_ylabel(f"speed ({unit})")
        ax_speed.set_xlabel(label)
        title = f"Speed from {a.speed_source} (electrical, min and max per point drawn)"
        if a.statistics_from_s > 0 and a.reference is not None:
            title += f"; shaded: left out of the angle error ({a._counted()})"
        ax_speed.set_title(title, fontsize=10)
        ax_speed.grid(alpha=0.3)
        _shade_skipped(ax_speed, a)
    if not a.faults:
        _no_data(ax_faults, "fault flags: give --gains-file to run the observer")
        return
    names = list(a.faults)
    for row, name in enumerate(names):
        ax_faults.axhline(row, color="0.85", lw=0.5, zorder=0)
    ax_faults.set_yticks(range(len(names)), names, fontsize=8)
    ax_faults.set_ylim(-0.6, len(names) - 0.4)
    ax_faults.set_xlabel(label)
    ax_faults.set_ylabel("flag")
    ax_faults.set_title(f"Fault flags of the observer (red: raised, drawn at least {MIN_FAULT_PX:.0f} pixels wide)",
                        fontsize=10)
    _shade_skipped(ax_faults, a)


def _draw_faults(ax_faults, a: CaptureAnalysis) -> None:
    """The fault spans, once the axes' size in pixels is final."""
    left, right = ax_faults.get_xlim()
    min_width = MIN_FAULT_PX * (right - left) / max(ax_faults.get_window_extent().width, 1.0)
    for row, name in enumerate(a.faults):
        spans = fault_spans(a.faults[name], a.last_s, min_width)
        if spans:
            ax_faults.broken_barh(spans, (row - 0.35, 0.7), color="tab:red", lw=0)


def draw_capture(plt, a: CaptureAnalysis):
    """The figure of ``a`` (a matplotlib ``Figure``, laid out; the caller closes it)."""
    fig = plt.figure(figsize=FIGURE_SIZE_IN)
    grid = fig.add_gridspec(3, 3, height_ratios=[3.2, 1.5, 1.2])
    ax_lissajous = fig.add_subplot(grid[0, 0])
    ax_error = fig.add_subplot(grid[0, 1])
    ax_spectrum = fig.add_subplot(grid[0, 2])
    ax_speed = fig.add_subplot(grid[1, :])
    ax_faults = fig.add_subplot(grid[2, :])
    _lissajous(ax_lissajous, a)
    _angle_error(ax_error, ax_spectrum, a)
    _speed_and_faults(ax_speed, ax_faults, a)
    fig.suptitle(f"{pathlib.Path(a.path).name}: {a.description}", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.975))
    if a.faults:
        _draw_faults(ax_faults, a)
    return fig


def plot_capture(plt, a: CaptureAnalysis, path: pathlib.Path) -> None:
    """Draws the figure of ``a`` into ``path`` (PNG)."""
    fig = draw_capture(plt, a)
    path.parent.mkdir(parents=True, exist_ok=True)
    with angletrack.OutputFile(path) as target:  # all or nothing
        fig.savefig(target.temporary_path, dpi=DPI, format="png")
    plt.close(fig)


def pyplot(hint: str = ""):
    """matplotlib's pyplot on the file-only Agg backend, or a one-line ``RuntimeError``
    saying how to get it (then ``hint``)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise RuntimeError(f"plotting needs matplotlib: pip install 'angletrack[plot]'{hint}") from None
    return plt


def plot_capture_file(
    s: tracking.TrackSettings, png: pathlib.Path, *, summary_json: Optional[pathlib.Path] = None,
    max_points: int = MAX_POINTS, include_start_up: bool = False,
) -> str:
    """Analyses ``s.capture`` (:func:`analyse_capture`), writes the figure to ``png`` (and the
    figures' numbers to ``summary_json``); returns the lines to print."""
    plt = pyplot()
    if png.suffix.lower() != ".png":
        raise ValueError(f"plot: {png} is not a .png file name")
    a = analyse_capture(s, max_points, include_start_up=include_start_up)
    if a.reference is not None and a.rows and a.last_s < s.skip_s:
        # As track refuses it: a figure without its angle error is not what was asked for.
        raise ValueError(f"skip: --skip {s.skip_s:g} s leaves no sample of the capture ({a.last_s:.6g} "
                         f"{'s' if a.time_unit == 's' else 'samples'} long) for the angle error")
    plot_capture(plt, a, png)
    lines = [a.describe(), f"plot: {png}"]
    if summary_json is not None:
        angletrack.write_output(summary_json, json.dumps(a.summary(), indent=2) + "\n")
        lines.append(f"figures: {summary_json}")
    return "\n".join(lines)
