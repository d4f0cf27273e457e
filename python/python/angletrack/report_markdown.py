"""The Markdown pieces of ``angletrack report``'s sections: numbers, tables, figures."""

from __future__ import annotations

import math
from typing import Optional


def pct(x: Optional[float]) -> str:
    """A fraction as a percentage, ``-`` for ``None``."""
    return "-" if x is None else f"{100.0 * x:.2f} %"


def num(x: Optional[float], fmt: str = ".3g", scale: float = 1.0) -> str:
    """``x * scale`` in ``fmt``, ``-`` for ``None`` or ``NaN``."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return format(x * scale, fmt)


def table(header: list[str], rows: list[list[str]]) -> str:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(" --- " for _ in header) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def khz(sample_period_s: float) -> str:
    """The sample rate of ``sample_period_s`` in kHz."""
    return f"{1 / sample_period_s / 1e3:.0f} kHz"


def figure(plots: bool, caption: str, file: str) -> list[str]:
    """The lines of a figure (empty without plots)."""
    return ["", f"![{caption}]({file})" if plots else "", ""]
