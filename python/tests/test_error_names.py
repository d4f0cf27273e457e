"""Every refused argument is named as the caller spelled it.

Each public function and method that takes numbers is called with one argument at a time
replaced by a bad value. The call must raise `angletrack.ConfigError` whose `parameter` is
that argument (or, for a value refused in relation to another argument, the one listed in
`NAMED_AS`) and whose message starts with it, unless `ACCEPTED` lists the value as valid
for that argument, in which case the call must succeed.
"""

import inspect
import math

import numpy as np
import pytest

import angletrack as at

BAD_VALUES = (math.nan, math.inf, -1.0, 0.0, 1e300)
TS = 1e-4


def _profile():
    return at.MotionProfile(0.0, 10.0)


def _generated(profile, sensor=None):
    # Profiles, sensor models and thresholds are checked where they are used: the probe
    # goes that far, so that the deferred check is the one whose naming is tested.
    return at.Scenario.generate(profile, sensor, sample_period_s=TS)


def _installed(thresholds):
    return at.Observer(at.Gains([0.06, 0.0019, 3e-5], TS), fault_thresholds=thresholds)


# (label, callable, valid keyword arguments). Every numeric argument is probed in turn.
CASES = [
    ("Gains", at.Gains, dict(gains=[0.06, 0.0019, 3e-5], sample_period_s=TS)),
    ("kalman", at.kalman, dict(process_noise_q=1e-9, measurement_noise_r=1.0, sample_period_s=TS)),
    ("kalman_from_jerk_std", at.kalman_from_jerk_std,
     dict(jerk_std_rad_s3=1e5, sensor_noise_std=0.01, sample_period_s=TS)),
    ("kalman_from_jerk_density", at.kalman_from_jerk_density,
     dict(jerk_density_rad2_s5=1e6, sensor_noise_std=0.01, sample_period_s=TS)),
    ("second_order_butterworth", at.second_order_butterworth,
     dict(time_constant_s=0.005, sample_period_s=TS)),
    ("second_order_from_bandwidth", at.second_order_from_bandwidth,
     dict(bandwidth_hz=100.0, damping=1.0, sample_period_s=TS)),
    ("second_order_from_tracking_error", at.second_order_from_tracking_error,
     dict(max_error_rad=1e-3, acceleration_rad_s2=100.0, damping=1.0, sample_period_s=TS)),
    ("second_order_from_tracking_error_sampled", at.second_order_from_tracking_error_sampled,
     dict(max_error_rad=1e-3, acceleration_rad_s2=2e3, overshoot=0.05, sample_period_s=50e-6)),
    ("second_order_bandwidth_ratio", at.second_order_bandwidth_ratio, dict(damping=1.0)),
    ("third_order_butterworth", at.third_order_butterworth,
     dict(time_constant_s=0.005, sample_period_s=TS)),
    ("third_order_from_poles", at.third_order_from_poles,
     dict(pole_ratio=39.04, pole_time_constant_s=0.02, pole_frequency_ratio=4.71,
          sample_period_s=TS)),
    ("third_order_from_overshoot", at.third_order_from_overshoot,
     dict(overshoot=0.1, settling_time_s=0.05, pole_frequency_ratio=4.71, sample_period_s=TS)),
    ("max_trackable_speed_rad_s", at.max_trackable_speed_rad_s, dict(sample_period_s=TS)),
    ("predicted_error", at.predicted_error,
     dict(gains=at.Gains([0.06, 0.0019, 3e-5], TS), sensor_noise_std=0.01, process_noise_q=0.0)),
    ("predicted_error_on_kalman_model", at.predicted_error_on_kalman_model,
     dict(gains=at.Gains([0.06, 0.0019, 3e-5], TS), sensor_noise_std=0.01,
          process_noise_q=1e-12)),
    ("FaultThresholds", lambda **k: _installed(at.FaultThresholds(**k)),
     dict(nominal_amplitude=1.0, max_input_amplitude=4.0, loss_of_signal=0.25,
          degradation_low=0.5, degradation_high=1.5, loss_of_tracking=0.1,
          max_speed_rad_s=1e4, filter_factor=0.0625, false_lock=0.0)),
    ("SensorModel", lambda **k: _generated(_profile().constant_speed(10.0, 0.01),
                                           at.SensorModel(**k)),
     dict(amplitude=1.0, offset_cos=0.01, offset_sin=0.01, amplitude_imbalance=0.01,
          quadrature_error_rad=0.01, third_harmonic=0.01, noise_std=0.01)),
    ("MotionProfile", lambda **k: _generated(at.MotionProfile(**k).constant_speed(1.0, 0.01)),
     dict(initial_angle_rad=0.0, initial_speed_rad_s=10.0)),
    ("MotionProfile.constant_speed", lambda **k: _generated(_profile().constant_speed(**k)),
     dict(speed_rad_s=10.0, duration_s=0.1)),
    ("MotionProfile.constant_acceleration", lambda **k: _generated(_profile().constant_acceleration(**k)),
     dict(acceleration_rad_s2=10.0, duration_s=0.1)),
    ("MotionProfile.step", lambda **k: _generated(_profile().step(**k)), dict(step_rad=0.5, duration_s=0.1)),
    ("MotionProfile.reversal", lambda **k: _generated(_profile().reversal(**k)),
     dict(acceleration_rad_s2=100.0)),
    ("MotionProfile.speed_ripple", lambda **k: _generated(_profile().speed_ripple(**k)),
     dict(ripple_rad_s=1.0, frequency_hz=5.0, duration_s=0.1)),
    ("MotionProfile.trapezoidal", lambda **k: _generated(_profile().trapezoidal(**k)),
     dict(distance_rad=10.0, max_speed_rad_s=50.0, max_acceleration_rad_s2=500.0)),
    ("MotionProfile.s_curve", lambda **k: _generated(_profile().s_curve(**k)),
     dict(distance_rad=10.0, max_speed_rad_s=50.0, max_acceleration_rad_s2=500.0,
          max_jerk_rad_s3=1e4)),
]


def _probes():
    for label, call, kwargs in CASES:
        for name, value in kwargs.items():
            if isinstance(value, float):
                for bad in BAD_VALUES:
                    yield pytest.param(label, call, kwargs, name, bad, id=f"{label}-{name}-{bad}")


# Values of BAD_VALUES that are valid for an argument (the call must accept them).
ACCEPTED = {
    # A loose error bound is a slow loop.
    ("second_order_from_tracking_error", "max_error_rad"): (1e300,),
    # A period of 1e300 s: a limit of 3e-300 rad/s.
    ("max_trackable_speed_rad_s", "sample_period_s"): (1e300,),
    # No noise, no jerk, or a huge jerk: a prediction.
    ("predicted_error", "sensor_noise_std"): (0.0,),
    ("predicted_error", "process_noise_q"): (0.0, 1e300),
    ("predicted_error_on_kalman_model", "sensor_noise_std"): (0.0,),
    ("predicted_error_on_kalman_model", "process_noise_q"): (0.0, 1e300),
    # A threshold never reached, or the false-lock check disabled.
    ("FaultThresholds", "loss_of_tracking"): (1e300,),
    ("FaultThresholds", "max_speed_rad_s"): (1e300,),
    ("FaultThresholds", "false_lock"): (0.0,),
    # The sensor model: any finite offset, imbalance, quadrature or harmonic; no noise.
    ("SensorModel", "amplitude"): (1e300,),
    ("SensorModel", "offset_cos"): (-1.0, 0.0, 1e300),
    ("SensorModel", "offset_sin"): (-1.0, 0.0, 1e300),
    ("SensorModel", "amplitude_imbalance"): (0.0, 1e300),
    ("SensorModel", "quadrature_error_rad"): (-1.0, 0.0, 1e300),
    ("SensorModel", "third_harmonic"): (-1.0, 0.0, 1e300),
    ("SensorModel", "noise_std"): (0.0, 1e300),
    # Motion: any finite angle, speed, acceleration or distance (backwards, or none); an
    # empty segment; limits that never bind.
    ("MotionProfile", "initial_angle_rad"): (-1.0, 0.0, 1e300),
    ("MotionProfile", "initial_speed_rad_s"): (-1.0, 0.0, 1e300),
    ("MotionProfile.constant_speed", "speed_rad_s"): (-1.0, 0.0, 1e300),
    ("MotionProfile.constant_speed", "duration_s"): (0.0,),
    ("MotionProfile.constant_acceleration", "acceleration_rad_s2"): (-1.0, 0.0, 1e300),
    ("MotionProfile.constant_acceleration", "duration_s"): (0.0,),
    ("MotionProfile.step", "step_rad"): (-1.0, 0.0, 1e300),
    ("MotionProfile.step", "duration_s"): (0.0,),
    ("MotionProfile.reversal", "acceleration_rad_s2"): (1e300,),
    ("MotionProfile.speed_ripple", "ripple_rad_s"): (-1.0, 0.0, 1e300),
    ("MotionProfile.speed_ripple", "frequency_hz"): (1e300,),
    ("MotionProfile.speed_ripple", "duration_s"): (0.0,),
    ("MotionProfile.trapezoidal", "distance_rad"): (-1.0, 0.0),
    ("MotionProfile.trapezoidal", "max_acceleration_rad_s2"): (1e300,),
    ("MotionProfile.s_curve", "distance_rad"): (-1.0, 0.0),
    ("MotionProfile.s_curve", "max_acceleration_rad_s2"): (1e300,),
    ("MotionProfile.s_curve", "max_jerk_rad_s3"): (1e300,),
}

# A value refused in relation to another argument names that one: the loop too fast for
# the sample period names the loop's argument, a ratio or a product out of range its other
# term, a profile too long for 1e8 samples the generate call's `profile`.
_TOO_FAST = {
    "second_order_butterworth": "time_constant_s",
    "second_order_from_bandwidth": "bandwidth_hz",
    "third_order_butterworth": "time_constant_s",
    "third_order_from_poles": "pole_time_constant_s",
    "third_order_from_overshoot": "settling_time_s",
}
NAMED_AS = {
    **{(label, "sample_period_s", 1e300): name for label, name in _TOO_FAST.items()},
    **{(label, name, 1e300): "max_error_rad"
       for label in ("second_order_from_tracking_error", "second_order_from_tracking_error_sampled")
       for name in ("acceleration_rad_s2", "sample_period_s")},
    ("kalman", "measurement_noise_r", 1e300): "process_noise_q",
    ("kalman_from_jerk_std", "sample_period_s", 1e300): "jerk_std_rad_s3",
    ("kalman_from_jerk_density", "sample_period_s", 1e300): "jerk_density_rad2_s5",
    ("FaultThresholds", "nominal_amplitude", 1e300): "degradation_high",
    ("FaultThresholds", "degradation_high", 1e300): "max_input_amplitude",
    **{(f"MotionProfile.{label}", name, 1e300): "profile"
       for label, names in (("constant_speed", ["duration_s"]), ("constant_acceleration", ["duration_s"]),
                            ("step", ["duration_s"]), ("speed_ripple", ["duration_s"]),
                            ("trapezoidal", ["distance_rad", "max_speed_rad_s"]),
                            ("s_curve", ["distance_rad", "max_speed_rad_s"]))
       for name in names},
}


@pytest.mark.parametrize("label,call,kwargs,name,bad", list(_probes()))
def test_a_refused_argument_is_named_as_the_caller_spelled_it(label, call, kwargs, name, bad):
    args = dict(kwargs, **{name: bad})
    if bad in ACCEPTED.get((label, name), ()):
        call(**args)
        return
    named = NAMED_AS.get((label, name, bad), name)
    with pytest.raises(at.ConfigError) as e:
        call(**args)
    assert e.value.parameter == named, str(e.value)
    assert str(e.value).startswith(named), str(e.value)


def test_the_tables_list_only_probed_arguments():
    probed = {(label, name) for label, _, kwargs in CASES for name in kwargs}
    assert set(ACCEPTED) <= probed
    assert {(label, name) for label, name, _ in NAMED_AS} <= probed


def test_every_case_is_valid_as_written():
    # The probes only mean something if the unmodified call is accepted.
    for label, call, kwargs in CASES:
        call(**kwargs)


def test_scenario_generation_names_its_keywords():
    with pytest.raises(at.ConfigError) as e:
        at.Scenario.generate(_profile().constant_speed(10.0, 0.01), sample_period_s=-1.0)
    assert e.value.parameter == "sample_period_s"
    with pytest.raises(at.ConfigError) as e:
        at.Scenario.from_arrays(sample_period_s=TS, angle_rad=np.zeros(3), y_c=np.zeros(3),
                                y_s=np.zeros(2))
    assert e.value.parameter in ("y_c", "y_s", "angle_rad")
