"""Gains for firmware: a C header, a Rust ``const`` block, or JSON (``angletrack design``).

The C header and the Rust block hold the gains rounded to the firmware's float type
(float32 by default: the shortest decimal that rounds back to the same float32), as the Rust
crate's ``angletrack::export`` writes them; the JSON file holds them in float64, exactly (it
round-trips into the same :class:`Gains`).
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

from angletrack import _angletrack
from angletrack._angletrack import ConfigError, Gains

if TYPE_CHECKING:
    from angletrack._angletrack import _FixedConstants as FixedConstants

JSON_FORMAT = "angletrack-gains"
JSON_VERSION = 1


def to_c_header(gains: Gains, *, name: str = "angletrack", dtype: str = "float32", description: str = "") -> str:
    """A self-contained C header with the gains, the sample period and the order.

    ``name`` prefixes every identifier (``NAME_GAINS``, ``NAME_SAMPLE_PERIOD_S``, ...); the
    Rust crate's ``angletrack::export::gains_c_header`` writes it.
    """
    return _angletrack.gains_c_header(gains, name=name, dtype=dtype, description=description)


def to_rust(gains: Gains, *, name: str = "angletrack", dtype: str = "float32", description: str = "") -> str:
    """A Rust ``const`` block for ``angletrack_core::Gains::<T, N>::new(GAINS, SAMPLE_PERIOD_S)``
    (``angletrack::export::gains_rust``)."""
    return _angletrack.gains_rust(gains, name=name, dtype=dtype, description=description)


def to_json(gains: Gains, *, metadata: dict[str, Any] | None = None) -> str:
    """JSON with the gains and the sample period in float64 (exact round trip), plus
    ``metadata`` (the design's method and specification)."""
    doc = {
        "format": JSON_FORMAT,
        "version": JSON_VERSION,
        "order": gains.order,
        "sample_period_s": gains.sample_period_s,
        "gains": list(gains.gains),
    }
    if metadata:
        doc["design"] = metadata
    return json.dumps(doc, indent=2) + "\n"


def json_document(text: str, what: str, format: str, version: int) -> dict:
    """The JSON object of ``text``, checked to be a ``format`` document of ``version``;
    ``ValueError`` starting with ``what`` (``"gains file"``) otherwise."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise ValueError(f"{what}: not JSON ({e})") from None
    if not isinstance(doc, dict) or doc.get("format") != format:
        raise ValueError(f"{what}: not an {format} document")
    if doc.get("version") != version:
        raise ValueError(f"{what}: version {doc.get('version')!r} is not supported (expected {version})")
    return doc


def gains_from_json(text: str) -> Gains:
    """The :class:`Gains` of a JSON document written by :func:`to_json` (checked again)."""
    doc = json_document(text, "gains file", JSON_FORMAT, JSON_VERSION)
    for key in ("gains", "sample_period_s"):
        if key not in doc:
            raise ValueError(f"gains file: missing {key!r}")
    order = doc.get("order")
    if order is not None and (not isinstance(doc["gains"], list) or order != len(doc["gains"])):
        # An order that contradicts the gains is a file edited by hand: neither is trusted.
        count = len(doc["gains"]) if isinstance(doc["gains"], list) else "no list of"
        e = ConfigError(f"order: the gains file says order {order!r} but holds {count} gains")
        e.parameter = "order"
        raise e
    return Gains(doc["gains"], sample_period_s=doc["sample_period_s"])


FIXED_JSON_FORMAT = "angletrack-fixed-gains"


def fixed_to_c_header(constants: FixedConstants, *, name: str = "angletrack", description: str = "") -> str:
    """A C header with the fixed-point constants of a design (``docs/theory.md §14``): the
    gains' multipliers and the acceleration's shift, for
    ``angletrack_core::FixedGains::from_constants``, which checks them again
    (``angletrack::export::fixed_c_header``)."""
    return _angletrack.fixed_c_header(constants, name=name, description=description)


def fixed_to_rust(constants: FixedConstants, *, name: str = "angletrack", description: str = "") -> str:
    """A Rust ``const`` for ``angletrack_core::FixedGains::<N>::from_constants(CONSTANTS, Ts)``
    (``angletrack::export::fixed_rust``)."""
    return _angletrack.fixed_rust(constants, name=name, description=description)


def fixed_to_json(constants: FixedConstants, *, metadata: dict[str, Any] | None = None) -> str:
    """JSON with the fixed-point constants, the gains they represent and the sample period."""
    doc = {"format": FIXED_JSON_FORMAT, "version": JSON_VERSION, "order": len(constants["multiplier"]), **constants}
    if metadata:
        doc["design"] = metadata
    return json.dumps(doc, indent=2) + "\n"
