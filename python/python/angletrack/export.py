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
from angletrack._angletrack import Gains

if TYPE_CHECKING:
    from angletrack._angletrack import _FixedConstants as FixedConstants

JSON_FORMAT = _angletrack.GAINS_FILE_FORMAT
JSON_VERSION = _angletrack.GAINS_FILE_VERSION


def to_c_header(gains: Gains, *, name: str = "angletrack", dtype: str = "float32", description: str = "") -> str:
    """A self-contained C header with the gains, the sample period and the order.

    ``name`` prefixes every identifier (``NAME_GAINS``, ``NAME_SAMPLE_PERIOD_S``, ...); the
    Rust crate's ``angletrack::export::gains_c_header`` writes it.
    """
    return _angletrack.gains_source(gains, "c", name=name, dtype=dtype, description=description)


def to_rust(gains: Gains, *, name: str = "angletrack", dtype: str = "float32", description: str = "") -> str:
    """A Rust ``const`` block for ``angletrack_core::Gains::<T, N>::new(GAINS, SAMPLE_PERIOD_S)``
    (``angletrack::export::gains_rust``)."""
    return _angletrack.gains_source(gains, "rust", name=name, dtype=dtype, description=description)


def to_json(gains: Gains, *, metadata: dict[str, Any] | None = None) -> str:
    """JSON with the gains and the sample period in float64 (exact round trip), plus
    ``metadata`` (the design's method and specification) under ``design``
    (``angletrack::export::GainsFile``)."""
    return _angletrack.gains_file_json(gains, json.dumps(metadata) if metadata else None)


def gains_from_json(text: str, file: str = "gains file") -> Gains:
    """The :class:`Gains` of a JSON document written by :func:`to_json`, checked by the core
    (``ValueError`` naming ``file`` and the field: another format or version, an ``order``
    that contradicts the gains, gains the core refuses)."""
    gains, sample_period_s = _angletrack.read_gains_file(text, file)
    return Gains(gains, sample_period_s=sample_period_s)


FIXED_JSON_FORMAT = _angletrack.FIXED_GAINS_FILE_FORMAT


def fixed_to_c_header(constants: FixedConstants, *, name: str = "angletrack", description: str = "") -> str:
    """A C header with the fixed-point constants of a design (``docs/theory.md §14``): the
    gains' multipliers and the acceleration's shift, for
    ``angletrack_core::FixedGains::from_constants``, which checks them again
    (``angletrack::export::fixed_c_header``)."""
    return _angletrack.fixed_source(constants, "c", name=name, description=description)


def fixed_to_rust(constants: FixedConstants, *, name: str = "angletrack", description: str = "") -> str:
    """A Rust ``const`` for ``angletrack_core::FixedGains::<N>::from_constants(CONSTANTS, Ts)``
    (``angletrack::export::fixed_rust``)."""
    return _angletrack.fixed_source(constants, "rust", name=name, description=description)


def fixed_to_json(constants: FixedConstants, *, metadata: dict[str, Any] | None = None) -> str:
    """JSON with the fixed-point constants, the gains they represent and the sample period
    (``angletrack::export::FixedGainsFile``)."""
    return _angletrack.fixed_gains_file_json(constants, json.dumps(metadata) if metadata else None)


def fixed_from_json(text: str, file: str = "gains file") -> FixedConstants:
    """The constants of a JSON document written by :func:`fixed_to_json`, checked by the core
    (``FixedGains::from_constants``), as ``Design.fixed_constants()`` gives them."""
    return _angletrack.read_fixed_gains_file(text, file)
