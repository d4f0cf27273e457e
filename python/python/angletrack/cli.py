"""The ``angletrack`` command line: ``design``, ``track``, ``calibrate``, ``export``, ``plot``,
``report``, ``study`` and ``lot``.

Every number comes from the Rust crates through the extension; this module reads
arguments and files, and writes files and text.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
from typing import Optional, Sequence

import angletrack
from angletrack import calibration as calibration_io
from angletrack import capture as capture_io
from angletrack import clipping, cli_tracker
from angletrack import harmonics, resolver, tracking
from angletrack.cli_args import (
    OneLineErrorParser,
    add_gains_source,
    add_reader_arguments,
    make_output_directories,
    non_negative_number,
    output_format,
    png_path,
    positive_number,
    refuse_overwriting_inputs,
    subcommand,
)
from angletrack.cli_design import add_design_parser
from angletrack.cli_study import add_lot_parser, add_study_parser


#: The extensions of the estimates track writes (the format follows the extension).
ESTIMATE_EXTENSIONS = (".csv", ".npy", ".npz")


def _cmd_track(args: argparse.Namespace) -> int:
    """run an observer over a recorded capture and write its estimates

    Streams CAPTURE (delimited text with any delimiter, with or without a header, an
    oscilloscope's (x, y) column pairs, integer ADC counts; or NumPy .npy/.npz) through an
    observer in constant memory and writes the estimates as CSV, a .npy structured array or
    an .npz of one array per column, by the output's extension. The capture's sample rate (time column) must agree
    with the gains'. The signals may be in any unit (volts, raw ADC counts): the loop is
    amplitude-invariant and the diagnostics are scaled to the capture's own amplitude. With a
    reference column, prints the errors against it. --calibrate learns and corrects the
    sensor's offsets, imbalance and quadrature error. Clipping is flagged against the ADC's
    range (--adc-range, --adc-bits; else extremes held flat), and the observer coasts
    through samples clipped in both channels and through front-end faults.
    """
    output = args.output or args.capture.with_name(args.capture.stem + "_estimates.csv")
    png = (args.plot or output.with_suffix(".png")) if args.plot is not None else None
    calibration_out = calibration_io.default_path(args.capture, args.calibration_out) if args.calibrate else None
    if args.calibration_out is not None and not args.calibrate:
        raise ValueError("calibration_out: --calibration-out is where --calibrate writes what it learns: give "
                         "--calibrate too (or leave --calibration-out out)")
    outputs = {"--output": output, "--calibration-out": calibration_out, "--plot": png}
    refuse_overwriting_inputs(args, outputs)
    if output.suffix.lower() not in ESTIMATE_EXTENSIONS:
        raise ValueError(f"--output: {output}: the estimates' format follows the extension, and the formats "
                         "written are CSV (.csv), NumPy (.npy) or .npz")
    from_tracker = cli_tracker.track_fields(args)
    stored = calibration_io.read_stored(args.calibration)
    adc_signed, adc_bits = clipping.stated_counts(args)
    options = dict(
        gains_file=args.gains_file, gains=args.gains, dtype=args.dtype or "float64", sin_cos=args.sin_cos,
        observer_arguments=calibration_io.observer_arguments(args.calibrate, stored),
        calibration=calibration_io.angle_calibration(stored), adc_range=clipping.stated_range(args),
        adc_signed=adc_signed, adc_bits=adc_bits,
    )
    windings = resolver.track_options(args)
    if from_tracker is not None:
        options.update(from_tracker)
        windings["pole_pairs"] = options.pop("pole_pairs")
    settings = tracking.TrackSettings(
        capture=args.capture,
        output=output,
        sample_rate_hz=args.sample_rate,
        columns=args.columns,
        delimiter=args.delimiter,
        decimal=args.decimal,
        skip_rows=args.skip_rows,
        time_unit=args.time_unit,
        skip_s=args.skip,
        lock_tolerance_rad=args.lock_tolerance,
        progress=args.progress or sys.stderr.isatty(),
        **windings,
        **options,
    )
    if png is not None:
        if args.carrier_hz is not None:
            raise ValueError("plot: --plot with --carrier-hz: the figure is drawn from y_c, y_s samples, not "
                             "carrier-modulated windings; draw the demodulated pairs from the estimates with "
                             "`angletrack plot ESTIMATES --columns time=time_s,y_c=y_c,y_s=y_s --sample-rate HZ`")
        from angletrack import plots

        plots.pyplot(" (or leave out --plot)")  # refused before tracking
    make_output_directories(outputs)
    summary, observer = tracking.track_capture(settings)
    written = [output]
    try:
        lines = [summary]
        if args.calibrate and observer is not None:
            lines.append(calibration_io.write_learned(args.capture, args.calibration_out, observer))
            written.append(calibration_out)
        if png is not None:
            lines.append(plots.plot_capture_file(settings, png))
    except BaseException:
        # A run that fails leaves no output that could pass for a complete one.
        for path in written:
            path.unlink(missing_ok=True)
        raise
    print("\n".join(lines))
    return 0


# ----------------------------------------------------------------------------- plot


def _add_plot_parser(sub) -> None:
    plot = subcommand(sub, _cmd_plot)
    plot.add_argument("capture", type=pathlib.Path, metavar="CAPTURE")
    add_gains_source(plot, required=False)
    plot.add_argument("--columns", metavar="ROLE=COLUMN,...", help="as for `angletrack track`")
    plot.add_argument("--delimiter", metavar="CHAR", help="as for `angletrack track`")
    plot.add_argument("--time-unit", choices=["s", "ms", "us", "ns"], default="s", help="unit of the time column")
    add_reader_arguments(plot)
    clipping.add_signedness(plot)
    plot.add_argument("--skip", type=non_negative_number, default=0.0, metavar="S",
                      help="leave the first S seconds out of the angle error (as well as the start-up)")
    plot.add_argument("--include-start-up", action="store_true",
                      help="against the observer's angle: count its start-up before the lock in the angle error "
                      "(default: left out, and shaded on the figure)")
    plot.add_argument("--lock-tolerance", type=positive_number, default=0.01, metavar="RAD",
                      help="against the observer's angle: it is locked once the error, averaged over blocks of "
                      "an eighth of the loop's time constant, has stayed within RAD (default 0.01) for 4 time "
                      "constants")
    where = plot.add_mutually_exclusive_group()
    where.add_argument("--output", "-o", type=png_path, metavar="FILE.png",
                       help="the figure (default: CAPTURE_plot.png beside the capture)")
    where.add_argument("--out", type=pathlib.Path, metavar="DIR",
                       help="directory for CAPTURE_plot.png and CAPTURE_plot.json (the fitted figures)")
    plot.add_argument("--max-points", type=int, default=200_000, metavar="N",
                      help="most points drawn per series (default 200000): larger captures are decimated")


def _cmd_plot(args: argparse.Namespace) -> int:
    """draw a capture: Lissajous with its ellipse, angle error and harmonics, speed, faults

    Draws one PNG of CAPTURE: the Lissajous figure of (y_c, y_s) with the least-squares
    ellipse (offsets, amplitude ratio, quadrature); the angle error atan2(y_s, y_c) minus the
    reference column (else the observer's angle, with gains) against the electrical angle,
    and its harmonics 1 to 10; the speed and the observer's fault flags over time. Against
    the observer's angle, its start-up until lock is left out of the error and shaded.
    Reads the capture in chunks: any size, at most --max-points points per series (the
    scatters a random subsample, the time series min and max per point). Given the results of
    `angletrack study` or `angletrack lot` (RESULTS.parquet), draws the yield curve and the
    error against each sensor parameter, or each calibration parameter's histogram with its
    outliers.
    """
    from angletrack import plots, study_plots

    if study_plots.is_results(args.capture):
        return study_plots.plot_command(args)
    if args.max_points < 2:
        raise ValueError(f"max_points: --max-points must be at least 2, got {args.max_points}")
    settings = tracking.TrackSettings(
        capture=args.capture, output=args.capture, gains_file=args.gains_file, gains=args.gains,
        sample_rate_hz=args.sample_rate, columns=args.columns, delimiter=args.delimiter,
        decimal=args.decimal, skip_rows=args.skip_rows, time_unit=args.time_unit, skip_s=args.skip,
        lock_tolerance_rad=args.lock_tolerance, adc_signed=args.adc_signed,
    )
    name = args.capture.stem + "_plot"
    summary = None
    if args.out is not None:
        png, summary = args.out / f"{name}.png", args.out / f"{name}.json"
    else:
        png = args.output or args.capture.with_name(f"{name}.png")
    outputs = {"--out" if args.out is not None else "--output": png, "--out (figures)": summary}
    refuse_overwriting_inputs(args, outputs)
    make_output_directories(outputs)
    print(plots.plot_capture_file(settings, png, summary_json=summary, max_points=args.max_points,
                                  include_start_up=args.include_start_up))
    return 0


# ----------------------------------------------------------------------------- report


def _add_report_parser(sub) -> None:
    rep = subcommand(sub, _cmd_report)
    rep.add_argument("--out", type=pathlib.Path, required=True, metavar="DIR", help="output directory")
    rep.add_argument("--no-plots", action="store_true", help="skip the PNG plots (no matplotlib needed)")


def _cmd_report(args: argparse.Namespace) -> int:
    """reproduce the paper's comparison of the three observers (report.md + PNG plots)

    Reproduces the paper's comparison of the 2nd-order, 3rd-order and Kalman observers (179
    degree step, speed ramp, constant acceleration, noise) and its four overshoot figures,
    then corrects a sensor's offsets, imbalance and quadrature with the online calibration and
    its angle-dependent errors with `angletrack calibrate`'s; writes DIR/report.md, the
    section's captures and calibration (DIR/harmonics/) and PNG plots (matplotlib).
    """
    from angletrack import report

    if args.out.exists() and not args.out.is_dir():
        raise ValueError(f"--out: {args.out} is a file, not a directory")
    path = report.write_report(args.out, plots=not args.no_plots)
    print(f"report: {path}")
    return 0


def _cmd_export(args: argparse.Namespace) -> int:
    """write a tracker file's firmware constants (C header or Rust consts)

    Rust: the whole setup of TRACKER as one `static` NAME_TRACKER (the core's Tracker),
    built by its const constructors, so the compiler checks every value and nothing is
    constructed at run time; counts need their amplitude stated (fault_thresholds), and what
    a firmware measures at run time (a mid-scale left to the capture, an online
    calibration's initial estimate) is refused. C: the gains in the number type (float32,
    float64, or the fixed-point constants) and the stored calibration with the angle
    error's harmonics, as `design` and `calibrate` write them, in one header; its first
    comment states the rest of the setup (input, ADC range, pole pairs) for the C chain's
    constructor. Settings the C header does not carry yet (fault thresholds, a winding
    check, an online calibration, a correction table) are refused.
    """
    language = output_format(args.format, args.output, default="c")
    if language not in ("c", "rust"):
        raise ValueError(f"format: export writes C (.h) or Rust (.rs), not {language}: the tracker file is the JSON")
    refuse_overwriting_inputs(args, {"--output": args.output})
    make_output_directories({"--output": args.output})
    tracker = cli_tracker.read(args.tracker)
    text = tracker.firmware_constants(language, name=args.name)
    if args.output is None:
        sys.stdout.write(text)
    else:
        capture_io.write_output(args.output, text)
        print(f"wrote the firmware constants of {args.tracker} ({language}) to {args.output}")
    return 0


def _add_export_parser(sub) -> None:
    export = subcommand(sub, _cmd_export)
    export.add_argument("tracker", type=pathlib.Path, metavar="TRACKER")
    export.add_argument("--format", choices=["c", "rust"],
                        help="c (header) or rust (const block); default: the output's by its extension (.h c, .rs "
                        "rust), else c")
    export.add_argument("--output", "-o", type=pathlib.Path, metavar="FILE",
                        help="where to write them (default: standard output)")
    export.add_argument("--name", default="angletrack", help="identifier prefix")


def build_parser() -> argparse.ArgumentParser:
    """The ``angletrack`` argument parser with its subcommands."""
    parser = OneLineErrorParser(
        prog="angletrack",
        description="Angle tracking observers (software resolver-to-digital conversion): "
        "design gains for firmware, run an observer over a capture, reproduce the paper.",
    )
    parser.add_argument("--version", action="version", version=f"angletrack {angletrack.__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    _add_track_parser(sub)
    add_design_parser(sub)
    _add_report_parser(sub)
    _add_plot_parser(sub)
    _add_calibrate_parser(sub)
    _add_export_parser(sub)
    add_study_parser(sub)
    add_lot_parser(sub)
    return parser


#: The calibration's options as the CLI spells them, for its errors.
_CALIBRATE_FLAGS = {
    "lowest_order": "--lowest-order", "highest_order": "--highest-order", "settle_fraction": "--settle-fraction",
    "min_significance": "--min-significance", "the calibration's own loop": "--loop own",
}


def _cmd_calibrate(args: argparse.Namespace) -> int:
    """learn a sensor's calibration (offsets, imbalance, quadrature, angle error harmonics)

    Reads CAPTURE twice in chunks (any length, constant memory; any unit: the amplitude is
    measured) and learns the offsets, imbalance and quadrature from the least-squares
    ellipse of its Lissajous figure, then the harmonics of the angle error: against the
    capture's reference column when it has one (every order, whatever the speed profile),
    else, or with --self, against the angle of a loop of the calibration's own designed from
    the capture's speed (--loop own, the default) or of the gains (--loop gains), past the
    first --settle-fraction, at roughly constant speed, over at least 5 turns. Without a
    reference an angle-synchronous speed ripple and a sensor error cannot be told apart:
    orders 1 and 2 are then the ellipse's. Each order is reported with its uncertainty; one
    below --min-significance times it is not learned. Writes JSON for `angletrack track
    --calibration`, or a C header / Rust const block for firmware.
    """
    calibration_format = output_format(args.format, args.output, default="json")
    refuse_overwriting_inputs(args, {"--output": args.output})
    make_output_directories({"--output": args.output})
    tracker = cli_tracker.read(args.tracker)
    from_tracker = {}
    if tracker is not None:
        cli_tracker.checked_flags(args, tracker)
        # The learning sees the samples as track does (mid-scale, scaling); what the file
        # stored before is replaced by what is learned.
        fields = tracker.replaced(calibration={"kind": "none"}, correction={"kind": "none"}).track_settings()
        from_tracker = {k: fields[k] for k in ("tracker_gains", "mid_scale", "counts_per_unit", "adc_range")}
    settings = tracking.TrackSettings(capture=args.capture, output=args.output, gains_file=args.gains_file,
                                      gains=args.gains, sample_rate_hz=args.sample_rate, columns=args.columns,
                                      delimiter=args.delimiter, decimal=args.decimal, skip_rows=args.skip_rows,
                                      time_unit=args.time_unit, adc_signed=args.adc_signed, **from_tracker)
    try:
        cal = tracking.calibrate_capture(
            settings, lowest_order=args.lowest_order, highest_order=args.highest_order,
            settle_fraction=args.settle_fraction, self_calibration=args.self_calibration,
            own_loop=args.loop == "own", min_significance=args.min_significance,
            reference_ratio=args.reference_ratio)
    except angletrack.ConfigError as e:
        message = str(e)
        for name, flag in _CALIBRATE_FLAGS.items():
            message = message.replace(name, flag)
        raise ValueError(message) from None
    text = {"json": cal.to_json, "c": cal.to_c_header, "rust": cal.to_rust}[calibration_format]()
    if tracker is not None and calibration_format == "json":
        text = tracker.with_calibration(text, "the calibration learned").to_json()
    if args.output is None:
        print(text, end="")
    else:
        capture_io.write_output(args.output, text)
    print(cal.describe(), file=sys.stderr if args.output is None else sys.stdout)
    return 0


def reference_ratio(text: str) -> int:
    """``--reference-ratio``: a whole number other than 0 (argparse names the option)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value == 0 or abs(value) > 1 << 16:
        raise argparse.ArgumentTypeError(f"expected a whole number from -65536 to 65536 other than 0, got {text}")
    return value


def _add_calibrate_parser(sub) -> None:
    cal = subcommand(sub, _cmd_calibrate)
    cal.add_argument("capture", type=pathlib.Path, metavar="CAPTURE")
    add_gains_source(cal, tracker=True)
    cal.add_argument("--columns", metavar="ROLE=COLUMN,...",
                     help="which columns hold what (as for track; a reference column is calibrated against)")
    cal.add_argument("--delimiter", metavar="CHAR", help="field delimiter (default: sniffed)")
    cal.add_argument("--time-unit", choices=["s", "ms", "us", "ns"], default="s",
                     help="unit of the time column (default s)")
    add_reader_arguments(cal)
    clipping.add_signedness(cal)
    cal.add_argument("--self", dest="self_calibration", action="store_true",
                     help="self-calibrate even when the capture has a reference column")
    cal.add_argument("--reference-ratio", type=reference_ratio, default=1, metavar="N",
                     help="the sensor's angle turns N times per turn of the reference column: a whole number, the "
                     "motor's pole pairs for a mechanical reference, negative for a reference counting the other way "
                     "(default 1; a constant offset between the two zeros needs nothing: it is taken as the "
                     "reference's zero)")
    cal.add_argument("--loop", choices=["own", "gains"], default="own",
                     help="self-calibration's loop: own (default: one designed from the capture's speed, every "
                     "order above its bandwidth) or gains (orders within their bandwidth are not learned)")
    cal.add_argument("--lowest-order", type=int, default=None, metavar="K",
                     help="lowest harmonic of the angle error learned (default: 1 against a reference, 3 in a "
                     "self-calibration, raised above the gains' bandwidth with --loop gains)")
    cal.add_argument("--highest-order", type=int, default=harmonics.MAX_ORDER, metavar="K",
                     help=f"highest harmonic learned (default and most {harmonics.MAX_ORDER})")
    cal.add_argument("--settle-fraction", type=float, default=0.2, metavar="F",
                     help="self-calibration: fraction of the capture, from its start, left out while the loop "
                     "settles (in [0, 1); default 0.2)")
    cal.add_argument("--min-significance", type=non_negative_number, default=3.0, metavar="X",
                     help="learn an order only when its amplitude is at least X times its uncertainty "
                     "(default 3; 0 learns every order, warning of those below their uncertainty)")
    cal.add_argument("--format", choices=["json", "c", "rust"],
                     help="json (for track --calibration; with --tracker: the tracker file with the calibration and "
                     "its harmonics as the correction), c (header) or rust (const block); default: the output's by "
                     "its extension (.json json, .h c, .rs rust), else json")
    cal.add_argument("--output", "-o", type=pathlib.Path, metavar="FILE",
                     help="where to write it (default: standard output)")


def _add_track_parser(sub) -> None:
    track = subcommand(sub, _cmd_track)
    track.add_argument("capture", type=pathlib.Path, metavar="CAPTURE")
    add_gains_source(track, tracker=True)
    cols = track.add_argument_group("the capture's layout (sniffed by default)")
    cols.add_argument("--columns", metavar="ROLE=COLUMN,...",
                      help="which columns hold what: roles y_c, y_s, time, reference; each column a header "
                      "name, else a 0-based index (e.g. y_c=cos,y_s=sin,time=t or y_c=0,y_s=1), or '-' to ignore "
                      "a time or reference column (time=-); one column per role; default: the columns named "
                      "y_c/cos, y_s/sin, time/t, reference/theta")
    cols.add_argument("--delimiter", metavar="CHAR",
                      help="field delimiter: one character, 'tab' or 'whitespace' (default: sniffed)")
    cols.add_argument("--time-unit", choices=["s", "ms", "us", "ns"], default="s",
                      help="unit of the time column (default s)")
    add_reader_arguments(cols)
    track.add_argument("--dtype", choices=["float32", "float64", "fixed"], default=None,
                       help="number type the observer runs on (default float64); fixed: the fixed-point chain "
                       "on integer counts (a --calibration applied in integers, as a firmware does)")
    track.add_argument("--sin-cos", choices=["fast", "exact"], default=None,
                       help="phase detector's sin/cos (default: fast for float32, exact for float64)")
    track.add_argument("--output", "-o", type=pathlib.Path, metavar="FILE",
                       help="estimates file, its format from its extension: .csv, .npy (a NumPy structured "
                       "array) or .npz (one array per column); never an input; written beside it and renamed "
                       "when complete (default: CAPTURE_estimates.csv beside the capture)")
    track.add_argument("--skip", type=non_negative_number, default=0.0, metavar="S",
                       help="with a reference: leave the first S seconds out of the error statistics")
    track.add_argument("--lock-tolerance", type=positive_number, default=0.01, metavar="RAD",
                       help="with a reference: angle error of the lock (default 0.01 rad)")
    track.add_argument("--progress", action="store_true",
                       help="report progress on stderr (default: only when stderr is a terminal)")
    track.add_argument("--calibrate", action="store_true",
                       help="learn the sensor's offsets, gain imbalance and quadrature error while tracking, "
                       "correct them, and write the calibration (JSON) beside the estimates")
    track.add_argument("--calibration-out", type=pathlib.Path, metavar="FILE.json",
                       help="with --calibrate: where to write it (default: CAPTURE_calibration.json)")
    track.add_argument("--calibration", type=pathlib.Path, metavar="FILE.json",
                       help="apply a stored calibration: one from `angletrack calibrate` (offsets, imbalance, "
                       "quadrature and the angle error harmonics, corrected before the phase detector, in --dtype's "
                       "type: float32, float64, or integers with fixed), "
                       "or one that --calibrate wrote (frozen; with --calibrate, learning starts from it)")
    resolver.add_track_arguments(track)
    clipping.add_arguments(track)
    track.add_argument("--plot", nargs="?", const="", type=png_path, metavar="FILE.png",
                       help="also draw the capture (as `angletrack plot`) into FILE.png (default: the "
                       "output's name with .png)")


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Entry point of the ``angletrack`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(clipping.joined_negative_range(list(sys.argv[1:] if argv is None else argv)))
    try:
        return args.func(args)
    except (ValueError, TypeError, OSError, RuntimeError, MemoryError) as e:
        # One line, never a traceback: a capture's error reads FILE:LINE:COLUMN: what.
        message = " ".join(str(e).split())
        print(f"angletrack: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
