//! The fit errors of the `f32` sin/cos polynomials that `docs/theory.md §11` quotes, once
//! their coefficients are rounded to `f32` (3.4e-8 for sin, 6.0e-8 for cos), each held
//! within 2x. The polynomials are evaluated in `f64`, so that only the coefficients' error
//! is measured, not the rounding of the evaluation.

use super::{F32_COS_POLY, F32_SIN_POLY};

/// The largest `|w P(w^2) - sin w|` and `|Q(w^2) - cos w|` over `n + 1` angles of
/// [-pi/2, pi/2].
fn fit_errors(n: usize) -> (f64, f64) {
    let polynomial = |coefficients: &[f32; 5], t: f64| {
        coefficients
            .iter()
            .rev()
            .fold(0.0, |sum, &c| sum * t + f64::from(c))
    };
    let (mut sin_error, mut cos_error) = (0.0f64, 0.0f64);
    for i in 0..=n {
        let w = -core::f64::consts::FRAC_PI_2 + core::f64::consts::PI * i as f64 / n as f64;
        let t = w * w;
        sin_error = sin_error.max((w * polynomial(&F32_SIN_POLY, t) - libm::sin(w)).abs());
        cos_error = cos_error.max((polynomial(&F32_COS_POLY, t) - libm::cos(w)).abs());
    }
    (sin_error, cos_error)
}

#[test]
fn f32_polynomials_fit_sin_and_cos_within_the_quoted_errors() {
    let (sin_error, cos_error) = fit_errors(20_000);
    assert!(sin_error > 1.7e-8 && sin_error < 6.8e-8, "sin {sin_error}");
    assert!(cos_error > 3.0e-8 && cos_error < 1.2e-7, "cos {cos_error}");
}
