"""Arguments the extension would otherwise ignore, clamp or convert silently: each is refused
with a one-line error whose message starts with the argument's name as the caller wrote it
(a ``ConfigError`` for a value, a ``TypeError`` for a type)."""

import math

import numpy as np
import pytest

import angletrack as at
from angletrack import _angletrack as X
from angletrack.harmonics import Calibration

SAMPLE_PERIOD = 1e-4


def gains2():
    return at.Gains([0.06, 0.001], sample_period_s=SAMPLE_PERIOD)


def circle(n=200, amplitude=1.0, speed_rad_per_sample=0.01):
    theta = speed_rad_per_sample * np.arange(n)
    return amplitude * np.cos(theta), amplitude * np.sin(theta)


def refused(exception, parameter, call):
    """``call()`` raises ``exception`` whose one-line message starts with ``parameter``."""
    with pytest.raises(exception) as e:
        call()
    message = str(e.value)
    assert message.startswith(parameter), message
    assert "\n" not in message, message
    if exception is at.ConfigError:
        assert e.value.parameter == parameter
    return message


# ---------------------------------------------------------------- ADC options with floats


@pytest.mark.parametrize("option, value", [("adc_mid_scale", 2048), ("adc_counts_per_unit", 1000.0)])
def test_adc_options_with_float_samples_are_refused(option, value):
    c, s = circle()
    refused(at.ConfigError, option, lambda: at.Observer(gains2(), **{option: value}).update(c, s))
    refused(at.ConfigError, option, lambda: at.track(gains2(), c, s, **{option: value}))
    # With counts the option applies: 2048 +- 1000 counts minus 2048, over 1000, is the circle.
    counts = [np.round(2048 + 1000 * v).astype(np.int32) for v in (c, s)]
    est = at.track(gains2(), *counts, adc_mid_scale=2048, adc_counts_per_unit=1000.0)
    assert abs(est.angle[-1] - 0.01 * 199) < 1e-2


# ------------------------------------------------------- a calibration given while off


def test_initial_calibration_with_the_calibration_off_is_refused():
    cal = at.SensorCalibration(offset_c=0.1, offset_s=-0.1, amplitude_s=1.1, quadrature_rad=0.02)
    refused(at.ConfigError, "initial_calibration", lambda: at.Observer(gains2(), initial_calibration=cal))
    o = at.Observer(gains2(), calibration="frozen", initial_calibration=cal)
    refused(at.ConfigError, "initial_calibration", lambda: o.set_calibration("off", cal))
    refused(at.ConfigError, "initial_calibration", lambda: o.set_calibration(None, cal))
    assert o.calibration_mode == "frozen"
    o.set_calibration(None)
    assert o.calibration_mode == "off"


# ------------------------------------------------------------------- the batch's input


@pytest.mark.parametrize("dtype", [np.int16, np.uint16, np.int32, np.int64])
def test_batch_refuses_raw_counts(dtype):
    c, s = circle()
    counts = [np.round(2048 + 1000 * v).astype(dtype)[None, :] for v in (c, s)]
    message = refused(TypeError, "y_c", lambda: at.track_batch(gains2(), *counts))
    assert "raw ADC counts" in message
    refused(TypeError, "y_c", lambda: at.ObserverBatch(gains2(), 1).update(*counts))


def test_batch_tracks_floats_of_amplitude_up_to_4_and_rejects_above():
    c, s = circle()
    est = at.track_batch(gains2(), np.stack([3.9 * c, 4.1 * c]), np.stack([3.9 * s, 4.1 * s]))
    assert abs(est.angle[0, -1] - 0.01 * 199) < 1e-2
    assert np.all((np.asarray(est.faults[1]) & int(at.Faults.BAD_SAMPLE)) != 0)


# ------------------------------------------------------------------------- set_state


@pytest.mark.parametrize("gains, call, parameter", [
    ("order2", dict(angle_rad=2.0**31 * 2 * math.pi), "angle_rad"),
    ("order2", dict(angle_rad=2.0**64), "angle_rad"),
    ("order2", dict(angle_rad=1e300), "angle_rad"),
    ("order2", dict(angle_rad=math.inf), "angle_rad"),
    ("order2", dict(angle_rad=0.0, speed_rad_s=1.01 * math.pi / SAMPLE_PERIOD), "speed_rad_s"),
    ("order2", dict(angle_rad=0.0, speed_rad_s=-1e300), "speed_rad_s"),
    ("order2", dict(angle_rad=0.0, acceleration_rad_s2=1.0), "acceleration_rad_s2"),
    ("order3", dict(angle_rad=0.0, acceleration_rad_s2=1.01 * math.pi / SAMPLE_PERIOD**2), "acceleration_rad_s2"),
    ("order3", dict(angle_rad=0.0, acceleration_rad_s2=math.nan), "acceleration_rad_s2"),
])
def test_set_state_refuses_what_the_state_cannot_hold(gains, call, parameter):
    g = gains2() if gains == "order2" else at.Gains([0.3, 0.04, 0.002], sample_period_s=SAMPLE_PERIOD)
    o = at.Observer(g)
    refused(at.ConfigError, parameter, lambda: o.set_state(**call))
    assert not o.is_initialised


def test_set_state_keeps_what_it_is_given_within_the_limits():
    o = at.Observer(at.Gains([0.3, 0.04, 0.002], sample_period_s=SAMPLE_PERIOD))
    angle = 1000.5 * 2 * math.pi
    o.set_state(angle, 0.9 * math.pi / SAMPLE_PERIOD, -0.9 * math.pi / SAMPLE_PERIOD**2)
    e = o.estimate
    assert abs(e.position - angle) < 1e-6 * angle
    assert abs(e.speed / (0.9 * math.pi / SAMPLE_PERIOD) - 1) < 1e-9
    assert abs(e.acceleration / (-0.9 * math.pi / SAMPLE_PERIOD**2) - 1) < 1e-9
    o2 = at.Observer(gains2())
    o2.set_state(1.0, 10.0, 0.0)
    assert abs(o2.estimate.speed - 10.0) < 1e-9


# ------------------------------------------------------------------- paired arrays


@pytest.mark.parametrize("function, second, kwargs, cut", [
    (X.CountsExtremes().add, "y_s", {}, 1),
    (X.measured_adc_range, "y_s", {}, 3),
    (X.plan_windings, "first_s", dict(carrier_hz=10e3, capture_hz=160e3), 7),
])
def test_paired_arrays_of_unequal_lengths_are_refused(function, second, kwargs, cut):
    k = np.arange(400)
    carrier = np.sin(2 * np.pi * k / 16.0)
    c = np.round(2048 + 1800 * np.cos(0.002 * k) * carrier)
    s = np.round(2048 + 1800 * np.sin(0.002 * k) * carrier)
    function(c, s, **kwargs)
    refused(at.ConfigError, second, lambda: function(c, s[:-cut], **kwargs))


@pytest.mark.parametrize("option, value", [
    ("carrier_amplitude_counts", math.nan), ("carrier_amplitude_counts", -1.0),
    ("carrier_amplitude_counts", 0.0), ("carrier_amplitude_counts", 1e300),
    ("adc_range", (4095.0, 0.0)), ("adc_range", (math.nan, 1.0)),
])
def test_plan_windings_refuses_a_stated_amplitude_or_range_no_adc_gives(option, value):
    k = np.arange(400)
    carrier = np.sin(2 * np.pi * k / 16.0)
    c, s = 2048 + 1800 * np.cos(0.002 * k) * carrier, 2048 + 1800 * np.sin(0.002 * k) * carrier
    refused(at.ConfigError, option,
            lambda: X.plan_windings(c, s, carrier_hz=10e3, capture_hz=160e3, **{option: value}))


# --------------------------------------------------------------------------- scenario


def test_scenario_from_arrays_refuses_a_reference_angle_not_finite():
    c, s = circle(10)
    angle = 0.01 * np.arange(10)
    angle[4] = np.nan
    message = refused(at.ConfigError, "angle_rad",
                      lambda: at.Scenario.from_arrays(sample_period_s=SAMPLE_PERIOD, angle_rad=angle, y_c=c, y_s=s))
    assert "index 4" in message


# -------------------------------------------------------- the calibrated observer's input


def no_calibration():
    return Calibration(sensor=(0.0, 0.0, 1.0, 1.0, 0.0), cos=(0.0,) * 8, sin=(0.0,) * 8)


@pytest.mark.parametrize("y, exception", [
    (None, at.ConfigError),
    (np.float64(1.0), at.ConfigError),
    (np.ones(8, dtype=np.complex128), TypeError),
    (["1.0"] * 8, TypeError),
    ([1 + 1j] * 8, TypeError),
    (np.ones(8, dtype=np.float32), TypeError),
])
def test_calibrated_observer_checks_its_samples_as_observer_does(y, exception):
    o = at.CalibratedObserver(gains2(), no_calibration())
    refused(exception, "y_c", lambda: o.update(y, y))
    refused(exception, "y_c", lambda: at.Observer(gains2()).update(y, y))


def test_calibrated_observer_of_float32_refuses_float64():
    o = at.CalibratedObserver(gains2(), no_calibration(), dtype=np.float32)
    c, s = circle()
    refused(TypeError, "y_c", lambda: o.update(c, s))
    est = o.update(c.astype(np.float32), s.astype(np.float32))
    assert est.angle.dtype == np.float32
    assert abs(est.angle[-1] - 0.01 * 199) < 1e-2


@pytest.mark.parametrize("y, exception", [
    (["1.0"] * 2000, TypeError),
    (np.ones(2000, dtype=np.complex128), TypeError),
    (None, at.ConfigError),
])
def test_calibrate_checks_its_samples(y, exception):
    refused(exception, "y_c", lambda: at.calibrate(y, y, gains2()))


# --------------------------------------------------------------- whole-number arguments


def design():
    return at.third_order_butterworth(2e-3, 1e-4)


INTEGER_ARGUMENTS = [
    ("adc_mid_scale", lambda v: at.Observer(gains2(), adc_mid_scale=v)),
    ("adc_mid_scale", lambda v: at.track(gains2(), np.zeros(4, np.int16), np.zeros(4, np.int16), adc_mid_scale=v)),
    ("startup_periods", lambda v: at.Demodulator(carrier_hz=10e3, carrier_amplitude_counts=1800.0,
                                                 samples_per_period=16.0, startup_periods=v)),
    ("pole_pairs", lambda v: at.DriveOutputs(sample_period_s=SAMPLE_PERIOD, pole_pairs=v)),
    ("speed_ratio", lambda v: at.DriveOutputs(sample_period_s=SAMPLE_PERIOD, speed_ratio=v)),
    ("input_shift", lambda v: at.FixedObserver(design(), input_shift=v)),
    ("mid_scale_counts", lambda v: at.FixedObserver(design(), mid_scale_counts=v)),
    ("lowest_order", lambda v: at.calibrate(*circle(4000), gains2(), lowest_order=v)),
    ("highest_order", lambda v: at.calibrate(*circle(4000), gains2(), highest_order=v)),
    ("seed", lambda v: at.Scenario.generate(at.MotionProfile().constant_speed(1.0, 1e-3),
                                            sample_period_s=SAMPLE_PERIOD, seed=v)),
    ("seed", lambda v: at.resolver_windings(at.MotionProfile().constant_speed(1.0, 1e-3), seed=v)),
    ("samples_per_period", lambda v: at.ResolverModel(samples_per_period=v)),
    ("adc_bits", lambda v: at.ResolverModel(adc_bits=v)),
    ("adc_bits", lambda v: at.SensorModel(adc_bits=v)),
    ("turns_learned", lambda v: X.sensor_calibration_to_json(at.SensorCalibration(), turns_learned=v)),
]


@pytest.mark.parametrize("value", [-1, 2**64, 1.5, "3"], ids=["negative", "2**64", "float", "str"])
@pytest.mark.parametrize("parameter, call", INTEGER_ARGUMENTS,
                         ids=[f"{p}-{k}" for k, (p, _) in enumerate(INTEGER_ARGUMENTS)])
def test_integer_arguments_out_of_range_name_the_argument(parameter, call, value):
    if value == -1 and parameter in ("adc_mid_scale", "mid_scale_counts"):
        value = -(2**31) - 1  # negative mid-scales are counts too
    with pytest.raises((at.ConfigError, TypeError)) as e:
        call(value)
    message = str(e.value)
    assert message.startswith(parameter), message
    assert "\n" not in message, message
