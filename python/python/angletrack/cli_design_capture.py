"""``angletrack design --from-capture``: the observer chosen from a capture
(:func:`angletrack.design_from_capture`), written as a tracker file with its predicted RMS
angle error, its estimates and the runners-up printed, its spectra and trade-off drawn."""

from __future__ import annotations

import argparse
import pathlib

import angletrack
from angletrack import capture as capture_io
from angletrack.cli_args import add_reader_arguments, make_output_directories, refuse_overwriting_inputs

#: ``--dtype`` -> the tracker file's number type.
_NUMBER_TYPES = {"float32": "f32", "float64": "f64", "fixed": "fixed"}


def add_arguments(design) -> None:
    """The options of ``design --from-capture``, beside the design command's own."""
    group = design.add_argument_group(
        "design from a capture (instead of OBSERVER and a specification)",
        "the sensor noise and the motion estimated from CAPTURE, the observer of least predicted "
        "RMS angle error chosen over the orders and bandwidths (docs/guide/design-from-capture.md)",
    )
    group.add_argument("--from-capture", type=pathlib.Path, metavar="CAPTURE",
                       help="the capture: its y_c, y_s and, if it has one, reference columns")
    group.add_argument("--columns", metavar="ROLE=COLUMN,...", help="as for `angletrack track`")
    group.add_argument("--delimiter", metavar="CHAR", help="as for `angletrack track`")
    group.add_argument("--time-unit", choices=["s", "ms", "us", "ns"], default="s",
                       help="unit of the time column (default s)")
    add_reader_arguments(group)
    group.add_argument("--max-overshoot", type=float, metavar="FRACTION",
                       help="largest overshoot of the linear step response (0.1 for 10 %%)")
    group.add_argument("--min-bandwidth", type=float, metavar="HZ", help="smallest -3 dB bandwidth (Hz)")
    group.add_argument("--speed-step", type=float, metavar="RAD_S",
                       help="largest speed step to acquire (rad/s; default none beyond the capture's own motion)")
    group.add_argument("--quantisation-step", type=float, metavar="STEP",
                       help="the samples' quantisation step in their unit (default: 1 for integer samples, "
                       "ADC counts; else none)")
    group.add_argument("--grid-points", type=int, default=31, metavar="N",
                       help="bandwidths tried per observer (default 31)")


def _read(args: argparse.Namespace):
    """The capture's arrays, its sample period and its quantisation step (stated, else 1 for
    integer samples)."""
    capture = capture_io.read_capture(
        args.from_capture, columns=args.columns, delimiter=args.delimiter, decimal=args.decimal,
        skip_rows=args.skip_rows, time_unit=args.time_unit, sample_rate_hz=args.sample_rate,
    )
    if capture.sample_rate_hz is None:
        raise ValueError("sample_rate: the capture has no time column: give --sample-rate")
    step = args.quantisation_step
    if step is None and capture.sample_dtype.startswith(("int", "uint")):
        step = 1.0
    return capture, 1.0 / capture.sample_rate_hz, step


def _with_flag(e: angletrack.ConfigError) -> str:
    """The binding's message about its keyword with the option the user wrote."""
    flags = {"max_overshoot": "--max-overshoot", "min_bandwidth_hz": "--min-bandwidth",
             "speed_step_rad_s": "--speed-step", "grid_points": "--grid-points",
             "quantisation_step": "--quantisation-step",
             "sample_period_s": "--sample-rate (its period, sample_period_s)"}
    message = str(e)
    flag = flags.get(e.parameter)
    return flag + message[len(e.parameter):] if flag and message.startswith(e.parameter) else message


def _describe(result: dict) -> str:
    """The estimates, the chosen design with its predicted error's parts, the runners-up."""
    noise, motion, chosen = result["noise"], result["motion"], result["chosen"]
    jerk = motion["jerk_std_rad_s3"]
    source = "the reference column" if motion["from_reference"] else (
        f"the signals' own angle (first pass {motion['first_pass_bandwidth_hz']:.4g} Hz)")
    quantisation = noise["quantisation_std"]
    lines = [
        f"noise per channel {noise['std']['value']:.4g} +- {noise['std']['std']:.2g} of the amplitude "
        f"{noise['amplitude']:.6g} (cos {noise['cos_std']['value']:.4g}, sin {noise['sin_std']['value']:.4g}; "
        f"white {noise['white_std']:.4g}, coloured {noise['coloured_std']:.4g} of pole {noise['coloured_pole']:.4g}"
        + (f"; quantisation {quantisation:.3g}" if quantisation is not None else "") + ")",
        f"motion from {source}: jerk {jerk['value']:.4g} +- {jerk['std']:.2g} rad/s^3, "
        f"{motion['turns']:.4g} turns, initial speed {motion['initial_speed_rad_s']:.4g} rad/s",
        f"chosen: {chosen['observer']}, -3 dB bandwidth {chosen['bandwidth_hz']:.5g} Hz, "
        f"predicted RMS angle error {chosen['predicted_error_rms_rad']:.4g} rad (noise {chosen['noise_rad']:.3g}, "
        f"lag {chosen['lag_rad']:.3g}, number type {chosen['number_type_rad']:.3g})",
    ]
    for c in result["runners_up"]:
        lines.append(f"runner-up: {c['observer']}, {c['bandwidth_hz']:.5g} Hz, "
                     f"{c['predicted_error_rms_rad']:.4g} rad (noise {c['noise_rad']:.3g}, lag {c['lag_rad']:.3g})")
    return "\n".join(lines)


def run(args: argparse.Namespace, specification: list[str]) -> int:
    """``design --from-capture``: choose, print, write the tracker file, draw.
    ``specification``: the options of a design by specification that were given, refused."""
    if specification:
        raise ValueError(f"{specification[0]}: not used with --from-capture, which measures the noise and the motion")
    if args.observer is not None:
        raise ValueError(f"observer: {args.observer} given with --from-capture, which chooses the observer")
    if args.format not in (None, "tracker"):
        raise ValueError(f"format: --from-capture writes a tracker file, not --format {args.format}")
    refuse_overwriting_inputs(args, {"--output": args.output, "--plot": args.plot})
    capture, sample_period_s, step = _read(args)
    try:
        result = angletrack.design_from_capture(
            capture.y_c, capture.y_s, sample_period_s, reference_angle_rad=capture.reference_rad,
            quantisation_step=step, max_overshoot=args.max_overshoot, min_bandwidth_hz=args.min_bandwidth,
            speed_step_rad_s=args.speed_step, number_type=_NUMBER_TYPES[args.dtype], grid_points=args.grid_points,
        )
    except angletrack.ConfigError as e:
        raise ValueError(_with_flag(e)) from None
    make_output_directories({"--output": args.output, "--plot": args.plot})
    print(_describe(result))
    text = result["tracker_json"]
    if args.output is None:
        print()
        print(text, end="")
    else:
        capture_io.write_output(args.output, text)
        print(f"\nwrote the tracker file (number type {args.dtype}, predicted_error_rms_rad "
              f"{result['predicted_error_rms_rad']:.4g}) to {args.output}")
    if args.plot is not None:
        from angletrack import design_plots

        print(design_plots.plot_design_from_capture(result, args.plot, title=str(args.from_capture)))
    return 0


__all__ = ["add_arguments", "run"]
