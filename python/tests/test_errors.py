"""Bad input: the right exception, naming the parameter; never a crash."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import angletrack
from conftest import SAMPLE_PERIOD, SECOND_ORDER, THIRD_ORDER


@pytest.fixture
def observer32():
    return angletrack.Observer(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD), dtype=np.float32)


def test_wrong_dtype_is_a_type_error_naming_the_argument(observer32):
    ok = np.ones(4, np.float32)
    with pytest.raises(TypeError, match=r"y_c: .*float32.*float64"):
        observer32.update(np.ones(4), ok)
    with pytest.raises(TypeError, match=r"y_s: .*float32.*int64"):
        observer32.update(ok, np.ones(4, np.int64))
    with pytest.raises(TypeError, match=r"y_c: .*float32 or float64.*int8"):
        angletrack.track(observer32.gains, np.arange(4, dtype=np.int8), np.arange(4, dtype=np.int8))
    with pytest.raises(TypeError, match=r"y_s: .*float64.*float32"):
        angletrack.track(observer32.gains, np.ones(4), ok)  # no silent up-cast of y_s
    with pytest.raises(TypeError, match=r"dtype: .*float32 or .*float64"):
        angletrack.Observer(observer32.gains, dtype=np.int16)


def test_wrong_shape_length_or_empty_is_a_value_error(observer32):
    ok = np.ones(4, np.float32)
    with pytest.raises(ValueError, match=r"y_c: expected a 1-D array.*shape \[2, 2\]"):
        observer32.update(np.ones((2, 2), np.float32), ok)
    with pytest.raises(ValueError, match=r"y_s: expected a 1-D array.*0 dimension"):
        observer32.update(ok, np.float32(1.0))
    with pytest.raises(ValueError, match=r"y_s: has 3 samples but y_c has 4"):
        observer32.update(ok, ok[:3])
    with pytest.raises(ValueError, match=r"y_c: is empty"):
        observer32.update(ok[:0], ok[:0])
    with pytest.raises(ValueError, match=r"y_c: cannot be read"):
        observer32.update([[1.0], [1.0, 2.0]], ok)
    # Strings are not parsed as numbers: a wrong type.
    with pytest.raises(TypeError, match=r"^y_c: expected real numbers, got a sequence of dtype <U"):
        observer32.update(["1.5", "2"], ["c", "d"])
    # A refused call leaves the state untouched.
    assert not observer32.is_initialised


@pytest.mark.parametrize(
    "gains, sample_period, parameter, message",
    [
        ([0.1, 0.01, -1e-5], 1e-4, "gains", r"^gains\[2\] \(l3\).*l3 > 0"),
        ([0.1, -0.01], 1e-4, "gains", r"^gains\[1\] \(l2\).*l2 > 0"),
        ([1.9, 0.5], 1e-4, "gains", r"^gains\[0\] \(l1\).*2 l1 \+ l2 < 4"),
        ([0.1, 0.01], 0.0, "sample_period_s", r"^sample_period_s must be positive"),
        ([0.1, 0.01], math.nan, "sample_period_s", r"^sample_period_s must be finite"),
        ([math.inf, 0.01], 1e-4, "gains", r"^gains\[0\] \(l1\) must be finite"),
        ([0.1], 1e-4, "gains", r"gains: expected 2 values .* or 3 .*got 1"),
        ([0.1, 0.2, 0.3, 0.4], 1e-4, "gains", r"gains: expected 2 values .* or 3 .*got 4"),
    ],
)
def test_refused_gains_name_the_parameter(gains, sample_period, parameter, message):
    """Each gain is named with the stability condition it fails (docs/theory.md §6)."""
    with pytest.raises(angletrack.ConfigError, match=message) as e:
        angletrack.Gains(gains, sample_period)
    assert e.value.parameter == parameter
    assert str(e.value).startswith(parameter)


def test_config_error_is_a_value_error_naming_the_callers_argument():
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.Gains(SECOND_ORDER, sample_period_s=-1.0)
    assert e.value.parameter == "sample_period_s"
    assert isinstance(e.value, ValueError)
    assert "sample_period must" not in str(e.value)
    g = angletrack.Gains(SECOND_ORDER, SAMPLE_PERIOD)
    for thresholds, parameter in (
        (angletrack.FaultThresholds(loss_of_signal=-1.0), "loss_of_signal"),
        (angletrack.FaultThresholds(degradation_low=1.2), "degradation_low"),
        (angletrack.FaultThresholds(max_speed_rad_s=0.0), "max_speed_rad_s"),
        (angletrack.FaultThresholds(false_lock=math.nan), "false_lock"),
    ):
        with pytest.raises(angletrack.ConfigError) as e:
            angletrack.Observer(g, fault_thresholds=thresholds)
        assert e.value.parameter == parameter
        assert str(e.value).startswith(parameter)
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.Observer(g, sin_cos="slow")
    assert e.value.parameter == "sin_cos"
    with pytest.raises(angletrack.ConfigError) as e:
        angletrack.Observer(g).update(np.ones(3), np.ones(2))
    assert e.value.parameter == "y_s"


def test_other_bad_arguments():
    g = angletrack.Gains(SECOND_ORDER, SAMPLE_PERIOD)
    with pytest.raises(ValueError, match=r"sin_cos: expected 'fast' or 'exact'"):
        angletrack.Observer(g, sin_cos="slow")
    with pytest.raises(ValueError, match=r"coefficients: expected 2 values"):
        angletrack.Gains.from_loop_polynomial([1.0], SAMPLE_PERIOD)
    with pytest.raises(TypeError):
        angletrack.Observer([0.1, 0.01])


def test_the_gil_is_released_during_a_run():
    """Another Python thread runs while the observer works: with the GIL held it could not."""
    import threading
    import time

    n = 4_000_000
    theta = np.arange(n) * 1e-3
    y_c, y_s = np.cos(theta), np.sin(theta)
    obs = angletrack.Observer(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD))
    window = {}

    def work():
        window["start"] = time.perf_counter()
        obs.update(y_c, y_s)
        window["end"] = time.perf_counter()

    ticks = []
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    start, end = window["start"], window["end"]
    margin = 0.1 * (end - start)
    inside = [t for t in ticks if start + margin < t < end - margin]
    assert end - start > 0.02  # long enough for the check to mean something
    assert len(inside) > 100


def test_bad_samples_never_make_the_state_non_finite():
    g = angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD)
    theta = np.arange(2000) * 1e-3
    y_c, y_s = np.cos(theta), np.sin(theta)
    y_c[500:520] = np.nan
    y_s[700:710] = np.inf
    est = angletrack.track(g, y_c, y_s)
    for name in ("angle", "position", "speed", "acceleration", "phase_error"):
        assert np.all(np.isfinite(getattr(est, name))), name
    assert est.position[-1] == pytest.approx(theta[-1], abs=1e-3)


float_arrays = hnp.arrays(
    dtype=st.sampled_from([np.float32, np.float64, np.int32, np.int64, np.bool_, np.complex64, np.float16]),
    shape=hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=5),
    elements=None,
)


@settings(max_examples=300, deadline=None)
@given(y_c=float_arrays, y_s=float_arrays, dtype=st.sampled_from([np.float32, np.float64]))
def test_random_junk_raises_the_right_exception_or_gives_finite_results(y_c, y_s, dtype):
    # The default input bound (4, nominal amplitude 1) stated: by default the diagnostics
    # would be scaled to the samples' own amplitude.
    obs = angletrack.Observer(
        angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD), dtype=dtype, fault_thresholds=angletrack.FaultThresholds()
    )
    # Raw ADC counts (int32 and numpy's default int64 here) are accepted, both channels of one
    # counts dtype; int64 within int32's range, then refused without adc_signed (a stream
    # reads no signedness from its samples).
    counts = y_c.dtype in (np.int32, np.int64)
    expected = None
    for name, a in (("y_c", y_c), ("y_s", y_s)):
        accepted = y_c.dtype if counts else dtype
        if a.ndim != 1:
            expected = expected or (ValueError, name)
        elif a.dtype != accepted:
            expected = expected or (TypeError, name)
        elif a.size == 0:
            expected = expected or (ValueError, name)
    # Each channel's counts are converted (and checked) before the lengths are compared.
    if expected is None and y_c.dtype == np.int64:
        for name, a in (("y_c", y_c), ("y_s", y_s)):
            if a.min() < -(2**31) or a.max() > 2**31 - 1:
                expected = expected or (ValueError, name)
        expected = expected or (ValueError, "adc_signed")
    if expected is None and len(y_c) != len(y_s):
        expected = (ValueError, "y_s")
    if expected is not None:
        with pytest.raises(expected[0], match=rf"^{expected[1]}: "):
            obs.update(y_c, y_s)
        return
    est = obs.update(y_c, y_s)
    assert len(est) == len(y_c)
    for name in ("angle", "position", "speed", "acceleration", "phase_error"):
        assert np.all(np.isfinite(getattr(est, name))), name
    # Junk samples are flagged: non-finite, or amplitude above the default input bound (4).
    with np.errstate(all="ignore"):
        amplitude = np.hypot(y_c.astype(np.float64), y_s.astype(np.float64))
    bad = ~np.isfinite(amplitude) | (amplitude > 4.0)
    clear = np.abs(amplitude - 4.0) > 1e-3 * 4.0  # away from the bound's rounding
    flagged = (est.faults & int(angletrack.Faults.BAD_SAMPLE)) != 0
    np.testing.assert_array_equal(flagged[clear], bad[clear])
