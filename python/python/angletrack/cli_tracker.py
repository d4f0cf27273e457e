"""``--tracker FILE`` on the command line: the setup of a tracker file
(:class:`angletrack.Tracker`) in place of the gains file, the calibration file and the
options, each option given beside it checked against the file (one that says otherwise is
refused, naming both; one that says the same is accepted)."""

from __future__ import annotations

import argparse
import pathlib
from typing import Any, Optional

from angletrack import capture as capture_io
from angletrack import clipping
from angletrack.tracker import Tracker

#: Relative difference of a --sample-rate and the file's rate taken as the same rate.
_SAME_RATE = 1e-9


def read(path: Optional[pathlib.Path]) -> Optional[Tracker]:
    """The tracker file given with ``--tracker`` (``None`` without one)."""
    if path is None:
        return None
    return Tracker.from_json(capture_io.read_text_file(path, "--tracker"), str(path))


def _contradiction(flag: str, given: Any, tracker: Tracker, field: str, value: Any) -> ValueError:
    return ValueError(f"{field}: {flag} {given} contradicts --tracker {tracker.file}, whose {field} is {value}; "
                      f"leave {flag} out (or edit the file)")


def _shown(value: Any) -> str:
    return "null" if value is None else f'"{value}"' if isinstance(value, str) else str(value)


def checked_flags(args: argparse.Namespace, tracker: Tracker) -> None:
    """Refuses an option beside ``--tracker`` that says otherwise than the file: the
    sample rate, the number type, the sin/cos, the ADC range, the pole pairs; a calibration
    file (the tracker holds the calibration); ``--calibrate`` unless the file's calibration
    is learned online."""
    d = tracker.document
    rate = getattr(args, "sample_rate", None)
    if rate is not None and abs(rate * d["sample_period_s"] - 1.0) > _SAME_RATE:
        raise _contradiction("--sample-rate", rate, tracker, "sample_period_s",
                             f"{d['sample_period_s']} ({1.0 / d['sample_period_s']:.6g} Hz)")
    dtype = getattr(args, "dtype", None)
    if dtype is not None and dtype != tracker.dtype:
        raise _contradiction("--dtype", dtype, tracker, "number_type", _shown(d["number_type"]))
    sin_cos = getattr(args, "sin_cos", None)
    if sin_cos is not None and sin_cos != d["sin_cos"]:
        raise _contradiction("--sin-cos", sin_cos, tracker, "sin_cos", _shown(d["sin_cos"]))
    stated = clipping.stated_range(args)
    if stated is not None and stated != tracker.adc_range:
        flag = "--adc-range" if getattr(args, "adc_range", None) is not None else "--adc-bits"
        shown = getattr(args, "adc_range", None) or f"{args.adc_bits} ({stated[0]:g} to {stated[1]:g})"
        raise _contradiction(flag, shown, tracker, "adc_range", d["adc_range"])
    pole_pairs = getattr(args, "pole_pairs", None)
    if pole_pairs is not None and pole_pairs != d["pole_pairs"]:
        raise _contradiction("--pole-pairs", pole_pairs, tracker, "pole_pairs", _shown(d["pole_pairs"]))
    if getattr(args, "calibration", None) is not None:
        raise ValueError(f"calibration: --calibration {args.calibration} with --tracker {tracker.file}: the tracker "
                         "file holds the calibration (its calibration and correction); give one of them")
    if getattr(args, "calibrate", False) and d["calibration"]["kind"] != "online":
        raise _contradiction("--calibrate", "(learn online)", tracker, "calibration.kind",
                             _shown(d["calibration"]["kind"]))


def track_fields(args: argparse.Namespace) -> Optional[dict]:
    """The ``TrackSettings`` fields of ``--tracker`` (``None`` without it), the options
    beside it checked against the file."""
    tracker = read(getattr(args, "tracker", None))
    if tracker is None:
        return None
    checked_flags(args, tracker)
    return tracker.track_settings(strict=False)
