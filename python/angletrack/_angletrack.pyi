"""Type stubs of the compiled extension ``angletrack._angletrack``."""

from collections.abc import Sequence
from typing import Literal, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Samples = Union[npt.NDArray[np.float32], npt.NDArray[np.float64], Sequence[float]]
_DType = Union[type[np.float32], type[np.float64], np.dtype, Literal["float32", "float64"], None]
_SinCos = Optional[Literal["fast", "exact"]]

class Gains:
    """Discrete gains ``(l1, l2[, l3])`` of the scaled-state recursion and the sample
    period (s), checked against the stability region of the discrete loop."""

    def __init__(self, gains: Sequence[float], sample_period: float) -> None: ...
    @staticmethod
    def from_loop_polynomial(coefficients: Sequence[float], sample_period: float) -> Gains: ...
    @property
    def gains(self) -> list[float]:
        """The discrete gains (dimensionless)."""
    @property
    def loop_polynomial(self) -> list[float]:
        """Closed-loop characteristic polynomial in ``s = z - 1``, lowest first, monic."""
    @property
    def sample_period(self) -> float:
        """Sample period (s)."""
    @property
    def sample_rate_hz(self) -> float:
        """Sample rate (Hz)."""
    @property
    def order(self) -> int:
        """2 (angle, speed) or 3 (angle, speed, acceleration)."""
    def __eq__(self, other: object) -> bool: ...

class Estimate:
    """The estimate after the last sample (scalars)."""

    @property
    def angle(self) -> float:
        """Angle (rad), wrapped to [-pi, pi)."""
    @property
    def turns(self) -> int:
        """Whole turns counted since initialisation."""
    @property
    def position(self) -> float:
        """Multi-turn position ``turns * 2 pi + angle`` (rad)."""
    @property
    def speed(self) -> float:
        """Speed (rad/s)."""
    @property
    def acceleration(self) -> float:
        """Acceleration (rad/s^2); 0 at order 2."""
    @property
    def phase_error(self) -> float:
        """Phase-detector output of the last sample."""

class Estimates:
    """Estimates of a run, one array per quantity. ``position`` is float64; the others
    have the input's dtype."""

    @property
    def angle(self) -> npt.NDArray[np.floating]:
        """Angle (rad), wrapped to [-pi, pi)."""
    @property
    def position(self) -> npt.NDArray[np.float64]:
        """Multi-turn position (rad)."""
    @property
    def speed(self) -> npt.NDArray[np.floating]:
        """Speed (rad/s)."""
    @property
    def acceleration(self) -> npt.NDArray[np.floating]:
        """Acceleration (rad/s^2)."""
    @property
    def phase_error(self) -> npt.NDArray[np.floating]:
        """Phase-detector output per sample."""
    @property
    def dtype(self) -> str:
        """'float32' or 'float64'."""
    @property
    def len(self) -> int:
        """Number of samples."""
    def __len__(self) -> int: ...

class Observer:
    """An observer whose state persists between calls: chunked input gives exactly the
    result of one call."""

    def __init__(self, gains: Gains, *, dtype: _DType = None, sin_cos: _SinCos = None) -> None: ...
    def update(self, y_c: _Samples, y_s: _Samples) -> Estimates:
        """Runs over 1-D samples of the observer's dtype; GIL released."""
    @property
    def estimate(self) -> Estimate: ...
    def reset(self) -> None: ...
    def initialise(self, y_c: float, y_s: float) -> None: ...
    def set_state(self, angle: float, speed: float = 0.0, acceleration: float = 0.0) -> None: ...
    @property
    def is_initialised(self) -> bool: ...
    @property
    def gains(self) -> Gains: ...
    @property
    def dtype(self) -> Literal["float32", "float64"]: ...
    @property
    def sin_cos(self) -> Literal["fast", "exact"]: ...
    @property
    def order(self) -> int: ...
    @property
    def sample_period(self) -> float: ...

def track(gains: Gains, y_c: _Samples, y_s: _Samples, *, sin_cos: _SinCos = None) -> Estimates:
    """Runs a fresh observer over the samples in their own dtype (float32 or float64)."""
