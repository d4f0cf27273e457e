"""The observers on numpy arrays: same numbers as the recursion, dtypes kept, streaming."""

import math
import pathlib

import numpy as np
import pytest

import angletrack
from conftest import SAMPLE_PERIOD, THIRD_ORDER, resolver_capture
import reference

FIELDS = ("angle", "position", "speed", "acceleration", "phase_error", "faults")


def test_imported_from_the_installed_package_not_the_source_tree():
    installed = pathlib.Path(angletrack.__file__).resolve()
    source = (pathlib.Path(__file__).parent.parent / "angletrack").resolve()
    assert "site-packages" in installed.parts
    assert installed.parent != source
    assert pathlib.Path(angletrack._angletrack.__file__).parent == installed.parent


def test_float64_exact_matches_the_recursion_sample_by_sample(gains, capture):
    """The one predictor-corrector recursion, wrapping and turn counting (docs/theory.md §5)."""
    _, y_c, y_s = capture
    est = angletrack.track(gains, y_c, y_s, sin_cos="exact")
    ref = reference.run(gains.gains, gains.sample_period_s, y_c, y_s)
    assert len(est) == len(y_c)
    np.testing.assert_allclose(est.angle, ref["angle"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(est.position, ref["position"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(est.phase_error, ref["phase_error"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(est.speed, ref["speed"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(est.acceleration, ref["acceleration"], rtol=1e-9, atol=1e-6)


def test_float32_fast_stays_close_to_the_float64_recursion(gains, capture):
    theta, y_c, y_s = capture
    est = angletrack.track(gains, y_c.astype(np.float32), y_s.astype(np.float32))
    ref = reference.run(gains.gains, gains.sample_period_s, y_c, y_s)
    # f32 rounding (6e-8 relative) and the fast sin/cos (error < 3e-7) on a loop that
    # forgets its past within a few hundred samples: a few 1e-6 rad.
    assert np.max(np.abs(est.position - ref["position"])) < 2e-5
    # Both track the shaft: within 10 mrad after the 50 ms transient.
    settled = slice(500, None)
    assert np.max(np.abs(est.position[settled] - theta[settled])) < 1e-2


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_dtype_is_kept(dtype, capture):
    _, y_c, y_s = capture
    obs = angletrack.Observer(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD), dtype=dtype)
    est = obs.update(y_c.astype(dtype), y_s.astype(dtype))
    for name in ("angle", "speed", "acceleration", "phase_error"):
        assert getattr(est, name).dtype == dtype, name
    assert est.position.dtype == np.float64
    assert est.dtype == np.dtype(dtype).name
    assert obs.dtype == np.dtype(dtype).name
    assert obs.sin_cos == ("fast" if dtype == np.float32 else "exact")


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("chunk", [1, 7, 1000])
def test_chunked_streaming_equals_one_call(gains, dtype, chunk):
    _, y_c, y_s = resolver_capture(n=3001, dtype=dtype)
    whole = angletrack.Observer(gains, dtype=dtype).update(y_c, y_s)
    obs = angletrack.Observer(gains, dtype=dtype)
    parts = [obs.update(y_c[i : i + chunk], y_s[i : i + chunk]) for i in range(0, len(y_c), chunk)]
    for name in FIELDS:
        joined = np.concatenate([getattr(p, name) for p in parts])
        np.testing.assert_array_equal(joined, getattr(whole, name), err_msg=name)
    last = obs.estimate
    assert last.angle == float(whole.angle[-1])
    assert last.position == float(whole.position[-1])
    assert last.speed == float(whole.speed[-1])


def test_multi_turn_position_and_wrapped_angle():
    n = 20_000
    theta = np.arange(n) * 0.01  # 200 rad, about 32 turns, 100 rad/s at 10 kHz
    est = angletrack.track(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD), np.cos(theta), np.sin(theta))
    assert np.all(est.angle >= -math.pi) and np.all(est.angle < math.pi)
    np.testing.assert_allclose(est.position[-1], theta[-1], atol=1e-6)
    wrapped = np.angle(np.exp(1j * est.position))
    np.testing.assert_allclose(np.angle(np.exp(1j * (wrapped - est.angle))), 0.0, atol=1e-9)
    assert est.speed[-1] == pytest.approx(100.0, abs=1e-3)


def test_speed_and_acceleration_of_a_constant_acceleration():
    n = 20_000
    t = np.arange(n) * SAMPLE_PERIOD
    theta = 0.5 * 300.0 * t**2  # 300 rad/s^2 from rest
    est = angletrack.track(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD), np.cos(theta), np.sin(theta))
    # The type III loop has no steady-state error under constant acceleration.
    assert est.acceleration[-1] == pytest.approx(300.0, abs=0.5)
    assert est.speed[-1] == pytest.approx(300.0 * t[-1], abs=1e-2)
    assert est.position[-1] == pytest.approx(theta[-1], abs=1e-5)


def test_state_control():
    obs = angletrack.Observer(angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD))
    assert not obs.is_initialised
    obs.initialise(0.0, 1.0)
    assert obs.is_initialised and obs.estimate.angle == pytest.approx(math.pi / 2, abs=1e-15)
    obs.set_state(7.0, speed_rad_s=100.0, acceleration_rad_s2=3.0)
    e = obs.estimate
    assert e.turns == 1 and e.angle == pytest.approx(7.0 - 2 * math.pi, abs=1e-12)
    assert e.position == pytest.approx(7.0, abs=1e-12)
    assert e.speed == pytest.approx(100.0, rel=1e-12) and e.acceleration == pytest.approx(3.0, rel=1e-9)
    obs.reset()
    assert not obs.is_initialised
    first = obs.update(np.array([-1.0]), np.array([0.0]))
    # atan2(0, -1) = pi, on the edge of [-pi, pi): kept inside it, at +-pi to 1 ulp.
    assert -math.pi <= first.angle[0] < math.pi
    assert abs(first.angle[0]) == pytest.approx(math.pi, abs=1e-15)


def test_strided_and_list_inputs_are_copied_not_refused(capture):
    _, y_c, y_s = capture
    g = angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD)
    strided = angletrack.track(g, y_c[::2], y_s[::2])
    dense = angletrack.track(g, np.ascontiguousarray(y_c[::2]), np.ascontiguousarray(y_s[::2]))
    np.testing.assert_array_equal(strided.position, dense.position)
    listed = angletrack.track(g, list(y_c[:100]), list(y_s[:100]))  # read as float64
    arrays = angletrack.track(g, y_c[:100], y_s[:100])
    np.testing.assert_array_equal(listed.position, arrays.position)


def test_gains_properties_and_repr():
    g = angletrack.Gains(THIRD_ORDER, sample_period_s=SAMPLE_PERIOD)
    assert g.order == 3 and g.gains == THIRD_ORDER
    assert g.sample_period_s == SAMPLE_PERIOD and g.sample_rate_hz == pytest.approx(1e4)
    same = angletrack.Gains.from_loop_polynomial(g.loop_polynomial, SAMPLE_PERIOD)
    np.testing.assert_allclose(same.gains, g.gains, rtol=1e-12)
    assert g == angletrack.Gains(THIRD_ORDER, SAMPLE_PERIOD)
    import pickle

    assert pickle.loads(pickle.dumps(g)) == g
    assert "Gains(gains=[" in repr(g) and "sample_period_s=1e-4" in repr(g)
    obs = angletrack.Observer(g, dtype="float32")
    assert "order=3" in repr(obs) and "float32" in repr(obs)
    assert "float32" in repr(obs.update(np.ones(3, np.float32), np.zeros(3, np.float32)))
