"""The ``angletrack`` command line's shared argument types and helpers: subcommands from
their functions, numbers, gains sources, capture-reader options and the check that no output
overwrites an input."""

from __future__ import annotations

import argparse
import math
import os
import pathlib
from typing import Callable, Optional

from angletrack import capture as capture_io


class OneLineErrorParser(argparse.ArgumentParser):
    """An argument parser whose refusals are one line, ``angletrack track: error: argument
    --latency: ...``, without the usage lines before it (``--help`` shows those); its
    subcommands' parsers are of its class too."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {' '.join(message.split())} (see {self.prog} --help)\n")


def subcommand(sub, run: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """The subcommand NAME of ``run`` (named ``_cmd_NAME``): the first line of its docstring
    is the command's help, the rest its description."""
    help_line, _, description = run.__doc__.partition("\n\n")
    name = run.__name__[len("_cmd_"):]
    parser = sub.add_parser(name, help=help_line.strip(), description=" ".join(description.split()))
    parser.set_defaults(func=run)
    return parser


def float_list(text: str) -> list[float]:
    """Comma-separated numbers, such as gains ``0.06,0.001``."""
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None


def finite_number(text: str, *, positive: bool) -> float:
    """A finite number, positive or at least 0; argparse names the option in its message."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value) or value < 0 or (positive and value == 0):
        raise argparse.ArgumentTypeError(f"expected a {'positive' if positive else 'non-negative'} number, got {text}")
    return value


def any_finite_number(text: str) -> float:
    """A finite number of either sign."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text}")
    return value


def positive_number(text: str) -> float:
    """A finite number above 0."""
    return finite_number(text, positive=True)


def non_negative_number(text: str) -> float:
    """A finite number, 0 or more."""
    return finite_number(text, positive=False)


def add_gains_source(p: argparse.ArgumentParser, required: bool = True, tracker: bool = False) -> None:
    """The observer's gains, from --gains-file or --gains (or --tracker, with ``tracker``;
    one of them required unless ``required`` is false), and --sample-rate."""
    g = p.add_argument_group("gains (one of)" if required else "gains (optional: run the observer)")
    src = g.add_mutually_exclusive_group(required=required)
    if tracker:
        src.add_argument("--tracker", type=pathlib.Path, metavar="FILE.json",
                         help="a tracker file (docs/guide/tracker-file.md): the gains and the whole setup (number "
                         "type, input, ADC range, calibration, correction...); an option beside it that says "
                         "otherwise than the file is refused")
    src.add_argument("--gains-file", type=pathlib.Path, metavar="FILE.json",
                     help="gains written by `angletrack design --format json`")
    src.add_argument("--gains", type=float_list, metavar="L1,L2[,L3]",
                     help="discrete gains (dimensionless); needs --sample-rate or a time column")
    p.add_argument("--sample-rate", type=positive_number, metavar="HZ",
                   help="the capture's true sample rate (Hz): overrides the gains file's and the time "
                   "column's, and skips the check of the time column's spacing (rounded, repeated or "
                   "jittered stamps; stamps going back are refused); default: the gains file's, checked "
                   "against the time column")


def add_reader_arguments(p) -> None:
    """The capture-reader options every command that reads a capture shares, beside its
    --columns, --delimiter and --time-unit."""
    p.add_argument("--decimal", choices=[".", ","], metavar="MARK",
                   help="decimal mark of the numbers: '.' or ',' (default: sniffed, ',' for numbers such as "
                   "0,5 beside a ';', tab or blank delimiter)")
    p.add_argument("--skip-rows", type=whole_number, default=0, metavar="N",
                   help="lines skipped before the header (an instrument's metadata; lines of another width "
                   "than the data are skipped without it)")


def whole_number(text: str) -> int:
    """A whole number, 0 or more."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number of at least 0, got {text}")
    return value


def refuse_overwriting_inputs(args: argparse.Namespace, outputs: dict) -> None:
    """Refuses an output that is an input of the command (the capture, the gains file, a
    stored calibration; those it has) or another output, before anything is written."""
    inputs = {"capture": getattr(args, "capture", None), "--gains-file": getattr(args, "gains_file", None),
              "--calibration": getattr(args, "calibration", None), "--tracker": getattr(args, "tracker", None)}
    capture_io.check_outputs(outputs, inputs)


def make_output_directories(outputs: dict) -> None:
    """Before anything is computed: makes the outputs' directories (as ``mkdir -p``), and
    refuses an output that is a directory or whose directory cannot be made or written in, in
    one line naming its flag (the keys of ``outputs``; ``None`` paths left out)."""
    for flag, path in outputs.items():
        if path is None:
            continue
        path = pathlib.Path(path)
        if path.is_dir():
            raise ValueError(f"{flag}: {path} is a directory: give a file name")
        in_the_way = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
        if in_the_way is not None:
            raise ValueError(f"{flag}: {path}: {in_the_way} is a file, not a directory")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise ValueError(f"{flag}: {path}: cannot make its directory: {e.strerror or e}") from None
        if not os.access(path.parent, os.W_OK | os.X_OK):
            raise ValueError(f"{flag}: {path}: its directory is not writable")


#: The format of a file an output's extension names (gains, a calibration); a tracker file
#: is JSON too.
_FORMAT_OF_EXTENSION = {".h": "c", ".hpp": "c", ".rs": "rust", ".json": "json"}


def output_format(given: Optional[str], output: Optional[pathlib.Path], default: str) -> str:
    """The format to write: ``given`` (--format), else the one the output's extension names
    (.h c, .rs rust, .json json), else ``default``. A --format other than the extension's is
    refused: the file would hold one format under another's name."""
    named = _FORMAT_OF_EXTENSION.get(output.suffix.lower()) if output is not None else None
    if given == "tracker" and named == "json":
        return given
    if given is not None and named is not None and given != named:
        raise ValueError(f"format: --format {given} does not match --output {output} ({named}); "
                         "give one of them, or both alike")
    return given or named or default


def png_path(text: str):
    """A .png file name; ``""`` (the option without its value) stays ``""``: the command's
    default name."""
    if text and not text.lower().endswith(".png"):
        raise argparse.ArgumentTypeError(f"expected a file name ending in .png, got {text!r}")
    return pathlib.Path(text) if text else ""
