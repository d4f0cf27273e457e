//! The refusals and the pieces of the estimates on exact signals; the whole method is
//! checked against a generator in `crates/angletrack/tests/design_from_capture.rs`.

use super::linear_loop;
use super::*;

const TS: f64 = 1e-4;

fn signals<'a>(cos: &'a [f64], sin: &'a [f64], reference: Option<&'a [f64]>) -> CaptureSignals<'a> {
    CaptureSignals {
        cos,
        sin,
        sample_period_s: TS,
        reference_angle_rad: reference,
        quantisation_step: None,
    }
}

fn circle(angle: &[f64], cos_offset: f64) -> (Vec<f64>, Vec<f64>) {
    (
        angle.iter().map(|a| cos_offset + 3.0 * a.cos()).collect(),
        angle.iter().map(|a| 2.0 * (a + 0.05).sin()).collect(),
    )
}

#[test]
fn a_capture_without_motion_enough_is_refused_naming_what_it_lacks() {
    let still = vec![0.3; 5000];
    let (cos, sin) = circle(&still, 0.0);
    let e = estimate_from_capture(&signals(&cos, &sin, Some(&still))).unwrap_err();
    assert_eq!(
        e.to_string(),
        "capture at standstill: the shaft travels 0.00 rad, the estimates need it turning"
    );
    let slow: Vec<f64> = (0..5000).map(|k| k as f64 * 1e-3).collect();
    let (cos, sin) = circle(&slow, 0.0);
    let e = estimate_from_capture(&signals(&cos, &sin, None)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "capture with too few turns: 0.79 turns travelled, at least 2 needed"
    );
    let mut bad = cos.clone();
    bad[17] = f64::NAN;
    let e = estimate_from_capture(&signals(&bad, &sin, None)).unwrap_err();
    assert_eq!(e.to_string(), "cos[17] is not a finite number");
    let e = estimate_from_capture(&signals(&cos, &sin[1..], None)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "sin has 4999 samples, cos has 5000: they must be the same length"
    );
}

#[test]
fn the_ellipse_of_offsets_imbalance_and_quadrature_is_undone_exactly() {
    let angle: Vec<f64> = (0..4000).map(|k| k as f64 * 0.01).collect();
    let (cos, sin) = circle(&angle, 0.4);
    let estimates = estimate_from_capture(&signals(&cos, &sin, None)).unwrap();
    assert!((estimates.noise.amplitude - 2.5).abs() < 1e-9);
    assert!(estimates.noise.std.value < 1e-9);
    // The signals' own angle, smoothed, is the shaft's up to the fit's rounding.
    let window = estimates.window();
    let mid = window.start + 100;
    assert!((estimates.motion.angle_rad[mid] - angle[mid]).abs() < 1e-6);
}

#[test]
fn coloured_noise_through_the_loop_is_the_simulated_variance() {
    // A first-order autoregression of pole 0.9 through a 2nd-order loop: the Lyapunov
    // figure against the mean square of the loop's output over a long deterministic run.
    let l = [0.2, 0.02];
    let predicted = linear_loop::noise_variance(&l, 0.0, 1.0, 0.9, 0.0).unwrap();
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut n = 0.0;
    let innovation_std = (12.0 * (1.0 - 0.81_f64)).sqrt();
    let noise: Vec<f64> = (0..400_000)
        .map(|_| {
            n = 0.9 * n + innovation_std * uniform();
            n
        })
        .collect();
    let out = linear_loop::filtered(&l, &noise, 0.0);
    let measured = out[1000..].iter().map(|x| x * x).sum::<f64>() / (out.len() - 1000) as f64;
    assert!(
        (measured / predicted - 1.0).abs() < 0.05,
        "{measured} {predicted}"
    );
}

#[test]
fn constraints_out_of_range_are_refused_by_name() {
    let angle: Vec<f64> = (0..4000).map(|k| k as f64 * 0.01).collect();
    let (cos, sin) = circle(&angle, 0.0);
    let constraints = DesignConstraints {
        max_overshoot: Some(-0.1),
        ..DesignConstraints::default()
    };
    let e = design_from_capture(&signals(&cos, &sin, Some(&angle)), &constraints).unwrap_err();
    assert_eq!(
        e.to_string(),
        "max_overshoot must be a fraction of at least 0"
    );
}

#[test]
fn the_third_difference_factor_is_one_half_at_stride_one_and_eleven_twentieths_h5_beyond() {
    // docs/theory.md §16.2: (1 + 16 + 1) / 36 at h = 1, the quadratic B-spline's 11/20 h^5.
    assert!((super::jerk::third_difference_factor(1) - 0.5).abs() < 1e-15);
    let h = 64;
    let ratio = super::jerk::third_difference_factor(h) / (h as f64).powi(5);
    assert!((ratio / 0.55 - 1.0).abs() < 1e-3, "{ratio}");
}

/// A standard normal sequence (Box-Muller on a xorshift), deterministic.
fn normals(count: usize, mut state: u64) -> Vec<f64> {
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..count)
        .map(|_| {
            let (u, v) = (uniform(), uniform());
            (-2.0 * u.ln()).sqrt() * (core::f64::consts::TAU * v).cos()
        })
        .collect()
}

#[test]
fn als_recovers_the_jerk_and_the_noise_of_the_kalman_model_within_its_uncertainty() {
    // The Kalman model itself: a white jerk of 1e4 rad/s^3 constant over each sample, and
    // a white angle noise of 0.01 rad, over 10 s at 10 kHz.
    let (jerk, noise, n) = (1e4, 0.01, 100_000);
    let (w, v) = (
        normals(n, 0x2545_f491_4f6c_dd1d),
        normals(n, 0x9e37_79b9_7f4a_7c15),
    );
    let (mut theta, mut speed, mut acceleration) = (0.0, 0.0, 0.0);
    let angle: Vec<f64> = (0..n)
        .map(|k| {
            let out = theta + noise * v[k];
            let j = jerk * w[k];
            theta += TS * speed + TS * TS / 2.0 * acceleration + TS.powi(3) / 6.0 * j;
            speed += TS * acceleration + TS * TS / 2.0 * j;
            acceleration += TS * j;
            out
        })
        .collect();
    let (q, r) = ((jerk * TS.powi(3)).powi(2), noise * noise);
    let hz = super::estimate::nominal_bandwidth_hz(q / r, TS);
    let gains = crate::kalman(q, r, TS).unwrap().gains.gains().to_vec();
    let als = super::als::estimate(&gains, hz, &angle, TS, 0.0, 0.0).unwrap();
    let j = als.jerk_std_rad_s3;
    assert!((j.value / jerk - 1.0).abs() < 0.15, "{als:?}");
    assert!(
        j.std > 0.0 && (j.value - jerk).abs() < 4.0 * j.std,
        "{als:?}"
    );
    assert!((als.noise_std.value / noise - 1.0).abs() < 0.02, "{als:?}");
}

#[test]
fn the_smoothed_noise_tracked_by_a_loop_is_the_simulated_variance() {
    // White noise smoothed forward and backward by a first pass, then tracked by a narrower
    // loop: the impulse response's energy against the mean square over a long run.
    let (first, l) = ([0.16, 0.014, 0.0006], [0.03, 0.0005, 4e-6]);
    let predicted =
        linear_loop::smoothed_noise_tracking_variance(&l, &first, 1.0, 0.0, 0.0, 20_000);
    let noise = normals(200_000, 0x1234_5678_9abc_def1);
    let smoothed = linear_loop::smoothed(&first, &noise, 1);
    let tracked = linear_loop::filtered(&l, &smoothed, 0.0);
    let window = 20_000..180_000;
    let measured = window
        .clone()
        .map(|k| (smoothed[k] - tracked[k]).powi(2))
        .sum::<f64>()
        / window.len() as f64;
    assert!(
        (measured / predicted - 1.0).abs() < 0.05,
        "{measured} {predicted}"
    );
}

#[test]
fn the_ellipse_fit_of_noisy_signals_is_unbiased_where_the_plain_least_squares_is_not() {
    // A circle of amplitude 2 traced 40 times under 10 % white noise per channel.
    let n = 100_000;
    let (a, b) = (
        normals(n, 0x0123_4567_89ab_cdef),
        normals(n, 0x7654_3210_fedc_ba98),
    );
    let angle: Vec<f64> = (0..n)
        .map(|k| k as f64 * 40.0 * core::f64::consts::TAU / n as f64)
        .collect();
    let cos: Vec<f64> = angle
        .iter()
        .zip(&a)
        .map(|(t, w)| 2.0 * t.cos() + 0.2 * w)
        .collect();
    let sin: Vec<f64> = angle
        .iter()
        .zip(&b)
        .map(|(t, w)| 2.0 * t.sin() + 0.2 * w)
        .collect();
    let fitted = super::ellipse::Ellipse::fit(&cos, &sin).unwrap();
    let plain = super::ellipse::Ellipse::fit_with_noise(&cos, &sin, 0.0).unwrap();
    let error = |e: &super::ellipse::Ellipse| (e.amplitude() / 2.0 - 1.0).abs();
    assert!(error(&fitted) < 0.002, "{fitted:?}");
    assert!(error(&plain) > 3.0 * error(&fitted), "{plain:?} {fitted:?}");
}
