"""``angletrack lot``: every end-of-line capture of a production lot calibrated and tracked
on Dask, one row per capture, and the lot's outliers.

Each capture is calibrated as ``angletrack calibrate --tracker`` calibrates it (the same
function, with its checks) and tracked with what was learned as ``angletrack track
--tracker`` tracks it (the same observer setup; the estimates counted, not written). A
capture that fails is a row with its error, never a stopped lot. The outliers are the
units beyond stated limits or beyond the lot's own spread (the crate's
``angletrack::lot::outliers``).
"""

from __future__ import annotations

import dataclasses
import glob
import math
import pathlib
import time
from typing import Optional, Sequence

import numpy as np

import angletrack
from angletrack import _angletrack, harmonics, tracker_run, tracking
from angletrack.tracker import Tracker

#: The sensor calibration's columns, in ``SensorCalibration::new``'s order.
SENSOR_COLUMNS = ("offset_c", "offset_s", "amplitude_c", "amplitude_s", "quadrature_rad")
#: The columns the outlier report looks at by default: the sensor calibration, the residual.
SCREENED = SENSOR_COLUMNS + ("residual_rms_rad",)
#: A unit further from the lot's median than this many scaled MADs (about standard
#: deviations for a normal lot) is an outlier by default.
SPREAD_FACTOR = 5.0


@dataclasses.dataclass(frozen=True)
class Layout:
    """The captures' layout, as ``track`` and ``calibrate`` take it."""

    columns: Optional[str] = None
    delimiter: Optional[str] = None
    decimal: Optional[str] = None
    skip_rows: int = 0
    time_unit: str = "s"
    sample_rate_hz: Optional[float] = None


def captures(patterns: Sequence[str]) -> list[str]:
    """The capture files of ``patterns`` (paths or globs such as ``'captures/*.csv'``), sorted,
    each once; a pattern that matches nothing is refused."""
    found: list[str] = []
    for pattern in patterns:
        matches = sorted(glob.glob(pattern)) if any(c in pattern for c in "*?[") else [pattern]
        if not matches:
            raise ValueError(f"CAPTURES: {pattern} matches no file")
        found += [m for m in matches if m not in found]
    return found


def _empty_row(capture: str) -> dict:
    row: dict = {"file": capture, "status": "ok", "error": "", "samples": 0, "method": ""}
    row.update({name: math.nan for name in SENSOR_COLUMNS + ("speed_rad_s", "turns", "error_rms_rad",
                                                             "residual_rms_rad")})
    for k in range(1, harmonics.MAX_ORDER + 1):
        row[f"h{k}_amplitude_rad"] = math.nan
        row[f"h{k}_uncertainty_rad"] = math.nan
    row.update({"tracked_rms_error_rad": math.nan, "tracked_max_error_rad": math.nan, "fault_samples": 0,
                "rejected_samples": 0, "faults": "", "seconds": 0.0})
    return row


def lot_task(capture_files: list, tracker_text: str, tracker_file: str, layout: Layout, skip_s: float) -> list:
    """The rows of ``capture_files``: one Dask task."""
    return [capture_row(c, tracker_text, tracker_file, layout, skip_s) for c in capture_files]


def capture_row(capture: str, tracker_text: str, tracker_file: str, layout: Layout, skip_s: float = 0.0) -> dict:
    """One capture calibrated and tracked with the tracker file's setup: its row (``status``
    ``"error"`` and the one-line ``error`` when it cannot be)."""
    started = time.monotonic()
    row = _empty_row(capture)
    try:
        tracker = Tracker.from_json(tracker_text, tracker_file)
        path = pathlib.Path(capture)
        # As `calibrate --tracker`: the samples as track sees them, without the file's own
        # calibration (replaced by what is learned).
        fields = tracker.replaced(calibration={"kind": "none"}, correction={"kind": "none"}).track_settings()
        learning = tracking.TrackSettings(
            capture=path, output=path, **dataclasses.asdict(layout),
            **{k: fields[k] for k in ("tracker_gains", "mid_scale", "counts_per_unit", "adc_range")})
        cal = tracking.calibrate_capture(learning)
        _fill_calibration(row, cal)
        calibrated = tracker.with_calibration(cal.to_json(), "the calibration learned")
        settings = tracking.TrackSettings(capture=path, output=path, skip_s=skip_s, **dataclasses.asdict(layout),
                                          **calibrated.track_settings(strict=False))
        _track(settings, row)
    except Exception as e:  # noqa: BLE001 - any failure is the capture's row, never a stopped lot
        known = isinstance(e, (ValueError, TypeError, OSError, RuntimeError, MemoryError))
        message = " ".join(str(e).split())
        row["status"], row["error"] = "error", message if known else f"{type(e).__name__}: {message}"
    row["seconds"] = time.monotonic() - started
    return row


def _fill_calibration(row: dict, cal: harmonics.Calibration) -> None:
    row.update(zip(SENSOR_COLUMNS, cal.sensor))
    row.update(method=cal.method, speed_rad_s=cal.speed_rad_s, turns=cal.turns, error_rms_rad=cal.error_rms_rad,
               residual_rms_rad=cal.residual_rms_rad)
    for order in cal.orders:
        if order["order"] <= harmonics.MAX_ORDER:
            row[f"h{order['order']}_amplitude_rad"] = order["amplitude_rad"]
            row[f"h{order['order']}_uncertainty_rad"] = order["uncertainty_rad"]


def _track(s: tracking.TrackSettings, row: dict) -> None:
    """Tracks the capture of ``s`` as ``track`` does (the tracker file's chain,
    ``tracker_run.Run``; its refusal of a capture mostly rejected), counting the faults and,
    against a reference column, the angle error; the estimates are not kept."""
    reader = angletrack.CaptureReader(s.capture, **s.reader_options(), chunk_rows=s.chunk_rows)
    chunks = iter(reader)
    first = next(chunks)
    gains = tracking.gains_for_capture(s, reader.sample_rate_hz if first.time_s is not None else None)
    stats = tracking._ErrorStatistics(s.skip_s, s.lock_tolerance_rad) if first.reference_rad is not None else None
    integer = reader.sample_dtype.startswith(("int", "uint"))
    mid = tracking._mid_scale(s, reader.sample_dtype) if integer else 0.0
    observer = tracker_run.Run(s, gains, reader.sample_dtype, first, mid)
    bad = int(angletrack.Faults.BAD_SAMPLE)
    faulty = rejected = 0
    chunk = first
    while chunk is not None:
        rows = observer.track(chunk.y_c, chunk.y_s)
        faults = rows["faults"]
        faulty += int(np.count_nonzero(faults))
        rejected += int(np.count_nonzero(faults & bad))
        if stats is not None:
            time_s = chunk.time_s
            if time_s is None:
                time_s = (chunk.first_sample + np.arange(len(chunk), dtype=np.float64)) * gains.sample_period_s
            stats.add(time_s, rows["angle_rad"], chunk.reference_rad)
        chunk = next(chunks, None)
    total = reader.rows
    if 2 * rejected > total:
        raise ValueError(tracking._rejections_error(s, rejected, total, reader, math.nan))
    row.update(samples=total, fault_samples=faulty, rejected_samples=rejected,
               faults=str(angletrack.Faults(observer.latched_faults).name or "none"))
    if stats is not None and stats.count:
        row["tracked_rms_error_rad"] = math.sqrt(stats.squares / stats.count)
        row["tracked_max_error_rad"] = stats.largest


def check_limits(limits: dict) -> None:
    """Refuses a ``--limit`` on a column the lot's rows do not have, or on a text column,
    before any capture is read."""
    numbers = [name for name, value in _empty_row("").items() if isinstance(value, (int, float))]
    for column in limits:
        if column not in numbers:
            raise ValueError(f"limit: {column} is not a number column of the lot's rows (one of: "
                             f"{', '.join(numbers)})")


def outlier_report(output: pathlib.Path, limits: dict, spread_factor: float = SPREAD_FACTOR) -> tuple[str, list]:
    """The lot's outliers in the dataset ``output``: for each screened column (and each of
    ``limits``, ``{column: (low, high)}``, either ``None``), the units beyond the limits or
    further than ``spread_factor`` scaled MADs from the lot's median (computed by the crate),
    and the failed captures. Returns the report's text and its rows (file, column, value, why)."""
    import pyarrow.parquet as pq

    table = pq.read_table(output)
    files = table.column("file").to_pylist()
    status = table.column("status").to_pylist()
    errors = table.column("error").to_pylist()
    failed = [(f, "status", math.nan, e) for f, s, e in zip(files, status, errors) if s != "ok"]
    found: list = []
    lines = [f"lot {output}: {len(files)} captures, {len(files) - len(failed)} calibrated and tracked, "
             f"{len(failed)} failed"]
    for column in dict.fromkeys(list(SCREENED) + list(limits)):
        if column not in table.column_names:
            raise ValueError(f"limit: {column} is not a column of the lot's results (columns: "
                             f"{', '.join(table.column_names)})")
        values = np.asarray(table.column(column).to_numpy(zero_copy_only=False), dtype=np.float64)
        low, high = limits.get(column, (None, None))
        median, scale, flags = _angletrack.lot_outliers(values, spread_factor, low, high)
        for k in np.flatnonzero(flags):
            why = (f"beyond the limits {low} to {high}" if (low is not None and values[k] < low)
                   or (high is not None and values[k] > high)
                   else f"{abs(values[k] - median) / scale:.3g} scaled MADs from the median {median:.6g}"
                   if scale > 0 else f"off the median {median:.6g} of a lot without spread")
            found.append((files[k], column, float(values[k]), why))
    for file, column, value, why in found:
        lines.append(f"  outlier {file}: {column} = {value:.6g}, {why}")
    for file, _, _, error in failed:
        lines.append(f"  failed {file}: {error}")
    if not found and not failed:
        lines.append("  no outliers")
    return "\n".join(lines), found + failed
