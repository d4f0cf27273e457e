"""ObserverBatch / track_batch: many channels on one gain set, equal to single observers."""

import numpy as np
import pytest

import angletrack


def _channels(n_channels, n_samples, dtype):
    k = np.arange(n_samples)
    theta = 0.3 * np.arange(n_channels)[:, None] + (20.0 + 13.0 * np.arange(n_channels))[:, None] * k * 1e-4
    y_c, y_s = np.cos(theta).astype(dtype), np.sin(theta).astype(dtype)
    y_s[3, 100:110] = np.nan  # a burst of bad samples on one channel
    return y_c, y_s


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("gains", [[0.061, 0.0019, 3.1e-5], [0.06, 0.001]])
def test_each_channel_of_a_batch_equals_a_single_observer(dtype, gains):
    g = angletrack.Gains(gains, sample_period_s=1e-4)
    y_c, y_s = _channels(11, 2000, dtype)
    batch = angletrack.track_batch(g, y_c, y_s)
    assert batch.angle.shape == (11, 2000) and batch.angle.dtype == dtype
    assert batch.position.dtype == np.float64 and batch.faults.dtype == np.uint8
    for c in range(11):
        single = angletrack.Observer(
            g, dtype=dtype, fault_thresholds=angletrack.FaultThresholds.disabled()
        ).update(y_c[c], y_s[c])
        np.testing.assert_array_equal(batch.angle[c], single.angle)
        np.testing.assert_array_equal(batch.position[c], single.position)
        np.testing.assert_array_equal(batch.speed[c], single.speed)
        np.testing.assert_array_equal(batch.acceleration[c], single.acceleration)
        np.testing.assert_array_equal(batch.phase_error[c], single.phase_error)
        np.testing.assert_array_equal(batch.faults[c], single.faults)
    assert (batch.faults[3, 100:110] == angletrack.Faults.BAD_SAMPLE).all()


def test_a_batch_streams_in_chunks_exactly_as_one_call():
    g = angletrack.Gains([0.061, 0.0019, 3.1e-5], sample_period_s=1e-4)
    y_c, y_s = _channels(9, 3000, np.float32)
    whole = angletrack.ObserverBatch(g, 9, dtype=np.float32).update(y_c, y_s)
    batch = angletrack.ObserverBatch(g, 9, dtype=np.float32)
    parts = [batch.update(y_c[:, a:b], y_s[:, a:b]) for a, b in [(0, 1000), (1000, 1001), (1001, 3000)]]
    np.testing.assert_array_equal(np.hstack([p.angle for p in parts]), whole.angle)
    np.testing.assert_array_equal(np.hstack([p.position for p in parts]), whole.position)
    assert "channels=9" in repr(batch)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_selected_outputs_equal_the_full_run_and_single_observers(dtype):
    # Bit for bit (tolerance 0): the selection changes what is written, not the recursion.
    g = angletrack.Gains([0.061, 0.0019, 3.1e-5], sample_period_s=1e-4)
    y_c, y_s = _channels(11, 700, dtype)  # a partial bank; 700 samples end inside a block
    full = angletrack.track_batch(g, y_c, y_s)
    picked = angletrack.track_batch(g, y_c, y_s, outputs=["angle", "speed", "angle"])
    assert picked.position is None and picked.acceleration is None and picked.faults is None
    assert picked.phase_error is None and picked.angle.shape == (11, 700)
    np.testing.assert_array_equal(picked.angle, full.angle)
    np.testing.assert_array_equal(picked.speed, full.speed)
    assert "angle, speed)" in repr(picked)
    batch = angletrack.ObserverBatch(g, 11, dtype=dtype)
    first = batch.update(y_c[:, :300], y_s[:, :300], outputs="position")
    rest = batch.update(y_c[:, 300:], y_s[:, 300:], outputs={"faults", "position"})
    assert first.angle is None and rest.faults.dtype == np.uint8
    np.testing.assert_array_equal(np.hstack([first.position, rest.position]), full.position)
    np.testing.assert_array_equal(rest.faults, full.faults[:, 300:])
    for c in (0, 3, 10):
        single = angletrack.Observer(
            g, dtype=dtype, fault_thresholds=angletrack.FaultThresholds.disabled()
        ).update(y_c[c], y_s[c])
        np.testing.assert_array_equal(picked.angle[c], single.angle)
        np.testing.assert_array_equal(picked.speed[c], single.speed)
    # No output: the channels still run, and the next call goes on from their state.
    quiet = angletrack.ObserverBatch(g, 11, dtype=dtype)
    assert quiet.update(y_c[:, :300], y_s[:, :300], outputs=()).angle is None
    after = quiet.update(y_c[:, 300:], y_s[:, 300:], outputs=("angle",))
    np.testing.assert_array_equal(after.angle, full.angle[:, 300:])


def test_unknown_outputs_are_refused_naming_outputs_and_the_name():
    g = angletrack.Gains([0.06, 0.001], sample_period_s=1e-4)
    y = np.ones((2, 5))
    with pytest.raises(angletrack.ConfigError, match="outputs.*'velocity'") as e:
        angletrack.track_batch(g, y, 0 * y, outputs=("angle", "velocity"))
    assert e.value.parameter == "outputs"
    for bad in ([1, 2], 3):
        with pytest.raises(ValueError, match="outputs"):
            angletrack.ObserverBatch(g, 2).update(y, 0 * y, outputs=bad)


def test_bad_batch_inputs_raise_naming_the_parameter():
    g = angletrack.Gains([0.06, 0.001], sample_period_s=1e-4)
    batch = angletrack.ObserverBatch(g, 2)
    with pytest.raises(ValueError, match="y_c.*2-D"):
        batch.update(np.ones(5), np.zeros(5))
    with pytest.raises(ValueError, match="y_s"):
        batch.update(np.ones((2, 5)), np.zeros((2, 4)))
    with pytest.raises(ValueError, match="channels"):
        batch.update(np.ones((3, 5)), np.zeros((3, 5)))
    with pytest.raises(TypeError, match="y_c"):
        batch.update(np.ones((2, 5), dtype=np.float32), np.zeros((2, 5), dtype=np.float32))
    with pytest.raises(ValueError, match="channels"):
        angletrack.ObserverBatch(g, 0)
    with pytest.raises(ValueError, match="empty"):
        batch.update(np.ones((2, 0)), np.zeros((2, 0)))
    # A transposed (non-contiguous) view is copied, not refused.
    y = np.ones((5, 2)).T
    assert batch.update(y, np.zeros((5, 2)).T).angle.shape == (2, 5)


def test_track_batch_takes_nested_lists_as_the_stubs_say():
    g = angletrack.Gains([0.06, 0.001], sample_period_s=1e-4)
    y_c, y_s = _channels(5, 120, np.float64)
    from_lists = angletrack.track_batch(g, y_c.tolist(), y_s.tolist(), outputs=("angle",))
    np.testing.assert_array_equal(from_lists.angle, angletrack.track_batch(g, y_c, y_s).angle)
    with pytest.raises(ValueError, match="y_c.*2-D"):
        angletrack.track_batch(g, y_c[0].tolist(), y_s[0].tolist())
    with pytest.raises(ValueError, match="y_c.*2-D"):
        angletrack.track_batch(g, 1.0, 0.0)
