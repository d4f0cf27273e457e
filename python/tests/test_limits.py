"""Arguments too large for memory, and states that are not numbers: each is an exception the
caller can catch (MemoryError, ValueError), never an abort or a PanicException."""

import numpy as np
import pytest

import angletrack

GAINS = angletrack.Gains([0.06, 0.001], sample_period_s=1e-4)


def test_a_batch_of_more_channels_than_memory_is_refused():
    with pytest.raises(angletrack.ConfigError) as raised:
        angletrack.ObserverBatch(GAINS, 2**40)
    assert raised.value.parameter == "channels"
    assert "fits in memory" in str(raised.value)


def test_a_broadcast_array_larger_than_memory_is_a_memory_error():
    huge = np.broadcast_to(np.ones(1), (2**36,))
    with pytest.raises(MemoryError, match="y_c: 549755813888 bytes are needed"):
        angletrack.track(GAINS, huge, huge)


def test_a_memmap_larger_than_memory_is_a_memory_error(tmp_path):
    # A sparse file: 2**33 float64 samples (64 GiB) that take no disk.
    path = tmp_path / "huge.f64"
    with open(path, "wb") as f:
        f.truncate(2**33 * 8)
    samples = np.memmap(path, dtype=np.float64, mode="r", shape=(2**33,))
    with pytest.raises(MemoryError, match=f"y_c: {2**33 * (5 * 8 + 1)} bytes are needed"):
        angletrack.track(GAINS, samples, samples)
    with pytest.raises(MemoryError):
        angletrack.Observer(GAINS).update(samples, samples)
    del samples


def test_outputs_that_fit_one_by_one_but_not_together_are_a_memory_error(tmp_path):
    # 2**31 float64 samples: each 16 GiB output array alone could be had (overcommitted), the
    # five of them (82 GiB) not; refused before any is allocated.
    path = tmp_path / "large.f64"
    with open(path, "wb") as f:
        f.truncate(2**31 * 8)
    samples = np.memmap(path, dtype=np.float64, mode="r", shape=(2**31,))
    with pytest.raises(MemoryError, match="bytes are needed and cannot be allocated"):
        angletrack.track(GAINS, samples, samples)
    del samples


@pytest.mark.parametrize(
    "call, parameter",
    [
        (lambda o: o.set_state(float("nan")), "angle_rad"),
        (lambda o: o.set_state(0.0, float("inf")), "speed_rad_s"),
        (lambda o: o.initialise(float("nan"), float("nan")), "y_c"),
        (lambda o: o.initialise(1.0, float("nan")), "y_s"),
    ],
)
def test_a_state_that_is_not_finite_is_refused_naming_it(call, parameter):
    observer = angletrack.Observer(GAINS)
    with pytest.raises(angletrack.ConfigError) as raised:
        call(observer)
    assert raised.value.parameter == parameter
    assert str(raised.value).startswith(f"{parameter}: ") and "is not finite" in str(raised.value)
    assert not observer.is_initialised
