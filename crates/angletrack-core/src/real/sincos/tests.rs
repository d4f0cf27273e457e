//! The fast sin/cos and its folded phase detector against `f64`'s own, and an observer
//! with it against one with the exact sin/cos (`docs/theory.md §11`).

use crate::test_support::{TS, largest_difference, n, run};
use crate::*;

/// The largest of `error(x, sin x, cos x)` (sin and cos in `f64`) over `n + 1` angles `x`
/// evenly spread over [-pi, pi].
fn worst_over_the_angle_range<T: Real>(n: usize, mut error: impl FnMut(T, f64, f64) -> f64) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..=n {
        let x = T::from_f64(-core::f64::consts::PI + core::f64::consts::TAU * i as f64 / n as f64);
        let (s64, c64) = x.to_f64().sin_cos();
        worst = worst.max(error(x, s64, c64));
    }
    worst
}

/// A sweep that found no error at all compared nothing: each float type must show some.
fn assert_the_sweeps_measured_something(e32: f64, e64: f64) {
    assert!(
        e32 > 1e-9 && e64 > 1e-17,
        "the sweep measured something: {e32} {e64}"
    );
}

/// Both rules of evaluation (Horner's, on a Cortex-M in `f32`; Estrin's elsewhere), on
/// every target: each type's bound holds for both.
#[test]
fn fast_sin_cos_error_is_within_its_documented_bound() {
    fn check<T: Real>(horner: bool) -> f64 {
        let n = if cfg!(miri) { 2_000 } else { 2_000_000 };
        let worst = worst_over_the_angle_range::<T>(n, |x, s64, c64| {
            let (s, c) = crate::real::sincos::fast_sin_cos_by(x, horner);
            (s.to_f64() - s64).abs().max((c.to_f64() - c64).abs())
        });
        assert!(worst < T::FAST_SIN_COS_MAX_ERROR.to_f64(), "error {worst}");
        worst
    }
    for horner in [true, false] {
        assert_the_sweeps_measured_something(check::<f32>(horner), check::<f64>(horner));
    }
}

/// The folded phase detector of `Fast` computes what the sin/cos it folds would give: both
/// outputs within the sin/cos error bound times the input amplitude (plus a few roundings) of
/// the exact `y_s cos - y_c sin` and `y_c cos + y_s sin`, over the whole angle range and
/// for inputs of every sign.
#[test]
fn fast_phase_detector_matches_the_sin_cos_it_folds() {
    fn check<T: Real>(horner: bool) -> f64 {
        let n = if cfg!(miri) { 500 } else { 200_000 };
        let inputs = [
            (0.8, 0.6),
            (-0.3, 0.95),
            (-1.9, -2.2),
            (3.5, -0.1),
            (0.0, -1.0),
        ];
        worst_over_the_angle_range::<T>(n, |x, s64, c64| {
            let mut worst = 0.0f64;
            for (y_c, y_s) in inputs {
                let (eps, in_phase) = crate::real::sincos::fast_phase_detector_by(
                    x,
                    T::from_f64(y_c),
                    T::from_f64(y_s),
                    horner,
                );
                let (y_c, y_s) = (T::from_f64(y_c).to_f64(), T::from_f64(y_s).to_f64());
                let amplitude = y_c.abs() + y_s.abs();
                let bound =
                    amplitude * (T::FAST_SIN_COS_MAX_ERROR.to_f64() + 4.0 * T::EPSILON.to_f64());
                let d_eps = (eps.to_f64() - (y_s * c64 - y_c * s64)).abs();
                let d_in = (in_phase.to_f64() - (y_c * c64 + y_s * s64)).abs();
                assert!(
                    d_eps <= bound && d_in <= bound,
                    "at {x}: {d_eps} {d_in} > {bound}"
                );
                worst = worst.max(d_eps / amplitude).max(d_in / amplitude);
            }
            worst
        })
    }
    for horner in [true, false] {
        assert_the_sweeps_measured_something(check::<f32>(horner), check::<f64>(horner));
    }
}

#[test]
fn fast_sin_cos_observer_matches_the_exact_one() {
    let fast = Gains::<f32, 3, Fast>::new([0.3, 0.04, 0.002], TS as f32).unwrap();
    let exact: Gains<f32, 3, Exact> = fast.with_sin_cos();
    let theta = |t: f64| (2.0 + 150.0 * t, 150.0);
    let a = run(&fast, n(20_000), theta);
    let b = run(&exact, n(20_000), theta);
    let worst = largest_difference(&a, &b, |e| e.0);
    assert!(worst < 1e-6, "fast sin/cos moved the angle by {worst} rad");
}

#[test]
fn a_sin_cos_used_as_a_unit_updates_exactly_as_the_gains_own() {
    let gains = Gains::<f32, 3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    let chain = Chain::new((), gains.with_unit::<Fast>());
    let mut by_gains = ObserverState::new();
    let mut by_unit = ChainState {
        front_end: (),
        observer: (ObserverState::new(), Fast),
    };
    for k in 0..500 {
        let angle = 0.01 * k as f32 * k as f32 * 1e-2;
        let (y_s, y_c) = (libm::sinf(angle), libm::cosf(angle));
        let expected = gains.update(&mut by_gains, y_c, y_s);
        assert_eq!(chain.update(&mut by_unit, (y_c, y_s)), expected);
    }
    assert_eq!(by_unit.observer.0, by_gains);
}
