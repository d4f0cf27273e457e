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
