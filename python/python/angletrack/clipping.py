"""The ADC range of a capture, against which ``angletrack track`` flags clipping: stated
(``--adc-range MIN,MAX``, or ``--adc-bits N`` with ``--adc-signed`` or ``--adc-unsigned``, which
also state the counts' signedness alone), or
else measured on the first chunk (an extreme held flat over several consecutive samples, with
the samples piled up there, as a clipped signal's are and a clean one's are not), or else
measured as the samples come by the observer's chain (the same test, sample by sample: the
core's ``HeldRailCheck``).

A sample at or beyond the range in either channel is flagged ``Faults.FRONT_END``
(``CLIPPING`` among the front-end faults); one clipped in both channels is not used: the
observer coasts on its prediction (``docs/theory.md §15``).
"""

from __future__ import annotations

import argparse
from typing import Optional

import numpy as np

from angletrack._angletrack import HELD_RAIL_SAMPLES, measured_adc_range

#: Consecutive samples at an extreme that make it a rail (the crate's rule).
FLAT_SAMPLES = HELD_RAIL_SAMPLES


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ADC range options (one group)."""
    g = parser.add_argument_group(
        "the ADC's range (clipping)",
        "a sample at or beyond the range in either channel is flagged FRONT_END (clipping); one clipped in "
        "both channels is not used (the observer coasts on its prediction); default: the capture's extremes "
        f"when held flat over {FLAT_SAMPLES} or more consecutive samples (a clipped signal) in the first chunk, "
        "else the rails measured the same way as the samples come (with --carrier-hz: the smallest "
        "power-of-two range holding the windings' samples)",
    )
    g.add_argument("--adc-range", metavar="MIN,MAX",
                   help="the ADC's lowest and highest values in the capture's units (counts or volts), "
                   "e.g. 0,4095 or -0.9,0.9")
    g.add_argument("--adc-bits", type=int, metavar="N",
                   help="the ADC's resolution (bits), with --adc-signed (-2^(N-1) to 2^(N-1)-1) or "
                   "--adc-unsigned (0 to 2^N-1)")
    add_signedness(g)


def add_signedness(parser) -> None:
    """``--adc-signed`` and ``--adc-unsigned``: the counts' signedness, stated (else read from
    the whole capture by the crate's rule, ``angletrack::capture_counts``)."""
    sign = parser.add_mutually_exclusive_group()
    sign.add_argument("--adc-signed", dest="adc_signed", action="store_true", default=None,
                      help="the counts are two's complement (a zero signal reads 0); with --adc-bits: the "
                      "ADC's range too; default: read from the whole capture (a negative sample: signed; both "
                      "channels swinging about 2^(N-1): unsigned; else refused)")
    sign.add_argument("--adc-unsigned", dest="adc_signed", action="store_false",
                      help="the counts are offset binary (a zero signal reads 2^(N-1), N from --adc-bits or the "
                      "smallest range holding the capture's largest sample); with --adc-bits: the ADC's range too")


def joined_negative_range(argv: list[str]) -> list[str]:
    """``argv`` with ``--adc-range -0.9,0.9`` written ``--adc-range=-0.9,0.9``: a value that
    starts with ``-`` and holds a comma is taken for an option by ``argparse``."""
    out: list[str] = []
    for arg in argv:
        if out and out[-1] == "--adc-range" and arg.startswith("-") and "," in arg:
            out[-1] = f"--adc-range={arg}"
        else:
            out.append(arg)
    return out


def integer_range(adc_range: Optional[tuple[float, float]], what: str) -> Optional[tuple[int, int]]:
    """``adc_range`` in whole counts for the fixed-point chain, or a one-line ``ValueError``
    naming ``what`` (the option the range came from) when a bound is not a whole number."""
    if adc_range is None:
        return None
    low, high = adc_range
    if low != int(low) or high != int(high) or not -(2**31) <= low < high < 2**31:
        raise ValueError(f"adc_range: --dtype fixed takes whole counts; {what} is {low:g} to {high:g}")
    return int(low), int(high)


def stated_range(args: argparse.Namespace) -> Optional[tuple[float, float]]:
    """The range the options state (``None``: none), or a one-line ``ValueError`` naming the
    option."""
    bits, signed = getattr(args, "adc_bits", None), getattr(args, "adc_signed", None)
    text = getattr(args, "adc_range", None)
    if text is not None:
        if bits is not None:
            raise ValueError("adc_range: give --adc-range or --adc-bits, not both")
        parts = text.split(",")
        try:
            low, high = (float(p) for p in parts)
        except ValueError:
            raise ValueError(f"adc_range: --adc-range {text!r}: expected MIN,MAX (two numbers)") from None
        if not (np.isfinite(low) and np.isfinite(high) and low < high):
            raise ValueError(f"adc_range: --adc-range {text}: expected finite MIN < MAX")
        return low, high
    if bits is None:
        return None
    if not 2 <= bits <= 32:
        raise ValueError(f"adc_range: --adc-bits {bits}: expected 2 to 32")
    if signed is None:
        raise ValueError(f"adc_range: --adc-bits {bits} needs --adc-signed or --adc-unsigned")
    if signed:
        return -(2.0 ** (bits - 1)), 2.0 ** (bits - 1) - 1.0
    return 0.0, 2.0**bits - 1.0


def stated_counts(args: argparse.Namespace) -> tuple[Optional[bool], Optional[int]]:
    """The counts' signedness and resolution the options state (``None``: not stated):
    ``--adc-signed``/``--adc-unsigned`` and ``--adc-bits``, or a stated ``--adc-range``
    (signed when it holds negative values; the resolution of an unsigned range 0 to
    ``2^N - 1``)."""
    signed, bits = getattr(args, "adc_signed", None), getattr(args, "adc_bits", None)
    text = getattr(args, "adc_range", None)
    if text is None or signed is not None:
        return signed, bits
    low, high = stated_range(args) or (0.0, 0.0)
    whole = high + 1.0
    power = whole >= 4 and whole == 2.0 ** round(np.log2(whole))
    return low < 0, (int(round(np.log2(whole))) if low == 0 and power else None)


def measured_range(y_c: np.ndarray, y_s: np.ndarray) -> Optional[tuple[float, float]]:
    """The range measured on the samples (``measured_adc_range``, the crate's rule): an
    extreme (of both channels) that is a rail (held flat over ``FLAT_SAMPLES`` consecutive
    samples, the samples piled up there); an extreme that is not is put one span beyond, so
    that it flags nothing. ``None`` when neither is a rail."""
    return measured_adc_range(np.ascontiguousarray(y_c, dtype=np.float64),
                              np.ascontiguousarray(y_s, dtype=np.float64))


def describe(adc_range: Optional[tuple[float, float]], stated: bool) -> str:
    """The range for the summary (``None``: none stated or found on the first chunk, the
    rails measured as the samples come)."""
    if adc_range is None:
        return (f"ADC range: not given: rails measured as the samples come (extremes held flat over "
                f"{FLAT_SAMPLES}+ samples)")
    how = "stated" if stated else f"measured: extremes held flat over {FLAT_SAMPLES}+ samples"
    return f"ADC range {adc_range[0]:.6g} to {adc_range[1]:.6g} ({how})"
