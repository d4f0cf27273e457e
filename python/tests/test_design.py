"""The design functions, DesignReport, scenarios and metrics through the binding: the same
numbers as the Rust crate (its documented figures), errors naming the argument."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import angletrack as at


def test_paper_overshoots_through_the_binding():
    settings = at.paper_settings()  # 100 kHz, at least 200 times each bandwidth
    assert at.PAPER_OVERSHOOT_SAMPLE_PERIOD_S == 1e-5
    assert [s.paper_overshoot_percent for s in settings] == [5.0, 20.8, 10.0, 30.9]
    for setting in settings:
        r = setting.design.report(sensor_noise_std=0.0)
        paper = setting.paper_overshoot_percent / 100.0
        assert r.sample_period_s == at.PAPER_OVERSHOOT_SAMPLE_PERIOD_S
        assert r.sample_period_s * r.bandwidth_hz < 1 / 200
        assert r.linear_step.overshoot == pytest.approx(paper, abs=0.003)
        assert r.continuous_step.overshoot == pytest.approx(paper, abs=0.001)


def test_paper_compared_observers_are_the_three_observers_at_10_khz():
    observers = dict(at.paper_compared_observers())
    assert list(observers) == ["2nd-order ATO", "3rd-order ATO", "Kalman ATO"]
    for design in observers.values():
        assert design.sample_period_s == at.PAPER_COMPARISON_SAMPLE_PERIOD_S == 1e-4
    assert observers["2nd-order ATO"].report().bandwidth_hz == pytest.approx(at.PAPER_COMPARISON_BANDWIDTH_HZ, rel=0.02)


def test_second_order_acceleration_constant_and_design_fields():
    d = at.second_order_from_tracking_error(max_error_rad=1e-3, acceleration_rad_s2=1e3, damping=1.0, sample_period_s=1e-5)
    assert d.order == 2 and d.discretisation == "pole_matching" and d.kalman is None
    k_a, k_b = d.continuous_gains
    assert k_b == pytest.approx(1e6, rel=1e-12) and k_a == pytest.approx(2.0 * 1e3, rel=1e-12)
    assert len(d.continuous_poles) == 2 and all(isinstance(p, complex) for p in d.continuous_poles)
    r = d.report(sensor_noise_std=0.01)
    # Ka of the discrete loop = l2 / ((1 - l1) Ts^2), close to the continuous k_b1 (docs/theory.md §2).
    l1, l2 = d.gains.gains
    assert r.acceleration_constant_per_s2 == pytest.approx(l2 / ((1 - l1) * 1e-10), rel=1e-9)
    assert r.acceleration_constant_per_s2 == pytest.approx(1e6, rel=0.02)
    assert r.error_per_unit_jerk_s3 is None
    assert "DesignReport:" in repr(r) and "-3 dB bandwidth" in repr(r) and "Ka discrete" in str(r)
    assert "Design(method=" in repr(d)


def test_kalman_design_matches_the_crate_doc_figures():
    d = at.kalman(process_noise_q=1e-9, measurement_noise_r=1.0, sample_period_s=1e-4)
    l1, l2, l3 = d.gains.gains
    assert l1 == pytest.approx(0.0613, abs=1e-3) and l2 == pytest.approx(0.00194, abs=1e-5) and l3 == pytest.approx(3.06e-5, abs=1e-7)
    k = d.kalman
    assert 0 < k.angle_floor_rad < 1 and k.process_noise_q == 1e-9 and len(k.covariance) == 3
    # The predicted error of a Kalman design at its own q, r is its Riccati floor (docs/theory.md §4, §8).
    p = at.predicted_error(d.gains, sensor_noise_std=1.0, process_noise_q=1e-9)
    assert p.angle_rms_rad == pytest.approx(k.angle_floor_rad, rel=1e-6)
    same = at.kalman_from_jerk_std(jerk_std_rad_s3=math.sqrt(1e-9) / 1e-12, sensor_noise_std=1.0, sample_period_s=1e-4)
    np.testing.assert_allclose(same.gains.gains, d.gains.gains, rtol=1e-6)


@pytest.mark.parametrize(
    "call, parameter, message",
    [
        (lambda: at.kalman(process_noise_q=-1.0, measurement_noise_r=1.0, sample_period_s=1e-4), "process_noise_q", r"process_noise_q must be positive"),
        (lambda: at.kalman(process_noise_q=1.0, measurement_noise_r=math.nan, sample_period_s=1e-4), "measurement_noise_r", r"measurement_noise_r must be finite"),
        (lambda: at.second_order_from_bandwidth(bandwidth_hz=1e5, damping=1.0, sample_period_s=1e-4), "bandwidth_hz", r"bandwidth_hz makes the loop too fast"),
        (lambda: at.second_order_from_tracking_error(max_error_rad=0.0, acceleration_rad_s2=1.0, damping=1.0, sample_period_s=1e-4), "max_error_rad", r"max_error_rad must be positive"),
        (lambda: at.third_order_from_poles(pole_ratio=39.04, pole_time_constant_s=0.02, pole_frequency_ratio=1.0, sample_period_s=0.0), "sample_period_s", r"sample_period_s must be positive"),
        (lambda: at.third_order_from_poles(pole_ratio=-1.0, pole_time_constant_s=0.02, pole_frequency_ratio=1.0, sample_period_s=1e-4), "pole_ratio", r"^pole_ratio \(K\) must be positive"),
        (lambda: at.third_order_butterworth(time_constant_s=0.005, sample_period_s=1e-4, discretisation="zoh"), "discretisation", r"discretisation .*expected pole_matching, forward_euler or tustin"),
        (lambda: at.kalman_from_jerk_density(jerk_density_rad2_s5=-1.0, sensor_noise_std=0.01, sample_period_s=1e-4), "jerk_density_rad2_s5", r"jerk_density_rad2_s5 must be positive"),
    ],
)
def test_design_errors_name_the_argument(call, parameter, message):
    with pytest.raises(at.ConfigError, match=message) as e:
        call()
    assert e.value.parameter == parameter


def test_discretisation_names_are_parsed_by_the_crate():
    kw = dict(time_constant_s=0.005, sample_period_s=1e-4)
    assert at.third_order_butterworth(**kw, discretisation="Forward-Euler").discretisation == "forward_euler"


def test_discretisations_differ_and_are_reported():
    kw = dict(bandwidth_hz=500.0, damping=0.8, sample_period_s=1e-4)
    matched = at.second_order_from_bandwidth(**kw)
    tustin = at.second_order_from_bandwidth(**kw, discretisation="tustin")
    assert tustin.discretisation == "tustin"
    assert matched.report().pole_shift == pytest.approx(0.0, abs=1e-9)
    assert tustin.report().pole_shift > 1e-3
    assert matched.gains != tustin.gains


def test_design_from_given_gains():
    g = at.Gains([0.05, 0.0012], sample_period_s=1e-4)
    d = at.Design.from_gains(g)
    assert d.gains == g and d.method == "given gains" and d.discretisation is None
    assert d.report().bandwidth_hz > 0


def test_scenario_is_seeded_and_metrics_measure_a_run():
    profile = at.MotionProfile(0.0, 0.0).trapezoidal(distance_rad=10.0, max_speed_rad_s=50.0, max_acceleration_rad_s2=500.0)
    assert len(profile) == 1 and "trapezoidal(distance_rad=10.0" in repr(profile)
    a = at.Scenario.generate(profile, at.SensorModel(noise_std=0.01), sample_period_s=1e-4, seed=7)
    b = at.Scenario.generate(profile, at.SensorModel(noise_std=0.01), sample_period_s=1e-4, seed=7)
    c = at.Scenario.generate(profile, at.SensorModel(noise_std=0.01), sample_period_s=1e-4, seed=8)
    np.testing.assert_array_equal(a.y_c, b.y_c)
    assert not np.array_equal(a.y_c, c.y_c)
    assert a.angle_rad[-1] == pytest.approx(10.0, abs=1e-9)
    assert a.time_s[1] == pytest.approx(1e-4) and len(a) == len(a.y_s)
    # The noise has the requested standard deviation (4000+ samples: within 5 %).
    resid = a.y_c - np.cos(a.angle_rad)
    assert np.std(resid) == pytest.approx(0.01, rel=0.05)
    design = at.third_order_from_poles(pole_ratio=39.04, pole_time_constant_s=0.02, pole_frequency_ratio=3 * math.pi / 2, sample_period_s=1e-4)
    est = at.track(design.gains, a.y_c, a.y_s)
    m = at.metrics(a, est, skip_s=0.05)
    err = np.angle(np.exp(1j * (a.angle_rad - est.position)))[500:]
    assert m.samples == len(err)
    assert m.angle_error_rad.rms == pytest.approx(np.sqrt(np.mean(err**2)), rel=1e-9)
    assert m.angle_error_rad.max == pytest.approx(np.max(np.abs(err)), rel=1e-12)
    assert m.speed_error_rad_s.rms == pytest.approx(np.sqrt(np.mean((a.speed_rad_s - est.speed)[500:] ** 2)), rel=1e-9)
    assert m.overshoot is not None and m.time_to_lock_s is not None


def test_float32_estimates_are_measured_too():
    profile = at.MotionProfile(0.3, 20.0).constant_speed(20.0, 0.2)
    sc = at.Scenario.generate(profile, sample_period_s=1e-4)
    g = at.Gains([0.1, 0.005, 1e-4], 1e-4)
    est32 = at.track(g, sc.y_c.astype(np.float32), sc.y_s.astype(np.float32))
    m = at.metrics(sc, est32, skip_s=0.1)
    assert m.angle_error_rad.max < 1e-5 and m.time_to_lock_s is not None


def test_capture_scenario_without_speed_reports_no_speed_error():
    t = np.arange(2000) * 1e-4
    theta = 1.0 + 30.0 * t
    sc = at.Scenario.from_arrays(sample_period_s=1e-4, angle_rad=theta, y_c=np.cos(theta), y_s=np.sin(theta))
    est = at.track(at.Gains([0.1, 0.005, 1e-4], 1e-4), sc.y_c, sc.y_s)
    m = at.metrics(sc, est, skip_s=0.1)
    assert m.speed_error_rad_s is None and m.angle_error_rad.max < 1e-6
    with pytest.raises(ValueError, match=r"y_s: has 3 samples but angle_rad has 2000"):
        at.Scenario.from_arrays(sample_period_s=1e-4, angle_rad=theta, y_c=np.cos(theta), y_s=np.zeros(3))


def test_bad_scenario_arguments_name_them():
    with pytest.raises(ValueError, match=r"noise|sensor_noise_std"):
        at.Scenario.generate(at.MotionProfile().constant_speed(1.0, 0.1), at.SensorModel(noise_std=-1.0), sample_period_s=1e-4)
    with pytest.raises(ValueError, match=r"sample_period_s"):
        at.Scenario.generate(at.MotionProfile().constant_speed(1.0, 0.1), sample_period_s=0.0)
    with pytest.raises(ValueError, match=r"duration_s"):
        at.Scenario.generate(at.MotionProfile().constant_speed(1.0, -0.1), sample_period_s=1e-4)


def test_diagnostics_flag_bad_samples_and_thresholds_are_checked():
    g = at.Gains([0.1, 0.005, 1e-4], 1e-4)
    obs = at.Observer(g)
    theta = np.arange(1000) * 1e-3
    y_c, y_s = np.cos(theta), np.sin(theta)
    y_c[300] = np.nan
    est = obs.update(y_c, y_s)
    assert est.faults.dtype == np.uint8
    assert at.Faults(int(est.faults[300])) & at.Faults.BAD_SAMPLE
    assert not (est.faults[:300] & at.Faults.BAD_SAMPLE).any()
    assert at.Faults(obs.latched_faults) & at.Faults.BAD_SAMPLE
    obs.clear_faults()
    assert not at.Faults(obs.latched_faults) & at.Faults.BAD_SAMPLE
    with pytest.raises(ValueError, match=r"filter_factor"):
        at.Observer(g, fault_thresholds=at.FaultThresholds(filter_factor=1.5))
    bare = at.Observer(g, fault_thresholds=at.FaultThresholds.disabled())
    assert not bare.fault_thresholds.monitor and not bare.fault_thresholds.re_acquire


def test_binding_run_equals_the_crates_own_179_degree_simulation():
    """The crate's DesignReport simulates the bare loop (f64, exact sin/cos) from rest at 0
    toward a constant 179 degrees; the binding's observer on the same samples gives the
    same overshoot, to rounding."""
    design = at.third_order_from_poles(pole_ratio=39.04, pole_time_constant_s=0.005, pole_frequency_ratio=3 * math.pi / 2, sample_period_s=1e-4)
    r = design.report()
    n = 20_000  # 2 s: many settling times
    target = at.LARGE_STEP_RAD
    obs = at.Observer(design.gains, dtype=np.float64, sin_cos="exact", fault_thresholds=at.FaultThresholds.disabled())
    obs.set_state(0.0)
    est = obs.update(np.full(n, math.cos(target)), np.full(n, math.sin(target)))
    overshoot = max(0.0, float(np.max((est.position - target) / target)))
    assert overshoot == pytest.approx(r.large_step.overshoot, rel=1e-12, abs=1e-15)
    # Both end on the step (the crate simulates a shorter horizon: still settling at 1e-7).
    assert est.position[-1] == pytest.approx(target, abs=1e-9)
    assert r.large_step_final_rad == pytest.approx(target, abs=1e-6)
    assert r.large_step_with_diagnostics.overshoot < r.large_step.overshoot


any_float = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([0.0, -1.0, 1e-300, 1e300])
DESIGNS = [
    (at.second_order_from_tracking_error, 4),
    (at.second_order_from_bandwidth, 3),
    (at.second_order_butterworth, 2),
    (at.third_order_from_poles, 4),
    (at.third_order_butterworth, 2),
    (at.third_order_from_overshoot, 4),
    (at.kalman, 3),
    (at.kalman_from_jerk_std, 3),
    (at.kalman_from_jerk_density, 3),
]


@settings(max_examples=60, deadline=None, derandomize=True)
@given(index=st.integers(0, len(DESIGNS) - 1), values=st.lists(any_float, min_size=4, max_size=4))
def test_design_functions_under_random_arguments_give_a_design_or_a_value_error(index, values):
    function, arity = DESIGNS[index]
    try:
        design = function(*values[:arity])
    except ValueError as e:
        assert str(e)  # a message naming the argument
        return
    l = design.gains.gains
    assert all(math.isfinite(x) for x in l) and design.gains.sample_period_s > 0


def test_noise_on_the_kalman_model_compares_the_three_observers():
    """Sensor noise and the Kalman model's random jerk (docs/theory.md §4, §8)."""
    observers = dict(at.paper_compared_observers())
    kalman = observers["Kalman ATO"]
    q = kalman.kalman.process_noise_q
    noise = at.PAPER_COMPARISON_SENSOR_NOISE_STD
    assert at.predicted_error_on_kalman_model(observers["2nd-order ATO"].gains, noise, q) is None
    floor = kalman.report(sensor_noise_std=noise).kalman_angle_floor_rad
    on_model = at.predicted_error_on_kalman_model(kalman.gains, noise, q)
    assert on_model.angle_rms_rad == pytest.approx(floor, rel=1e-6)
    third = at.predicted_error_on_kalman_model(observers["3rd-order ATO"].gains, noise, q)
    assert third.angle_rms_rad > on_model.angle_rms_rad
    # Without the random jerk it is the sensor-noise-only figure of every design.
    for design in observers.values():
        alone = at.predicted_error_on_kalman_model(design.gains, noise, 0.0)
        assert alone.angle_rms_rad == pytest.approx(design.report(sensor_noise_std=noise).angle_error_rms_rad, rel=1e-12)
    with pytest.raises(at.ConfigError) as e:
        at.predicted_error_on_kalman_model(kalman.gains, noise, -1.0)
    assert e.value.parameter == "process_noise_q"


def test_largest_trackable_speed_is_half_a_turn_per_sample():
    """docs/theory.md §9."""
    assert at.max_trackable_speed_rad_s(1e-4) == pytest.approx(math.pi / 1e-4, rel=1e-15)
    d = at.second_order_butterworth(time_constant_s=0.005, sample_period_s=1e-4)
    assert d.report().max_speed_rad_s == at.max_trackable_speed_rad_s(1e-4)


def test_sampled_tracking_error_design_meets_its_specification_on_the_sampled_loop():
    d = at.second_order_from_tracking_error_sampled(
        max_error_rad=1e-3, acceleration_rad_s2=2e3, overshoot=0.05, sample_period_s=50e-6
    )
    assert d.order == 2 and d.discretisation is None and d.continuous_gains is None
    np.testing.assert_allclose(d.gains.gains, [0.2134374, 0.003932813], rtol=1e-6)
    r = d.report()
    assert 2e3 / r.acceleration_constant_per_s2 == pytest.approx(1e-3, rel=1e-3)
    assert r.linear_step.overshoot == pytest.approx(0.05, abs=1e-4)
    with pytest.raises(at.ConfigError) as e:
        at.second_order_from_tracking_error_sampled(
            max_error_rad=1e-3, acceleration_rad_s2=2e3, overshoot=1.5, sample_period_s=50e-6
        )
    assert e.value.parameter == "overshoot"


def test_continuous_gains_pair_with_the_gains_and_the_loop_polynomial_is_lowest_first():
    d = at.third_order_butterworth(time_constant_s=0.005, sample_period_s=1e-4)
    k_a, k_b, k_c = d.continuous_gains
    tc = 0.005
    assert (k_a, k_b, k_c) == pytest.approx((2 / tc, 2 / tc**2, 1 / tc**3), rel=1e-12)
    assert d.continuous_loop_polynomial == [k_c, k_b, k_a]
