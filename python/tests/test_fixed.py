"""`FixedObserver`: the core's fixed-point observer (docs/theory.md §14) on int16 arrays,
against the float64 observer, chunked, from its constants, and its refusals and faults."""

import math

import numpy as np
import pytest

import angletrack

SAMPLE_PERIOD_S = 1e-4  # 10 kHz
AMPLITUDE_COUNTS = 2**14
WINDOW = 32  # the fixed-point monitor's window (samples)
FIELDS = (
    "angle", "turns", "speed", "acceleration", "phase_error", "faults",
    "position_rad", "speed_rad_s", "acceleration_rad_s2",
)
DTYPES = {
    "angle": np.int32, "turns": np.int64, "speed": np.int32, "acceleration": np.int64,
    "phase_error": np.int32, "faults": np.uint8, "position_rad": np.float64,
    "speed_rad_s": np.float64, "acceleration_rad_s2": np.float64,
}


def kalman_design():
    """The paper's Kalman ATO at 10 kHz, from the package's design function."""
    return angletrack.kalman_from_jerk_std(
        jerk_std_rad_s3=1e5, sensor_noise_std=0.01, sample_period_s=SAMPLE_PERIOD_S
    )


def second_order_design():
    (name, design), = [(n, d) for n, d in angletrack.paper_compared_observers() if n.startswith("2nd")]
    return design


def scenario():
    """The move of tests/fixed.rs: 100 rad/s^2 up to 20 rad/s, constant speed, a step down
    to 5 rad/s, with sensor noise 0.01 of the amplitude."""
    profile = (
        angletrack.MotionProfile(0.3, 0.0)
        .constant_acceleration(100.0, 0.2)
        .constant_speed(20.0, 0.05)
        .constant_speed(5.0, 0.05)
    )
    sensor = angletrack.SensorModel(noise_std=0.01)
    return angletrack.Scenario.generate(profile, sensor, sample_period_s=SAMPLE_PERIOD_S, seed=2026)


def counts(y):
    """Samples in int16 counts of amplitude 2^14, rounded."""
    return np.round(np.asarray(y) * AMPLITUDE_COUNTS).astype(np.int16)


def rotating_counts(n, speed_rad_per_sample=0.01, amplitude=AMPLITUDE_COUNTS):
    theta = 0.3 + speed_rad_per_sample * np.arange(n)
    return (np.round(amplitude * np.cos(theta)).astype(np.int16),
            np.round(amplitude * np.sin(theta)).astype(np.int16))


@pytest.mark.parametrize("design", [kalman_design(), second_order_design()], ids=["kalman", "order2"])
def test_follows_the_float64_observer_within_2_to_the_minus_16_turn_rms(design):
    s = scenario()
    fixed = angletrack.FixedObserver(design).update(counts(s.y_c), counts(s.y_s))
    float64 = angletrack.track(design.gains, s.y_c, s.y_s)
    rms_turns = math.sqrt(np.mean(((fixed.position_rad - float64.position) / (2 * math.pi)) ** 2))
    print(f"{design.method}: RMS difference {rms_turns:.3e} turn ({rms_turns * 2**16:.3f} of 2^-16)")
    assert len(fixed) == len(s.y_c) == 3000
    assert rms_turns < 2.0**-16


def test_arrays_are_the_firmware_integers_and_their_conversions():
    s = scenario()
    est = angletrack.FixedObserver(kalman_design()).update(counts(s.y_c), counts(s.y_s))
    for field in FIELDS:
        assert getattr(est, field).dtype == DTYPES[field], field
        assert getattr(est, field).shape == (len(s.y_c),), field
    # position = 2 pi (turns + angle / 2^32), speed 2^-32 turn per sample, acceleration 2^-63
    # turn per sample^2: the same float operations as the core, to the last bit but one.
    position = (est.turns + est.angle / 2.0**32) * 2 * math.pi
    np.testing.assert_allclose(est.position_rad, position, rtol=1e-15, atol=0)
    speed = est.speed / 2.0**32 * 2 * math.pi / SAMPLE_PERIOD_S
    np.testing.assert_allclose(est.speed_rad_s, speed, rtol=1e-15, atol=0)
    acceleration = est.acceleration / 2.0**63 * 2 * math.pi / SAMPLE_PERIOD_S**2
    np.testing.assert_allclose(est.acceleration_rad_s2, acceleration, rtol=1e-15, atol=0)
    # At the end (5 rad/s after the step down), the speed within 0.5 rad/s of the truth.
    assert abs(est.speed_rad_s[-1] - 5.0) < 0.5


def test_chunked_input_gives_exactly_the_one_call_result():
    s = scenario()
    c, y = counts(s.y_c), counts(s.y_s)
    whole = angletrack.FixedObserver(kalman_design()).update(c, y)
    chunked = angletrack.FixedObserver(kalman_design())
    cuts = [0, 1, 31, 32, 33, 1000, 2999, len(c)]
    parts = [chunked.update(c[a:b], y[a:b]) for a, b in zip(cuts, cuts[1:])]
    for field in FIELDS:
        joined = np.concatenate([getattr(p, field) for p in parts])
        np.testing.assert_array_equal(joined, getattr(whole, field), err_msg=field)
    last = chunked.estimate
    assert (last.angle, last.turns, last.speed, last.acceleration) == (
        whole.angle[-1], whole.turns[-1], whole.speed[-1], whole.acceleration[-1])
    assert last.position_rad == whole.position_rad[-1]


@pytest.mark.parametrize("design", [kalman_design(), second_order_design()], ids=["kalman", "order2"])
def test_from_constants_runs_the_same_integers_as_the_design(design):
    constants = design.fixed_constants()
    by_design = angletrack.FixedObserver(design)
    by_constants = angletrack.FixedObserver.from_constants(constants, SAMPLE_PERIOD_S)
    assert by_constants.constants == by_design.constants == constants
    assert by_constants.gains == constants["quantised_gains"]
    # Within 2^-16 of the designed gains (half a unit of multipliers of at least 2^16).
    np.testing.assert_allclose(by_design.gains, design.gains.gains, rtol=2.0**-16, atol=0)
    s = scenario()
    a = by_design.update(counts(s.y_c), counts(s.y_s))
    b = by_constants.update(counts(s.y_c), counts(s.y_s))
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), err_msg=field)


def test_reset_starts_again_and_a_list_of_integers_is_read_as_int16():
    c, s = rotating_counts(200)
    observer = angletrack.FixedObserver(kalman_design())
    first = observer.update(c, s)
    observer.reset()
    again = observer.update(c.tolist(), s.tolist())
    np.testing.assert_array_equal(first.angle, again.angle)
    np.testing.assert_array_equal(first.turns, again.turns)


def one_line_error(exception, call):
    with pytest.raises(exception) as info:
        call()
    message = str(info.value)
    assert "\n" not in message
    return info.value, message


def test_refused_samples_name_their_argument_and_leave_the_state():
    c, s = rotating_counts(100)
    observer = angletrack.FixedObserver(kalman_design())
    observer.update(c, s)
    before = observer.estimate
    _, message = one_line_error(TypeError, lambda: observer.update(c.astype(np.float64), s))
    assert message.startswith("y_c: expected an array of dtype int16, got an array of dtype float64")
    # Other integer dtypes are read as int16 when every value fits (tested below), else refused.
    wide = s.astype(np.int32)
    wide[3] = 40_000
    e, message = one_line_error(angletrack.ConfigError, lambda: observer.update(c, wide))
    assert message == "y_s: sample 40000 (index 3) is outside the int16 range [-32768, 32767]"
    e, message = one_line_error(angletrack.ConfigError, lambda: observer.update([0, 40000], [0, 0]))
    assert e.parameter == "y_c"
    assert message == "y_c: sample 40000 (index 1) is outside the int16 range [-32768, 32767]"
    e, message = one_line_error(angletrack.ConfigError, lambda: observer.update([0, 1], [-32769, 0]))
    assert e.parameter == "y_s"
    assert message == "y_s: sample -32769 (index 0) is outside the int16 range [-32768, 32767]"
    e, message = one_line_error(angletrack.ConfigError, lambda: observer.update(np.zeros((2, 2), np.int16), s))
    assert e.parameter == "y_c" and "1-D" in message
    _, message = one_line_error(TypeError, lambda: observer.update([1.5, 2.0], [0, 0]))
    assert message.startswith("y_c: expected int16 samples")
    e, message = one_line_error(angletrack.ConfigError, lambda: observer.update(c, s[:-1]))
    assert e.parameter == "y_s"
    assert message == "y_s: has 99 samples but y_c has 100: they must be equal"
    after = observer.estimate
    assert (after.angle, after.speed, after.turns) == (before.angle, before.speed, before.turns)


def test_refused_constants_name_the_gain_or_the_key():
    constants = kalman_design().fixed_constants()
    zero = dict(constants, multiplier=[0] + constants["multiplier"][1:])
    e, message = one_line_error(
        angletrack.ConfigError, lambda: angletrack.FixedObserver.from_constants(zero, SAMPLE_PERIOD_S))
    assert e.parameter == "constants"
    assert message.startswith("constants: gains[0] (l1) is out of its allowed range")
    shift = dict(constants, acceleration_shift=16)
    _, message = one_line_error(
        angletrack.ConfigError, lambda: angletrack.FixedObserver.from_constants(shift, SAMPLE_PERIOD_S))
    assert message.startswith("constants: gains[2] (l3) is out of its allowed range")
    missing = {"multiplier": constants["multiplier"]}
    e, message = one_line_error(
        angletrack.ConfigError, lambda: angletrack.FixedObserver.from_constants(missing, SAMPLE_PERIOD_S))
    assert e.parameter == "constants"
    assert message.startswith("constants: has no key 'acceleration_shift'")
    e, _ = one_line_error(
        angletrack.ConfigError, lambda: angletrack.FixedObserver.from_constants(constants, -1.0))
    assert e.parameter == "sample_period_s"
    e, _ = one_line_error(
        angletrack.ConfigError, lambda: angletrack.FixedObserver(kalman_design(), nominal_amplitude=2000.0))
    assert e.parameter == "nominal_amplitude"


@pytest.mark.parametrize("drop_at", [3200, 3201, 3215, 3231])
def test_a_signal_dropped_to_2000_counts_is_flagged_within_one_window(drop_at):
    n = 4000
    c, s = rotating_counts(n)
    c[drop_at:] = np.round(c[drop_at:] * (2000 / AMPLITUDE_COUNTS)).astype(np.int16)
    s[drop_at:] = np.round(s[drop_at:] * (2000 / AMPLITUDE_COUNTS)).astype(np.int16)
    observer = angletrack.FixedObserver(kalman_design())
    est = observer.update(c, s)
    lost = (est.faults & angletrack.Faults.LOSS_OF_SIGNAL) != 0
    assert not lost[:drop_at].any()
    first = int(np.flatnonzero(lost)[0])
    assert drop_at <= first < drop_at + WINDOW
    assert lost[first:].all()
    assert observer.latched_faults & angletrack.Faults.LOSS_OF_SIGNAL
    assert observer.clear_faults() & angletrack.Faults.LOSS_OF_SIGNAL
    assert observer.latched_faults == 0
    # With the monitor off, nothing is flagged.
    quiet = angletrack.FixedObserver(kalman_design(), nominal_amplitude=None).update(c, s)
    assert not quiet.faults.any()


def test_int64_counts_are_read_as_int16_and_counts_outside_int16_are_refused():
    # numpy's default integers (int64), as the CLI reads them: the same integers as int16.
    c, s = rotating_counts(300)
    as_int16 = angletrack.FixedObserver(kalman_design()).update(c, s)
    as_int64 = angletrack.FixedObserver(kalman_design()).update(c.astype(np.int64), s.astype(np.int64))
    assert np.array_equal(as_int16.angle, as_int64.angle) and np.array_equal(as_int16.faults, as_int64.faults)
    wide = c.astype(np.int64)
    wide[7] = 40_000
    with pytest.raises(angletrack.ConfigError, match=r"^y_c: .*index 7.*int16"):
        angletrack.FixedObserver(kalman_design()).update(wide, s.astype(np.int64))
    with pytest.raises(TypeError, match="^y_s: "):
        angletrack.FixedObserver(kalman_design()).update(c, s.astype(np.float64))
