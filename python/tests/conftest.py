"""Shared fixtures: gain sets of the three observers and a simulated resolver capture."""

import pathlib

import numpy as np
import pytest

import angletrack

# 10 kHz gains of the three observers of the paper, as the benchmarks and the firmware run
# them (angletrack::paper).
_BENCHMARK = angletrack.paper_benchmark_gains()
SAMPLE_PERIOD = _BENCHMARK[0].sample_period_s
SECOND_ORDER, THIRD_ORDER, KALMAN = (g.gains for g in _BENCHMARK)


@pytest.fixture(params=[SECOND_ORDER, THIRD_ORDER, KALMAN], ids=["order2", "order3", "kalman"])
def gains(request):
    return angletrack.Gains(request.param, sample_period_s=SAMPLE_PERIOD)


def resolver_capture(n=4000, seed=1, noise=0.01, dtype=np.float64):
    """A shaft accelerating at 400 rad/s^2 from 5 rad/s, seen by a noisy resolver."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * SAMPLE_PERIOD
    theta = 0.3 + 5.0 * t + 0.5 * 400.0 * t**2
    y_c = np.cos(theta) + noise * rng.standard_normal(n)
    y_s = np.sin(theta) + noise * rng.standard_normal(n)
    return theta, y_c.astype(dtype), y_s.astype(dtype)


@pytest.fixture
def capture():
    return resolver_capture()


@pytest.fixture
def file_reads(monkeypatch):
    """The names of the files read through ``pathlib.Path.read_text`` or ``read_bytes``
    during the test, one entry per read (to check that a command reads a file once)."""
    reads, inside = [], []

    def counting(read):
        def counted(self, *args, **kwargs):
            # One entry per read, whichever of the two calls the other.
            if not inside:
                reads.append(self.name)
            inside.append(self)
            try:
                return read(self, *args, **kwargs)
            finally:
                inside.pop()
        return counted

    monkeypatch.setattr(pathlib.Path, "read_text", counting(pathlib.Path.read_text))
    monkeypatch.setattr(pathlib.Path, "read_bytes", counting(pathlib.Path.read_bytes))
    return reads
