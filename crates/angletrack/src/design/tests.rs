//! Unit tests of the design functions: arguments, gains, poles and discretisations
//! (`docs/theory.md §2` to `§4`, `§7`).

use std::f64::consts::SQRT_2;

use angletrack_core::{Gains, ObserverState};

use crate::paper::{FIVE_PERCENT_DAMPING, POLE_FREQUENCY_RATIO, POLE_RATIO};
use crate::*;

const PM: Discretisation = Discretisation::PoleMatching;

/// The bad values every positive argument must refuse, with the error each gives.
fn bad_positive(argument: Argument) -> [(f64, Error); 5] {
    [
        (f64::NAN, Error::NotFinite(argument)),
        (f64::INFINITY, Error::NotFinite(argument)),
        (f64::NEG_INFINITY, Error::NotFinite(argument)),
        (0.0, Error::NotPositive(argument)),
        (-1.0, Error::NotPositive(argument)),
    ]
}

/// Checks that replacing argument `i` of `good` by each bad value gives the expected error.
fn check_arguments<const K: usize, D: std::fmt::Debug>(
    good: [f64; K],
    arguments: [Argument; K],
    design: impl Fn([f64; K]) -> Result<D, Error>,
) {
    assert!(
        design(good).is_ok(),
        "the good arguments {good:?} are refused"
    );
    for (i, argument) in arguments.iter().enumerate() {
        for (value, expected) in bad_positive(*argument) {
            let mut args = good;
            args[i] = value;
            let err = design(args).expect_err("a bad argument must be refused");
            assert_eq!(err, expected, "argument {i} = {value}");
            assert_eq!(err.argument(), Some(*argument));
            assert!(err.to_string().contains(argument.name()), "{err}");
        }
    }
}

#[test]
fn every_design_function_refuses_each_bad_argument() {
    use Argument::*;
    check_arguments(
        [1e-3, 1e3, 1.0, 1e-5],
        [MaxError, Acceleration, Damping, SamplePeriod],
        |[e, a, m, ts]| second_order_from_tracking_error(e, a, m, ts, PM),
    );
    check_arguments(
        [100.0, 0.7, 1e-5],
        [Bandwidth, Damping, SamplePeriod],
        |[b, m, ts]| second_order_from_bandwidth(b, m, ts, PM),
    );
    check_arguments([1e-2, 1e-5], [TimeConstant, SamplePeriod], |[tc, ts]| {
        second_order_butterworth(tc, ts, PM)
    });
    check_arguments(
        [POLE_RATIO, 0.01, POLE_FREQUENCY_RATIO, 1e-5],
        [
            PoleRatio,
            PoleTimeConstant,
            PoleFrequencyRatio,
            SamplePeriod,
        ],
        |[k, t, psi, ts]| third_order_from_poles(k, t, psi, ts, PM),
    );
    check_arguments(
        [0.1, 0.05, POLE_FREQUENCY_RATIO, 1e-5],
        [Overshoot, SettlingTime, PoleFrequencyRatio, SamplePeriod],
        |[o, st, psi, ts]| third_order_from_overshoot(o, st, psi, ts, PM),
    );
    check_arguments([1e-2, 1e-5], [TimeConstant, SamplePeriod], |[tc, ts]| {
        third_order_butterworth(tc, ts, PM)
    });
    check_arguments(
        [1e-12, 1e-4, 1e-4],
        [ProcessNoise, MeasurementNoise, SamplePeriod],
        |[q, r, ts]| kalman(q, r, ts),
    );
    check_arguments(
        [1e5, 0.01, 1e-4],
        [JerkStd, SensorNoiseStd, SamplePeriod],
        |[j, s, ts]| kalman_from_jerk_std(j, s, ts),
    );
    check_arguments(
        [1e6, 0.01, 1e-4],
        [JerkDensity, SensorNoiseStd, SamplePeriod],
        |[j, s, ts]| kalman_from_jerk_density(j, s, ts),
    );
}

#[test]
fn out_of_range_arguments_name_the_argument() {
    let too_fast = second_order_from_bandwidth(1e4, 0.7, 1e-4, PM).unwrap_err();
    assert!(matches!(
        too_fast,
        Error::TooFastForSampleRate {
            argument: Argument::Bandwidth,
            ..
        }
    ));
    assert!(too_fast.to_string().contains("bandwidth_hz"));
    // Lightly damped complex poles leave the forward-Euler stability region first.
    // K = 2, T = 1 ms at 10 kHz: the complex pair has |s| Ts = 0.48 > 2 / sqrt(1 + psi^2).
    let euler = third_order_from_poles(
        2.0,
        1e-3,
        POLE_FREQUENCY_RATIO,
        1e-4,
        Discretisation::ForwardEuler,
    );
    assert!(matches!(
        euler,
        Err(Error::TooFastForSampleRate {
            argument: Argument::PoleTimeConstant,
            ..
        })
    ));
    assert!(third_order_from_poles(2.0, 1e-3, POLE_FREQUENCY_RATIO, 1e-4, PM).is_ok());
    assert!(matches!(
        second_order_from_tracking_error(1e-3, 1e3, 1e4, 1e-5, PM),
        Err(Error::OutOfRange {
            argument: Argument::Damping,
            ..
        })
    ));
    assert!(matches!(
        kalman(1.0, 1e-9, 1e-4),
        Err(Error::OutOfRange {
            argument: Argument::ProcessNoise,
            ..
        })
    ));
    assert!(matches!(
        kalman_from_jerk_std(1e30, 1e-3, 1e-4),
        Err(Error::OutOfRange {
            argument: Argument::JerkStd,
            ..
        })
    ));
    // Below what K <= 1e4 gives: refused (after a bounded search).
    assert_eq!(
        third_order_from_overshoot(1e-9, 0.05, POLE_FREQUENCY_RATIO, 1e-5, PM).unwrap_err(),
        Error::NoSolution(Argument::Overshoot)
    );
    // psi = 1 cannot give 50 % overshoot in the family.
    assert_eq!(
        third_order_from_overshoot(0.5, 0.05, 1.0, 1e-5, PM).unwrap_err(),
        Error::NoSolution(Argument::Overshoot)
    );
    // Errors are std errors with a source for the core's refusals.
    let wrapped: Box<dyn std::error::Error> = Box::new(Error::Gains(
        Gains::<f64, 2>::new([-1.0, 0.1], 1e-4).unwrap_err(),
    ));
    assert!(wrapped.source().is_some());
}

/// Relative distance between the continuous-equivalent and the design poles.
fn shift(design_report: &DesignReport) -> f64 {
    design_report.pole_shift.expect("a continuous design")
}

#[test]
fn pole_matching_is_exact_to_rounding_even_far_below_the_sample_rate() {
    for ts in [1e-3, 1e-5, 1e-7, 1e-9] {
        let design = third_order_from_poles(POLE_RATIO, 0.1, POLE_FREQUENCY_RATIO, ts, PM).unwrap();
        let poles = crate::linalg::roots(&design.gains.loop_polynomial());
        for s in &design.continuous_poles {
            let nearest = poles
                .iter()
                .map(|u| (crate::linalg::ln_1p(*u) / ts - s).norm() / s.norm())
                .fold(f64::INFINITY, f64::min);
            // Rounding of the gains themselves: relative error ~ eps / (|s| Ts).
            let bound = 1e-12_f64.max(50.0 * f64::EPSILON / (s.norm() * ts));
            assert!(nearest < bound, "ts {ts}: relative pole error {nearest}");
        }
    }
}

#[test]
fn euler_and_tustin_move_the_poles_as_their_series_say() {
    // Forward Euler: ln(1 + s Ts) / Ts = s (1 - s Ts / 2 + ...): relative shift |s| Ts / 2.
    // Tustin: 2/Ts atanh(s Ts / 2) = s (1 + (s Ts)^2 / 12 + ...).
    let (tc, ts) = (1e-2, 1e-4);
    let s_ts = ts / tc; // every Butterworth pole has |s| = 1/Tc
    let euler = third_order_butterworth(tc, ts, Discretisation::ForwardEuler).unwrap();
    let tustin = third_order_butterworth(tc, ts, Discretisation::Tustin).unwrap();
    let matched = third_order_butterworth(tc, ts, PM).unwrap();
    let e = shift(&DesignReport::new(&euler, 0.0).unwrap());
    let t = shift(&DesignReport::new(&tustin, 0.0).unwrap());
    let m = shift(&DesignReport::new(&matched, 0.0).unwrap());
    assert!((e / (s_ts / 2.0) - 1.0).abs() < 0.02, "Euler shift {e}");
    assert!(
        (t / (s_ts * s_ts / 12.0) - 1.0).abs() < 0.02,
        "Tustin shift {t}"
    );
    assert!(m < 1e-10, "pole matching shift {m}");
}

#[test]
fn second_order_paper_rule_gives_its_continuous_gains_and_ka() {
    let design = second_order_from_tracking_error(2e-3, 400.0, 1.945, 1e-5, PM).unwrap();
    let [k_a, k_b] = design.continuous_gains.unwrap();
    assert!((k_b - 2e5).abs() < 1e-9 * 2e5);
    assert!((k_a - 2.0 * 1.945 * 2e5_f64.sqrt()).abs() < 1e-9 * k_a);
    let report = DesignReport::new(&design, 0.0).unwrap();
    // The generic steady-state error solve agrees with the closed form of the core docs.
    let [l1, l2] = design.gains.gains();
    let ka = l2 / ((1.0 - l1) * 1e-10);
    let reported = report.acceleration_constant_per_s2.unwrap();
    assert!((reported / ka - 1.0).abs() < 1e-9, "{reported} vs {ka}");
    assert_eq!(report.continuous_acceleration_constant_per_s2, Some(k_b));
    // Discretisation error of Ka at fs = 100 kHz, 57 Hz loop: below 1 %.
    assert!((reported / k_b - 1.0).abs() < 0.01);
}

#[test]
fn bandwidth_design_meets_its_bandwidth() {
    for damping in [0.5, SQRT_2 / 2.0, 1.0, 2.0] {
        let design = second_order_from_bandwidth(50.0, damping, 1e-6, PM).unwrap();
        let report = DesignReport::new(&design, 0.0).unwrap();
        let bw = report.bandwidth_hz.unwrap();
        assert!((bw / 50.0 - 1.0).abs() < 2e-3, "damping {damping}: {bw} Hz");
    }
}

#[test]
fn butterworth_settings_have_the_textbook_gains() {
    let tc = 4e-3;
    let two = second_order_butterworth(tc, 1e-5, PM).unwrap();
    let [a, b] = two.continuous_gains.unwrap();
    assert!((a - SQRT_2 / tc).abs() < 1e-9 * a && (b - 1.0 / (tc * tc)).abs() < 1e-9 * b);
    let three = third_order_butterworth(tc, 1e-5, PM).unwrap();
    let [a, b, c] = three.continuous_gains.unwrap();
    assert!((a - 2.0 / tc).abs() < 1e-9 * a);
    assert!((b - 2.0 / (tc * tc)).abs() < 1e-9 * b);
    assert!((c - 1.0 / (tc * tc * tc)).abs() < 1e-9 * c);
}

#[test]
fn overshoot_design_meets_its_overshoot_and_settling_time() {
    let design = third_order_from_overshoot(0.1, 0.04, POLE_FREQUENCY_RATIO, 2e-6, PM).unwrap();
    let report = DesignReport::new(&design, 0.0).unwrap();
    let continuous = report.continuous_step.unwrap();
    assert!((continuous.overshoot - 0.1).abs() < 1e-6);
    assert!((continuous.settling_time_s / 0.04 - 1.0).abs() < 1e-3);
    // The discrete loop, at ~700 times its bandwidth, follows within 0.1 point.
    assert!((report.linear_step.overshoot - 0.1).abs() < 1e-3);
    // The paper's K for 10 %.
    let k = design.continuous_poles[0].re / design.continuous_poles[1].re;
    assert!((k - POLE_RATIO).abs() < 0.05, "K = {k}");
}

#[test]
fn kalman_gain_solves_the_riccati_equation_and_depends_on_q_over_r_only() {
    let design = kalman(1e-10, 1e-3, 1e-4).unwrap();
    let solution = design.kalman.unwrap();
    let l = design.gains.gains();
    // P = A (P - P e1 e1^T P / (r + P11)) A^T + q G G^T, and K = P e1 / (r + P11).
    let p = nalgebra::Matrix3::from_fn(|i, j| solution.predicted_covariance[i][j]);
    let a = nalgebra::Matrix3::new(1.0, 1.0, 0.5, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0);
    let g = nalgebra::Vector3::new(1.0 / 6.0, 0.5, 1.0);
    let r = solution.measurement_noise_r;
    let filtered = p - p.column(0) * p.row(0) / (r + p[(0, 0)]);
    let residual = a * filtered * a.transpose() + g * g.transpose() * 1e-10 - p;
    assert!(
        residual.norm() < 1e-10 * p.norm(),
        "residual {}",
        residual.norm()
    );
    for i in 0..3 {
        assert!((l[i] - p[(i, 0)] / (r + p[(0, 0)])).abs() < 1e-12 * l[i].abs().max(1e-300));
    }
    let scaled = kalman(1e-6, 10.0, 1e-4).unwrap().gains.gains();
    for i in 0..3 {
        assert!((scaled[i] / l[i] - 1.0).abs() < 1e-8, "gain {i}");
    }
    // The filtered covariance is the steady state of the loop under both noises.
    let predicted = predicted_error(&design.gains, r.sqrt(), 1e-10).unwrap();
    assert!((predicted.angle_rms_rad / solution.angle_floor_rad() - 1.0).abs() < 1e-8);
    assert!((predicted.speed_rms_rad_s / solution.speed_floor_rad_s(1e-4) - 1.0).abs() < 1e-8);
}

#[test]
fn kalman_from_physical_units_scales_as_documented() {
    let ts = 5e-5;
    let by_std = kalman_from_jerk_std(2e4, 0.02, ts).unwrap();
    let direct = kalman((2e4 * ts.powi(3)).powi(2), 0.02 * 0.02, ts).unwrap();
    let same = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x / y - 1.0).abs() < 1e-12);
    assert!(same(by_std.gains.gains(), direct.gains.gains()));
    let by_density = kalman_from_jerk_density(3e6, 0.02, ts).unwrap();
    let direct = kalman(3e6 * ts.powi(5), 0.02 * 0.02, ts).unwrap();
    assert!(same(by_density.gains.gains(), direct.gains.gains()));
}

#[test]
fn f32_conversion_is_checked_by_the_core() {
    let design = kalman(1e-12, 1e-4, 1e-4).unwrap();
    let single = design.to_gains::<f32>().unwrap();
    for (a, b) in single.gains().iter().zip(design.gains.gains()) {
        assert!(((*a as f64) / b - 1.0).abs() < 1e-7);
    }
    // Gains on the edge of the stability region in f64 can leave it when rounded to f32.
    let edge = Gains::<f64, 2>::new([1.0, 2.0 - 1e-12], 1e-4).unwrap();
    assert!(matches!(
        convert_gains::<f32, 2>(&edge),
        Err(Error::Gains(angletrack_core::ConfigError::Unstable { .. }))
    ));
}

#[test]
fn kalman_design_works_over_its_whole_documented_range() {
    for ratio in [1e-30, 1e-24, 1e-18, 1e-12, 1e-6, 1.0, 1e6] {
        let design =
            kalman(ratio * 1e-2, 1e-2, 1e-4).unwrap_or_else(|e| panic!("q/r = {ratio:e}: {e}"));
        let solution = design.kalman.unwrap();
        let l = design.gains.gains();
        let p = solution.predicted_covariance;
        let r = solution.measurement_noise_r;
        for i in 0..3 {
            let expected = p[i][0] / (r + p[0][0]);
            assert!(
                (l[i] / expected - 1.0).abs() < 1e-9,
                "q/r = {ratio:e}, gain {i}"
            );
        }
        // The filtered angle variance is below the measurement's and above 0.
        assert!(solution.covariance[0][0] > 0.0 && solution.covariance[0][0] < r);
        if ratio == 1e-30 || ratio == 1e6 {
            // The extreme designs analyse too (a loop 10^5 samples slow, a near-deadbeat one).
            let report = DesignReport::new(&design, 0.1).unwrap();
            assert!(report.angle_error_rms_rad > 0.0 && report.angle_error_rms_rad.is_finite());
            assert!(report.discrete_poles.iter().all(|z| z.norm() < 1.0));
        }
    }
}

#[test]
fn design_functions_never_panic_on_any_argument() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let specials = [
        f64::NAN,
        f64::INFINITY,
        -1.0,
        0.0,
        f64::MIN_POSITIVE,
        f64::MAX,
        1e-300,
    ];
    let value = |rng: &mut rand_chacha::ChaCha8Rng| {
        if rng.random_bool(0.2) {
            specials[rng.random_range(0..specials.len())]
        } else {
            10f64.powf(rng.random_range(-12.0..12.0))
        }
    };
    let disc = [PM, Discretisation::ForwardEuler, Discretisation::Tustin];
    let mut accepted = 0;
    for i in 0..300 {
        let d = disc[i % 3];
        let a: [f64; 4] = std::array::from_fn(|_| value(&mut rng));
        let mut results = [
            second_order_from_tracking_error(a[0], a[1], a[2], a[3], d).map(|x| x.gains.gains()[0]),
            second_order_from_bandwidth(a[0], a[1], a[2], d).map(|x| x.gains.gains()[0]),
            second_order_butterworth(a[0], a[1], d).map(|x| x.gains.gains()[0]),
            third_order_from_poles(a[0], a[1], a[2], a[3], d).map(|x| x.gains.gains()[0]),
            third_order_butterworth(a[0], a[1], d).map(|x| x.gains.gains()[0]),
            kalman(a[0], a[1], a[2]).map(|x| x.gains.gains()[0]),
            kalman_from_jerk_std(a[0], a[1], a[2]).map(|x| x.gains.gains()[0]),
            kalman_from_jerk_density(a[0], a[1], a[2]).map(|x| x.gains.gains()[0]),
        ]
        .to_vec();
        // The sampled design simulates its loop: one call in ten keeps the sweep short.
        if i % 10 == 0 {
            results.push(
                second_order_from_tracking_error_sampled(a[0], a[1], a[2], a[3])
                    .map(|x| x.gains.gains()[0]),
            );
        }
        for result in results {
            match result {
                Ok(l1) => {
                    assert!(l1.is_finite() && l1 > 0.0);
                    accepted += 1;
                }
                Err(e) => assert!(!e.to_string().is_empty()),
            }
        }
    }
    // The sweep reaches the accepting side too.
    assert!(accepted > 100, "only {accepted} designs accepted");
}

/// The headline specification (1 mrad at 2000 rad/s^2, 5 %, 20 kHz): the sampled design
/// meets it on the discrete loop, where the paper's continuous rule falls short.
#[test]
fn sampled_design_meets_tracking_error_and_overshoot_on_the_discrete_loop() {
    let (max_error, alpha, ts) = (1e-3, 2e3, 50e-6);
    let design = second_order_from_tracking_error_sampled(max_error, alpha, 0.05, ts).unwrap();
    assert_eq!(design.method, DesignMethod::SecondOrderSampledTrackingError);
    let report = DesignReport::new(&design, 0.0).unwrap();
    let error = alpha / report.acceleration_constant_per_s2.unwrap();
    assert!((error / max_error - 1.0).abs() < 1e-9, "{error} rad");
    let overshoot = report.linear_step.overshoot;
    assert!((overshoot - 0.05).abs() < 1e-6, "{overshoot}");
    // The core's loop under constant acceleration settles at that error (sin e ~ e).
    let mut state = ChainState {
        front_end: (),
        observer: ObserverState::at(0.0, 0.0, 0.0, ts).unwrap(),
    };
    let mut last = 0.0;
    for k in 0..40_000 {
        let theta = 0.5 * alpha * (k as f64 * ts).powi(2);
        last = theta
            - Chain::new((), design.gains)
                .update(&mut state, (theta.cos(), theta.sin()))
                .position();
    }
    assert!((last / max_error - 1.0).abs() < 1e-3, "{last} rad");
    // The paper's rule for the same specification: 0.869 mrad and 4.35 % when sampled.
    let paper =
        second_order_from_tracking_error(max_error, alpha, FIVE_PERCENT_DAMPING, ts, PM).unwrap();
    let paper = DesignReport::new(&paper, 0.0).unwrap();
    let paper_error = alpha / paper.acceleration_constant_per_s2.unwrap();
    assert!((paper_error - 0.869e-3).abs() < 1e-6, "{paper_error}");
    assert!((paper.linear_step.overshoot - 0.0435).abs() < 5e-4);
}

#[test]
fn sampled_design_reaches_overshoots_across_its_range_and_refuses_the_rest() {
    for (overshoot, ts) in [(0.2, 1e-4), (0.01, 1e-6), (0.001, 1e-4), (0.9, 1e-4)] {
        let design = second_order_from_tracking_error_sampled(1e-3, 1e3, overshoot, ts).unwrap();
        let report = DesignReport::new(&design, 0.0).unwrap();
        assert!(
            (report.linear_step.overshoot - overshoot).abs() < 1e-6,
            "{overshoot}"
        );
        let ka = report.acceleration_constant_per_s2.unwrap();
        assert!((ka / 1e6 - 1.0).abs() < 1e-9, "{overshoot}: Ka {ka}");
    }
    use Argument::*;
    check_arguments(
        [1e-3, 1e3, 0.05, 1e-4],
        [MaxError, Acceleration, Overshoot, SamplePeriod],
        |[e, a, o, ts]| second_order_from_tracking_error_sampled(e, a, o, ts),
    );
    let sampled = |o: f64, ts: f64| second_order_from_tracking_error_sampled(1e-3, 1e3, o, ts);
    assert!(matches!(
        sampled(1.0, 1e-4),
        Err(Error::OutOfRange {
            argument: Overshoot,
            ..
        })
    ));
    assert_eq!(
        sampled(1e-9, 1e-4).unwrap_err(),
        Error::NoSolution(Overshoot)
    );
    assert!(matches!(
        sampled(0.05, 2e-3),
        Err(Error::TooFastForSampleRate {
            argument: MaxError,
            ..
        })
    ));
    assert!(matches!(
        sampled(0.05, 1e-8),
        Err(Error::OutOfRange {
            argument: MaxError,
            ..
        })
    ));
}

#[test]
fn designs_name_the_caller_s_argument_at_the_extremes_of_its_range() {
    // A loop so slow that its gains underflow is refused naming the argument that sets its
    // speed, not the core's gains, which the caller never wrote.
    match third_order_butterworth(1e120, 1e-4, PM) {
        Err(Error::GainsRefused { argument, .. }) => assert_eq!(argument, Argument::TimeConstant),
        other => panic!("expected GainsRefused, got {other:?}"),
    }
    match second_order_butterworth(1e300, 1e-4, PM) {
        Err(Error::GainsRefused { argument, .. }) => assert_eq!(argument, Argument::TimeConstant),
        other => panic!("expected GainsRefused, got {other:?}"),
    }
    // Poles that overflow to NaN (a critically damped pair at an infinite natural frequency)
    // are refused, not folded away, and the message says so.
    let e = second_order_from_bandwidth(1e308, 1.0, 1e-4, PM).unwrap_err();
    assert_eq!(e.argument(), Some(Argument::Bandwidth));
    assert!(e.to_string().contains("out of floating-point range"), "{e}");
    let e = second_order_from_bandwidth(1e300, 1.0, 1e-4, PM).unwrap_err();
    assert_eq!(e.argument(), Some(Argument::Bandwidth), "{e}");
    // The noise passed on to the Kalman design as r is reported under the caller's name.
    assert_eq!(
        kalman_from_jerk_std(1e5, 1e300, 1e-4).unwrap_err(),
        Error::NotFinite(Argument::SensorNoiseStd)
    );
    assert_eq!(
        kalman_from_jerk_density(1e6, 1e300, 1e-4).unwrap_err(),
        Error::NotFinite(Argument::SensorNoiseStd)
    );
}
