"""What ``angletrack plot`` computes from a capture, chunk by chunk in constant memory: the
ellipse of the Lissajous figure (offsets, amplitude ratio, quadrature), the angle error
binned over the electrical turn with its harmonic spectrum, where the observer's start-up
ends (its lock), and thinned series for plotting (a min/max envelope over time, a uniform
random subsample of a scatter).

Each accumulator takes chunks (``add``) and gives its result at any time, so that a capture
of 1e8 rows costs the memory of one chunk plus a fixed number of plotted points.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Optional

import numpy as np

#: Bins of the electrical turn for the angle error (0.5 degree each): fine enough that the
#: binning attenuates harmonic 10 by less than 0.03 % (sinc(10 / 720)).
ERROR_BINS = 720
#: Harmonic orders shown in the spectrum.
HARMONIC_ORDERS = tuple(range(1, 11))
#: The widest gap without samples (fraction of the electrical turn) that the spectrum
#: interpolates over; a wider one would invent the error there.
WIDEST_GAP = 0.1


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles (rad) wrapped into [-pi, pi)."""
    return np.remainder(angle + math.pi, 2 * math.pi) - math.pi


@dataclasses.dataclass(frozen=True)
class EllipseFit:
    """The Lissajous ellipse ``y_c = o_c + a_c cos(theta)``, ``y_s = o_s + a_s sin(theta +
    quadrature)`` (the scenario generator's sensor model without harmonics or noise)."""

    offset_cos: float
    offset_sin: float
    amplitude_cos: float
    amplitude_sin: float
    #: Quadrature error (rad): the sine channel's phase lead over 90 degrees.
    quadrature_rad: float

    @property
    def amplitude_ratio(self) -> float:
        """``a_s / a_c``; ``1 + amplitude_imbalance`` of the sensor model."""
        return self.amplitude_sin / self.amplitude_cos

    def points(self, count: int = 361) -> tuple[np.ndarray, np.ndarray]:
        """``count`` points (y_c, y_s) around the fitted ellipse."""
        theta = np.linspace(0.0, 2 * math.pi, count)
        return (
            self.offset_cos + self.amplitude_cos * np.cos(theta),
            self.offset_sin + self.amplitude_sin * np.sin(theta + self.quadrature_rad),
        )

    def describe(self) -> str:
        """One line with the fitted figures, for a title or a terminal."""
        return (
            f"offsets y_c {self.offset_cos:+.4g}, y_s {self.offset_sin:+.4g}; amplitude ratio "
            f"a_s/a_c {self.amplitude_ratio:.4f}; quadrature {1e3 * self.quadrature_rad:+.3g} mrad"
        )


class ConicMoments:
    """The least-squares conic fit's scatter matrix ``sum d d^T``, ``d = (x^2, xy, y^2, x, y,
    1)``, summed over chunks. ``x, y`` are shifted and scaled by the first chunk's mean and
    spread (one scale for both, so that the quadrature is unchanged) to keep the 6x6 system
    well conditioned for signals of any offset and amplitude."""

    def __init__(self) -> None:
        self.scatter = np.zeros((6, 6))
        self.count = 0
        self.shift: Optional[tuple[float, float]] = None
        self.scale = 1.0

    def add(self, y_c: np.ndarray, y_s: np.ndarray) -> None:
        finite = np.isfinite(y_c) & np.isfinite(y_s)
        y_c, y_s = y_c[finite], y_s[finite]
        if len(y_c) == 0:
            return
        if self.shift is None:
            self.shift = (float(np.mean(y_c)), float(np.mean(y_s)))
            spread = math.hypot(float(np.std(y_c)), float(np.std(y_s)))
            self.scale = spread if spread > 0 else 1.0
        x = (y_c - self.shift[0]) / self.scale
        y = (y_s - self.shift[1]) / self.scale
        d = np.stack([x * x, x * y, y * y, x, y, np.ones_like(x)])
        self.scatter += d @ d.T
        self.count += len(x)

    def fit(self) -> Optional[EllipseFit]:
        """The ellipse (Fitzgibbon's direct fit, constraint ``4 A C - B^2 = 1``, in Halir and
        Flusser's stable form), or ``None`` when the points fit no ellipse (too few, on a
        line, or all at one point)."""
        if self.count < 6 or self.shift is None:
            return None
        s1, s2, s3 = self.scatter[:3, :3], self.scatter[:3, 3:], self.scatter[3:, 3:]
        try:
            t = -np.linalg.solve(s3, s2.T)
        except np.linalg.LinAlgError:
            return None
        m = s1 + s2 @ t
        m = np.array([m[2] / 2, -m[1], m[0] / 2])
        values, vectors = np.linalg.eig(m)
        vectors = np.real(vectors)
        condition = 4 * vectors[0] * vectors[2] - vectors[1] ** 2
        candidates = np.flatnonzero(condition > 0)
        if len(candidates) == 0:
            return None
        a1 = vectors[:, candidates[0]]
        return _ellipse_of_conic(np.concatenate([a1, t @ a1]), self.shift, self.scale)


def _ellipse_of_conic(conic: np.ndarray, shift: tuple[float, float], scale: float) -> Optional[EllipseFit]:
    """``A x^2 + B xy + C y^2 + D x + E y + F = 0`` (in shifted, scaled coordinates) as the
    sensor model's offsets, amplitudes and quadrature. Centred, the model's ellipse is
    ``u^2 / a_c^2 - 2 sin(q) u v / (a_c a_s) + v^2 / a_s^2 = cos(q)^2``."""
    a, b, c, d, e, f = conic
    try:
        u0, v0 = np.linalg.solve([[2 * a, b], [b, 2 * c]], [-d, -e])
    except np.linalg.LinAlgError:
        return None
    centre_value = a * u0 * u0 + b * u0 * v0 + c * v0 * v0 + d * u0 + e * v0 + f
    if centre_value == 0:
        return None
    alpha, beta, gamma = -a / centre_value, -b / centre_value, -c / centre_value
    if not (alpha > 0 and gamma > 0):
        return None
    sin_q = -beta / (2 * math.sqrt(alpha * gamma))
    if abs(sin_q) >= 1:
        return None
    q = math.asin(sin_q)
    cos_q = math.cos(q)
    return EllipseFit(
        offset_cos=shift[0] + scale * float(u0),
        offset_sin=shift[1] + scale * float(v0),
        amplitude_cos=scale / (cos_q * math.sqrt(alpha)),
        amplitude_sin=scale / (cos_q * math.sqrt(gamma)),
        quadrature_rad=q,
    )


class AngleErrorBins:
    """The angle error (rad) averaged in :data:`ERROR_BINS` bins of the electrical angle over
    one turn: the error as a function of the angle, whatever the speed profile (a plain
    average over time would weight the angles the shaft lingers at)."""

    def __init__(self, bins: int = ERROR_BINS) -> None:
        self.sums = np.zeros(bins)
        self.squares = 0.0
        self.counts = np.zeros(bins, dtype=np.int64)

    def add(self, angle_rad: np.ndarray, error_rad: np.ndarray) -> None:
        keep = np.isfinite(angle_rad) & np.isfinite(error_rad)
        angle_rad, error_rad = angle_rad[keep], error_rad[keep]
        bins = len(self.counts)
        index = np.floor(np.remainder(angle_rad, 2 * math.pi) * (bins / (2 * math.pi))).astype(np.int64)
        index = np.minimum(index, bins - 1)
        self.sums += np.bincount(index, weights=error_rad, minlength=bins)
        self.counts += np.bincount(index, minlength=bins)
        self.squares += float(np.dot(error_rad, error_rad))

    @property
    def count(self) -> int:
        return int(self.counts.sum())

    def rms_rad(self) -> float:
        """RMS of every error sample added (rad)."""
        return math.sqrt(self.squares / self.count) if self.count else float("nan")

    def centres_rad(self) -> np.ndarray:
        """The bins' centre angles (rad), in [0, 2 pi)."""
        bins = len(self.counts)
        return (np.arange(bins) + 0.5) * (2 * math.pi / bins)

    def mean_error_rad(self) -> np.ndarray:
        """The mean error per bin (rad); empty bins interpolated around the turn, ``NaN``
        everywhere without samples."""
        filled = self.counts > 0
        if not filled.any():
            return np.full(len(self.counts), np.nan)
        means = np.zeros(len(self.counts))
        means[filled] = self.sums[filled] / self.counts[filled]
        if not filled.all():
            x = self.centres_rad()
            means[~filled] = np.interp(x[~filled], x[filled], means[filled], period=2 * math.pi)
        return means

    def widest_gap(self) -> float:
        """The widest run of bins without samples, around the turn (fraction of the turn):
        a phase-locked sample rate fills only some bins, evenly spread, which is no gap."""
        filled = np.flatnonzero(self.counts)
        if len(filled) == 0:
            return 1.0
        steps = np.diff(np.append(filled, filled[0] + len(self.counts)))
        return float(steps.max() - 1) / len(self.counts)

    def harmonics_rad(self, orders=HARMONIC_ORDERS) -> np.ndarray:
        """Amplitudes (rad, peak) of the error's harmonics of the electrical angle, ``e =
        sum_k A_k cos(k theta + phi_k)``, from the binned mean over the turn; ``NaN`` when
        the samples leave a gap wider than :data:`WIDEST_GAP` of the turn."""
        means = self.mean_error_rad()
        if self.widest_gap() > WIDEST_GAP or not np.isfinite(means).all():
            return np.full(len(orders), np.nan)
        spectrum = np.fft.rfft(means) * (2.0 / len(means))
        return np.abs(spectrum[list(orders)])


class Envelope:
    """A series over time decimated to at most ``max_points`` blocks, each kept as its
    smallest and largest value (so that a spike of one sample still shows): blocks double
    in length whenever the points would exceed the limit."""

    def __init__(self, max_points: int) -> None:
        self.max_points = max(2, int(max_points))
        self.block = 1
        self.time = np.empty(0)
        self.low = np.empty(0)
        self.high = np.empty(0)
        self._pending: tuple[np.ndarray, np.ndarray] = (np.empty(0), np.empty(0))

    def add(self, time_s: np.ndarray, values: np.ndarray) -> None:
        time_s = np.concatenate([self._pending[0], time_s])
        values = np.concatenate([self._pending[1], np.asarray(values, dtype=np.float64)])
        whole = len(values) // self.block * self.block
        self._pending = (time_s[whole:], values[whole:])
        blocks = values[:whole].reshape(-1, self.block)
        self.time = np.concatenate([self.time, time_s[:whole:self.block]])
        self.low = np.concatenate([self.low, blocks.min(axis=1)])
        self.high = np.concatenate([self.high, blocks.max(axis=1)])
        while len(self.time) > self.max_points:
            self._halve()

    def _halve(self) -> None:
        even = len(self.time) // 2 * 2
        tail = slice(even, None)
        self.time = np.concatenate([self.time[:even:2], self.time[tail]])
        self.low = np.concatenate([np.minimum(self.low[:even:2], self.low[1:even:2]), self.low[tail]])
        self.high = np.concatenate([np.maximum(self.high[:even:2], self.high[1:even:2]), self.high[tail]])
        self.block *= 2

    def series(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(time, low, high) of every block, the last partial block included."""
        t, v = self._pending
        if len(v) == 0:
            return self.time, self.low, self.high
        return (
            np.append(self.time, t[0]),
            np.append(self.low, v.min()),
            np.append(self.high, v.max()),
        )


class RandomSample:
    """A uniform random subsample of a scatter, at most ``max_points`` points, chunk by chunk:
    each point gets a random key and the points of the smallest keys are kept (bottom-k
    sampling). Unlike every n-th point, it cannot alias with a capture's periodicity (200
    samples per turn thinned by 8 would keep 25 angles)."""

    def __init__(self, max_points: int, seed: int = 0) -> None:
        self.max_points = max(2, int(max_points))
        self.seen = 0
        self._rng = np.random.default_rng(seed)
        self._keys = np.empty(0)
        self._order = np.empty(0, dtype=np.int64)
        self.columns: Optional[list[np.ndarray]] = None

    def add(self, *columns: np.ndarray) -> None:
        n = len(columns[0])
        keys = self._rng.random(n)
        order = self.seen + np.arange(n, dtype=np.int64)
        self.seen += n
        picked = [np.asarray(c, dtype=np.float64) for c in columns]
        if self.columns is not None and len(self._keys) >= self.max_points:
            # Full: only a key below the largest kept one can enter.
            entering = keys < self._keys.max()
            keys, order, picked = keys[entering], order[entering], [c[entering] for c in picked]
        if self.columns is not None:
            keys = np.concatenate([self._keys, keys])
            order = np.concatenate([self._order, order])
            picked = [np.concatenate(p) for p in zip(self.columns, picked)]
        if len(keys) > self.max_points:
            kept = np.argpartition(keys, self.max_points - 1)[: self.max_points]
            keys, order, picked = keys[kept], order[kept], [c[kept] for c in picked]
        self._keys, self._order, self.columns = keys, order, picked

    def points(self) -> list[np.ndarray]:
        """The kept points' columns, in the order they were added."""
        if self.columns is None:
            return []
        ordered = np.argsort(self._order, kind="stable")
        return [c[ordered] for c in self.columns]


#: The observer is locked once its error has stayed within the tolerance for this many time
#: constants of the loop's slowest pole (2 % of an exponential after 3.9 of them), averaged
#: over blocks of an eighth of one.
LOCK_HOLD_TIME_CONSTANTS = 4.0
LOCK_BLOCKS_PER_TIME_CONSTANT = 8


def slowest_time_constant_samples(loop_polynomial: list[float]) -> float:
    """The time constant (samples) of the slowest closed-loop pole, from the polynomial in
    ``s = z - 1`` (lowest power first, as ``Gains.loop_polynomial``)."""
    poles = 1.0 + np.roots(np.asarray(loop_polynomial, dtype=np.float64)[::-1])
    radius = float(np.abs(poles).max())
    return -1.0 / math.log(radius) if 0.0 < radius < 1.0 else math.inf


class LockDetector:
    """Where the observer's start-up ends, chunk by chunk. The error is averaged over blocks
    of ``block`` samples (the loop's transient is slow beside a block; the sensor's noise is
    averaged down), and the lock is the first sample after ``hold`` samples' worth of
    consecutive blocks whose mean is within ``tolerance_rad`` (a block with a NaN is
    outside). From the lock on every sample counts, whatever its error. The samples must
    come in order from the capture's first."""

    def __init__(self, tolerance_rad: float, hold: int, block: int = 1) -> None:
        self.tolerance_rad = tolerance_rad
        self.block = max(1, int(block))
        self.hold_blocks = max(1, -(-int(hold) // self.block))
        #: Index of the lock sample, once reached.
        self.lock_index: Optional[int] = None
        self._pending = np.empty(0)
        self._blocks = 0
        self._run_start: Optional[int] = None

    @property
    def hold(self) -> int:
        """The samples the error must stay within the tolerance for."""
        return self.hold_blocks * self.block

    def add(self, first_index: int, error_rad: np.ndarray) -> np.ndarray:
        """The chunk's mask of samples at or after the lock (``first_index`` is the
        chunk's first sample in the capture)."""
        n = len(error_rad)
        if self.lock_index is None:
            error = np.concatenate([self._pending, np.asarray(error_rad, dtype=np.float64)])
            whole = len(error) // self.block * self.block
            self._pending = error[whole:]
            means = error[:whole].reshape(-1, self.block).mean(axis=1)
            first_block = self._blocks
            self._blocks += len(means)
            outside = first_block + np.flatnonzero(~(np.abs(means) <= self.tolerance_rad))
            run_start = first_block if self._run_start is None else self._run_start
            starts = np.concatenate([[run_start], outside + 1])
            ends = np.append(outside, self._blocks)  # the last run is still open
            long_enough = np.flatnonzero(ends - starts > self.hold_blocks)
            if len(long_enough):
                # A block begun in the previous chunk: its samples there are past.
                lock = (int(starts[long_enough[0]]) + self.hold_blocks) * self.block
                self.lock_index = max(lock, first_index)
                self._pending = np.empty(0)
            self._run_start = int(starts[-1])
        if self.lock_index is None:
            return np.zeros(n, dtype=bool)
        return first_index + np.arange(n) >= self.lock_index
