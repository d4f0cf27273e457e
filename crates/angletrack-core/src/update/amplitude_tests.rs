//! The amplitude-invariant loop (`docs/theory.md §12`): the same gains give the same
//! estimates at any amplitude and in any unit, and an amplitude step during tracking does
//! not change the loop's transient.

extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use crate::test_support::{TS, designs, n, proptest_config, settling_samples};
use crate::*;

/// The motion of these tests: starts at 0.5 rad, speed 100 rad/s and acceleration 400
/// rad/s^2 from the first sample, so the observer (starting at rest) goes through a
/// transient before it tracks.
fn theta(k: usize) -> f64 {
    let t = k as f64 * TS;
    0.5 + 100.0 * t + 200.0 * t * t
}

/// Multi-turn angles (rad) of an observer from `ObserverState::new` fed the motion at
/// amplitude `amplitude(k)`.
fn angles<const N: usize>(
    gains: &Gains<f64, N>,
    samples: usize,
    amplitude: impl Fn(usize) -> f64,
) -> Vec<f64> {
    let mut state = ObserverState::new();
    (0..samples)
        .map(|k| {
            let (a, th) = (amplitude(k), theta(k));
            gains
                .update(&mut state, a * th.cos(), a * th.sin())
                .position()
        })
        .collect()
}

/// The largest |difference| of two runs' angles from sample `from` on.
fn largest_from(a: &[f64], b: &[f64], from: usize) -> f64 {
    a[from..]
        .iter()
        .zip(&b[from..])
        .fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Raw units (amplitude 1e-3 to 1e5, 1800 being 12-bit ADC counts): the same angles as at
/// amplitude 1 within 1e-5 rad once the loop has settled, with the monitor's thresholds
/// scaled to the amplitude and with one set of wide thresholds for all.
#[test]
fn the_same_gains_give_the_same_angles_at_any_amplitude() {
    let (o2, o3, ok) = designs();
    fn check<const N: usize>(gains: Gains<f64, N>, name: &str) {
        let samples = 4 * settling_samples(&gains);
        let from = settling_samples(&gains);
        let wide = FaultThresholds {
            max_input_amplitude: 1e6,
            ..FaultThresholds::disabled()
        };
        let reference = angles(&gains, samples, |_| 1.0);
        for amplitude in [1e-3, 1.0, 1800.0, 1e5] {
            for thresholds in [FaultThresholds::for_amplitude(amplitude), wide] {
                let scaled = gains.with_fault_thresholds(thresholds).unwrap();
                let d = largest_from(&angles(&scaled, samples, |_| amplitude), &reference, from);
                assert!(d < 1e-5, "{name} at amplitude {amplitude}: {d} rad");
            }
        }
    }
    check(o2, "2nd order");
    check(o3, "3rd order");
    check(ok, "Kalman");
}

/// A 20 % amplitude step in the middle of the loop's transient (a quarter of its settling
/// time after the start) moves the angle by less than 2e-3 of the transient's peak error:
/// the normalisation follows the step at once in `f64` (and within a sample in `f32`: 1.7 %
/// off on the first one, 1.4e-4 on the next), so the transient, and its overshoot, are the
/// design's. Without the normalisation the loop gain itself would step by 20 %.
#[test]
fn an_amplitude_step_during_tracking_adds_no_overshoot() {
    let (o2, o3, ok) = designs();
    fn check<const N: usize>(gains: Gains<f64, N>, name: &str) {
        let samples = 2 * settling_samples(&gains);
        let at = settling_samples(&gains) / 4;
        let steady = angles(&gains, samples, |_| 1.0);
        let stepped = angles(&gains, samples, |k| if k < at { 1.0 } else { 1.2 });
        let peak = steady
            .iter()
            .enumerate()
            .fold(0.0, |m: f64, (k, a)| m.max((theta(k) - a).abs()));
        let d = largest_from(&stepped, &steady, 0);
        assert!(d < 2e-3 * peak, "{name}: {d} rad of a {peak} rad transient");
    }
    check(o2, "2nd order");
    check(o3, "3rd order");
    check(ok, "Kalman");
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Any amplitude from 1e-4 to 1e6 (any unit) and any start: the same estimates as at
    /// amplitude 1, within 1e-9 rad (angle) and 1e-9 relative (speed), the thresholds
    /// scaled to the amplitude.
    #[test]
    fn estimates_do_not_depend_on_amplitude_or_unit(
        decades in -4.0f64..6.0,
        start in -3.0f64..3.0,
        speed in -300.0f64..300.0,
    ) {
        let amplitude = 10f64.powf(decades);
        let (_, _, kalman) = designs();
        let scaled = kalman
            .with_fault_thresholds(FaultThresholds::for_amplitude(amplitude))
            .unwrap();
        let (mut unit, mut other) = (ObserverState::new(), ObserverState::new());
        for k in 0..n(2000) {
            let th = start + speed * k as f64 * TS;
            let (c, s) = (th.cos(), th.sin());
            let a = kalman.update(&mut unit, c, s);
            let b = scaled.update(&mut other, amplitude * c, amplitude * s);
            prop_assert!((a.position() - b.position()).abs() < 1e-9);
            prop_assert!((a.speed - b.speed).abs() <= 1e-9 * (1.0 + a.speed.abs()));
            prop_assert!((a.phase_error - b.phase_error).abs() < 1e-9);
            prop_assert_eq!(a.faults, b.faults);
        }
        prop_assert!((other.amplitude() / amplitude - 1.0).abs() < 1e-12);
    }
}
