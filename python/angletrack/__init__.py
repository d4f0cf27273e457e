"""Angle tracking observers (software resolver-to-digital conversion) on numpy arrays.

A resolver (after demodulation), a sin/cos magnetic encoder or high-frequency injection gives
two noisy signals ``y_c ~ cos(theta)`` and ``y_s ~ sin(theta)``. An angle tracking observer
(ATO) turns them into angle (rad), speed (rad/s) and acceleration (rad/s^2), sample by sample.
The observers run in Rust (the ``angletrack-core`` crate) with the GIL released; float32
input stays float32 and float64 stays float64.

>>> import numpy as np, angletrack
>>> gains = angletrack.Gains([0.06, 0.001], sample_period=1e-4)   # 2nd-order ATO, 10 kHz
>>> theta = np.linspace(0.0, 20.0, 10_000)                        # rad
>>> est = angletrack.track(gains, np.cos(theta), np.sin(theta))
>>> round(float(est.position[-1]), 3)
20.0
"""

from angletrack._angletrack import (
    Estimate,
    Estimates,
    Gains,
    Observer,
    __version__,
    track,
)

__all__ = [
    "Estimate",
    "Estimates",
    "Gains",
    "Observer",
    "__version__",
    "track",
]
