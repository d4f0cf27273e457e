"""``angletrack design``: an observer's gains from a specification, its report, the gains
exported as C, Rust or JSON, and its plots."""

from __future__ import annotations

import argparse
import pathlib
import sys

import angletrack
from angletrack import capture as capture_io
from angletrack import cli_design_capture, export
from angletrack.cli_args import (
    make_output_directories, output_format, png_path, positive_number, refuse_overwriting_inputs, subcommand,
)


#: For each observer, its design variants: (function, required options, optional options).
#: A variant applies when all its required options are given; of two that apply, the one whose
#: options include the other's is meant.
_DESIGNS = {
    "second-order": [
        ("second_order_from_tracking_error_sampled", ["max_error", "acceleration", "overshoot"], []),
        ("second_order_from_tracking_error", ["max_error", "acceleration"], ["damping"]),
        ("second_order_from_bandwidth", ["bandwidth"], ["damping"]),
        ("second_order_butterworth", ["butterworth_time_constant"], []),
    ],
    "third-order": [
        ("third_order_from_poles", ["pole_ratio", "pole_time_constant"], ["pole_frequency_ratio"]),
        ("third_order_from_overshoot", ["overshoot", "settling_time"], ["pole_frequency_ratio"]),
        ("third_order_butterworth", ["butterworth_time_constant"], []),
    ],
    "kalman": [
        ("kalman", ["q", "r"], []),
        ("kalman_from_jerk_std", ["jerk_std", "noise_std"], []),
        ("kalman_from_jerk_density", ["jerk_density", "noise_std"], []),
    ],
}

#: CLI option (dest) -> keyword argument of the design functions.
_KEYWORDS = {
    "max_error": "max_error_rad",
    "acceleration": "acceleration_rad_s2",
    "damping": "damping",
    "bandwidth": "bandwidth_hz",
    "butterworth_time_constant": "time_constant_s",
    "pole_ratio": "pole_ratio",
    "pole_time_constant": "pole_time_constant_s",
    "pole_frequency_ratio": "pole_frequency_ratio",
    "overshoot": "overshoot",
    "settling_time": "settling_time_s",
    "q": "process_noise_q",
    "r": "measurement_noise_r",
    "jerk_std": "jerk_std_rad_s3",
    "jerk_density": "jerk_density_rad2_s5",
    "noise_std": "sensor_noise_std",
}

_DEFAULTS = {"damping": 1.0, "pole_frequency_ratio": angletrack.PAPER_POLE_FREQUENCY_RATIO}

_CONTINUOUS = {"second-order", "third-order"}

#: Design functions that design the discrete loop itself: no discretisation argument.
_DISCRETE = {"second_order_from_tracking_error_sampled", "kalman", "kalman_from_jerk_std", "kalman_from_jerk_density"}


#: Sensor noise of `design --plot`'s trade-off without --noise-std (per channel, amplitude 1).
_PLOT_NOISE_STD = 1e-3


def _option(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def _design_from_args(args: argparse.Namespace) -> tuple[angletrack.Design, dict]:
    """Picks the design variant from the options given and calls it."""
    given = {dest for dest in _KEYWORDS if getattr(args, dest, None) is not None}
    variants = _DESIGNS[args.observer]
    matching = [v for v in variants if set(v[1]) <= given]
    matching = [v for v in matching if not any(set(v[1]) < set(w[1]) for w in matching)]
    if len(matching) != 1:
        choices = "; or ".join(" ".join(_option(o) + " ..." for o in req) for _, req, _ in variants)
        what = "several specifications" if matching else "no complete specification"
        raise ValueError(f"{args.observer}: {what} given; give exactly one of: {choices}")
    function, required, optional = matching[0]
    used = set(required) | set(optional)
    unused = given - used - ({"noise_std"} if args.observer in _CONTINUOUS else set())
    if unused:
        raise ValueError(f"{args.observer}: {', '.join(sorted(_option(u) for u in unused))} not used by {function}")
    kwargs = {_KEYWORDS[o]: getattr(args, o) for o in required}
    for o in optional:
        value = getattr(args, o)
        kwargs[_KEYWORDS[o]] = _DEFAULTS[o] if value is None else value
    if args.sample_rate is None or not args.sample_rate > 0:
        raise ValueError("sample_rate: --sample-rate must be a positive number of Hz")
    kwargs["sample_period_s"] = 1.0 / args.sample_rate
    if function not in _DISCRETE:
        kwargs["discretisation"] = args.discretisation
    try:
        design = getattr(angletrack, function)(**kwargs)
    except angletrack.ConfigError as e:
        raise ValueError(_with_flag(str(e), e.parameter)) from None
    return design, {"function": function, **kwargs}


def _with_flag(message: str, parameter: str) -> str:
    """A design function's message about its keyword ``parameter`` with the option the user
    wrote in its place (``bandwidth_hz must be positive`` reads ``--bandwidth must be
    positive``); the keyword is kept where no option names it."""
    flags = {keyword: _option(dest) for dest, keyword in _KEYWORDS.items()}
    flags["sample_period_s"] = "--sample-rate (its period, sample_period_s)"
    flag = flags.get(parameter)
    if flag is None or not message.startswith(parameter):
        return message
    return flag + message[len(parameter):]


def add_design_parser(sub) -> None:
    design = subcommand(sub, _cmd_design)
    design.add_argument("observer", choices=sorted(_DESIGNS), nargs="?",
                        help="which observer (none with --from-capture, which chooses it)")
    design.add_argument("--sample-rate", type=float, metavar="HZ",
                        help="sample rate (Hz); with --from-capture, the capture's time column's by default")
    spec = design.add_argument_group(
        "specification (one set, by observer)",
        "second-order: --max-error, --acceleration and --overshoot (met by the sampled loop itself), "
        "or --max-error and --acceleration [--damping], or --bandwidth [--damping], or "
        "--butterworth-time-constant; third-order: --pole-ratio and --pole-time-constant "
        "[--pole-frequency-ratio], or --overshoot and --settling-time [--pole-frequency-ratio], or "
        "--butterworth-time-constant; kalman: --q and --r, or --jerk-std and --noise-std, or "
        "--jerk-density and --noise-std",
    )
    for dest, (metavar, text) in {
        "max_error": ("RAD", "tolerated angle error at --acceleration (rad)"),
        "acceleration": ("RAD_S2", "acceleration of the tolerated error (rad/s^2)"),
        "damping": ("M", f"damping ratio m (default 1; the paper: {angletrack.PAPER_FIVE_PERCENT_DAMPING} "
                    "for 5 %% overshoot)"),
        "bandwidth": ("HZ", "-3 dB bandwidth of the continuous loop (Hz)"),
        "butterworth_time_constant": ("S", "time constant Tc of the Butterworth setting (s)"),
        "pole_ratio": ("K", f"real pole at -K/T (the paper: {angletrack.PAPER_POLE_RATIO})"),
        "pole_time_constant": ("S", "time constant T of the complex pair (s)"),
        "pole_frequency_ratio": ("PSI", "complex pair at (-1 +- j psi)/T (default 3 pi/2)"),
        "overshoot": ("FRACTION", "target overshoot (0.1 for 10 %%)"),
        "settling_time": ("S", "target 2 %% settling time (s)"),
        "q": ("Q", "process noise variance of the scaled jerk Ts^3 beta (rad^2)"),
        "r": ("R", "measurement noise variance per channel"),
        "jerk_std": ("RAD_S3", "standard deviation of the jerk (rad/s^3)"),
        "jerk_density": ("RAD2_S5", "power spectral density of the jerk (rad^2/s^5)"),
        "noise_std": ("STD", "sensor noise standard deviation per channel (amplitude 1); "
                      "also the noise of the report's predicted errors"),
    }.items():
        spec.add_argument(_option(dest), dest=dest, type=float, metavar=metavar, help=text)
    # The design functions parse the name (the Rust crate's Discretisation::from_str).
    design.add_argument("--discretisation", default="pole_matching", metavar="NAME",
                        help="mapping of a continuous design: pole_matching (default), forward_euler or "
                        "tustin ('-' for '_' and any case accepted)")
    design.add_argument("--format", choices=["c", "rust", "json", "tracker"],
                        help="gains file format (default: the output's by its extension, .h c, .rs rust, "
                        ".json json; else c); tracker: a tracker file (JSON, docs/guide/tracker-file.md) of the "
                        "gains with --dtype as its number type, for `angletrack calibrate|track --tracker`")
    design.add_argument("--output", "-o", type=pathlib.Path, metavar="FILE",
                        help="write the gains there (default: print them after the report)")
    design.add_argument("--dtype", choices=["float32", "float64", "fixed"], default="float32",
                        help="float type of the C/Rust constants (default float32; JSON is always float64), "
                             "or fixed: the fixed-point observer's integer constants (docs/theory.md §14)")
    design.add_argument("--name", default="angletrack", help="identifier prefix in the C/Rust output")
    design.add_argument("--plot", type=png_path, metavar="FILE.png",
                        help="draw the loop's Bode plot and its noise-against-bandwidth trade-off")
    design.add_argument("--plot-acceleration", type=positive_number, default=1000.0, metavar="RAD_S2",
                        help="acceleration of the trade-off's tracking error, 2nd order (default 1000 rad/s^2)")
    cli_design_capture.add_arguments(design)
    design.add_argument("--plot-jerk", type=positive_number, default=1e5, metavar="RAD_S3",
                        help="jerk of the trade-off's tracking error, 3rd order (default 1e5 rad/s^3)")


def _tracker_text(gains_json: str, dtype: str) -> str:
    """The tracker file of the gains file's text ``gains_json`` whose number type is
    ``dtype`` (fixed: on counts, their mid-scale measured), its other settings the defaults."""
    from angletrack.tracker import Tracker

    number_type = {"float32": "f32", "float64": "f64", "fixed": "fixed"}[dtype]
    settings: dict = {"number_type": number_type}
    if dtype == "fixed":
        settings["input"] = {"kind": "counts"}
    return Tracker.from_gains_json(gains_json, "the design").replaced(**settings).to_json()


def _cmd_design(args: argparse.Namespace) -> int:
    """design gains from a specification, print the design's report, export the gains

    Designs an observer from a specification, prints its datasheet (poles, bandwidth, error
    constants, noise, step responses) and writes the gains as a C header, a Rust const block
    or JSON, ready for angletrack-core's Gains::new(gains, Ts).
    """
    if args.from_capture is not None:
        given = [_option(dest) for dest in _KEYWORDS if getattr(args, dest, None) is not None]
        return cli_design_capture.run(args, given)
    if args.observer is None:
        raise ValueError("observer: give the observer (second-order, third-order or kalman) or --from-capture")
    gains_format = output_format(args.format, args.output, default="c")
    refuse_overwriting_inputs(args, {"--output": args.output, "--plot": args.plot})
    design, spec = _design_from_args(args)
    make_output_directories({"--output": args.output, "--plot": args.plot})
    noise = args.noise_std if args.noise_std is not None else 0.0
    report = design.report(sensor_noise_std=noise)
    spec_text = ", ".join(f"{k}={v!r}" for k, v in spec.items() if k != "function")
    description = (
        f"{design.method} ({spec['function']}: {spec_text})\n"
        f"-3 dB bandwidth {report.bandwidth_hz or float('nan'):.6g} Hz, linear step overshoot "
        f"{100 * report.linear_step.overshoot:.3g} %, 2 % settling {report.linear_step.settling_time_s:.6g} s"
    )
    metadata = {"method": design.method, "discretisation": design.discretisation, "specification": spec}
    if gains_format == "tracker":
        text = _tracker_text(export.to_json(design.gains, metadata=metadata), args.dtype)
    elif args.dtype == "fixed":
        constants = design.fixed_constants()
        if gains_format == "c":
            text = export.fixed_to_c_header(constants, name=args.name, description=description)
        elif gains_format == "rust":
            text = export.fixed_to_rust(constants, name=args.name, description=description)
        else:
            text = export.fixed_to_json(constants, metadata=metadata)
    elif gains_format == "c":
        text = export.to_c_header(design.gains, name=args.name, dtype=args.dtype, description=description)
    elif gains_format == "rust":
        text = export.to_rust(design.gains, name=args.name, dtype=args.dtype, description=description)
    else:
        text = export.to_json(design.gains, metadata=metadata)
    print(f"{design!r}\n")
    print(report)
    if args.output is None:
        print()
        sys.stdout.write(text)
    else:
        capture_io.write_output(args.output, text)
        kind = args.dtype if gains_format != 'json' or args.dtype == 'fixed' else 'float64'
        what = f"a tracker file, number type {args.dtype}" if gains_format == "tracker" else f"{gains_format}, {kind}"
        print(f"\nwrote the gains ({what}) to {args.output}")
    if args.plot is not None:
        from angletrack import design_plots

        print(design_plots.plot_design(
            design, args.plot, sensor_noise_std=noise or _PLOT_NOISE_STD, acceleration_rad_s2=args.plot_acceleration,
            jerk_rad_s3=args.plot_jerk, title=f"{design.method}: " + ", ".join(
                f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}" for k, v in spec.items() if k != "function"),
        ))
    return 0
