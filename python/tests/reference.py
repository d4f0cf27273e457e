"""An independent, plain-Python restatement of the observer recursion (the scaled discrete
state and the predictor-corrector recursion, with wrapping and turn counting:
docs/theory.md §5; the phase error normalised by the signal's magnitude, as float64 does it:
docs/theory.md §12), used to check the Rust results sample by sample. Slow on purpose: it is
the specification.
"""

import math
import sys

import numpy as np


def _wrap(angle, turns):
    if angle >= math.pi or angle < -math.pi:
        k = math.floor((angle + math.pi) / (2.0 * math.pi))
        angle -= k * 2.0 * math.pi
        turns += k
    return angle, turns


def run(gains, sample_period, y_c, y_s):
    """Runs the predictor-corrector observer with discrete gains ``gains`` (length 2 or 3)
    over the samples; returns a dict of float64 arrays (angle, position, speed, acceleration,
    phase_error)."""
    n_states = len(gains)
    out = {k: np.zeros(len(y_c)) for k in ("angle", "position", "speed", "acceleration", "phase_error")}
    x = None
    turns = 0
    for k, (c, s) in enumerate(zip(y_c, y_s)):
        c, s = float(c), float(s)
        if x is None:
            x = [math.atan2(s, c)] + [0.0] * (n_states - 1)
            eps = 0.0
        else:
            # X_p = A X_e, A = [[1, 1, 1/2], [0, 1, 1], [0, 0, 1]] (or its 2x2 block).
            if n_states == 3:
                p = [x[0] + x[1] + 0.5 * x[2], x[1] + x[2], x[2]]
            else:
                p = [x[0] + x[1], x[1]]
            p[0], turns = _wrap(p[0], turns)
            # The smallest normal float keeps the magnitude positive: a zero sample gives 0.
            magnitude = math.sqrt(c * c + s * s + sys.float_info.min)
            eps = (s * math.cos(p[0]) - c * math.sin(p[0])) / magnitude
            if not math.isfinite(eps):
                eps = 0.0
            x = [p[i] + gains[i] * eps for i in range(n_states)]
        x[0], turns = _wrap(x[0], turns)
        out["angle"][k] = x[0]
        out["position"][k] = turns * 2.0 * math.pi + x[0]
        out["speed"][k] = x[1] / sample_period
        out["acceleration"][k] = x[2] / sample_period**2 if n_states == 3 else 0.0
        out["phase_error"][k] = eps
    return out
