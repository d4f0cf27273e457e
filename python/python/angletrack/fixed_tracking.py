"""``angletrack track --dtype fixed``: what the fixed-point chain (the core's ``Tracker`` on
16-bit counts, run by ``angletrack.tracker_run``) writes, and the options it cannot run.
The counts' mid-scale is the capture's (stated, or read from the whole capture:
``tracking.counts_mid_scale``); the shift to 16 bits is the ADC's (``16 - bits``) when its
bits are stated, else measured on the first samples by the Rust crate; the calibration is
learned in float (``angletrack calibrate`` or ``track --calibrate``) and applied in integers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import numpy as np

if TYPE_CHECKING:
    from angletrack.tracking import TrackSettings

#: The columns ``track --dtype fixed`` writes and their dtypes: the estimates in physical
#: units beside the firmware's binary angle (2^32 per turn).
COLUMNS = [("time_s", np.float64), ("angle_rad", np.float64), ("position_rad", np.float64),
           ("speed_rad_s", np.float64), ("acceleration_rad_s2", np.float64), ("phase_error", np.float64),
           ("faults", np.uint8), ("angle_binary", np.int32)]


def refusal(s: "TrackSettings") -> Optional[str]:
    """The one-line refusal of a combination of options ``--dtype fixed`` cannot run, naming
    both flags and why; ``None`` when it can."""
    if s.carrier_hz is not None:
        return ("dtype: --dtype fixed with --carrier-hz: the demodulator's pairs are float64; track them "
                "with --dtype float32 or float64")
    if s.sin_cos is not None:
        return "dtype: --dtype fixed with --sin-cos: the fixed-point observer has its own Q15 sin/cos table"
    if s.observer_arguments.get("calibration") == "learn":
        return ("dtype: --dtype fixed with --calibrate: the online calibration learns in float; learn it "
                "with --calibrate (float64) or `angletrack calibrate`, then apply it with --dtype fixed "
                "--calibration FILE")
    return None
