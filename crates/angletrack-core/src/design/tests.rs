//! The core's designs against the `angletrack` crate's (`design/reference.rs`, a grid of
//! settings): relative agreement per gain within 1e-9 in `f64` and within 1e-4 in `f32`
//! (`docs/theory.md §2, §3, §4, §7`), and the refusals naming the parameter.

use super::reference::{KALMAN, SECOND_ORDER, THIRD_ORDER};
use crate::*;

/// Relative agreement of the `f64` designs with the `angletrack` crate's.
const F64_TOLERANCE: f64 = 1e-9;
/// Relative agreement of the `f32` designs with the `angletrack` crate's (`f64`) ones.
const F32_TOLERANCE: f64 = 1e-4;

/// The largest relative difference between the gains.
fn relative_error<const N: usize>(actual: [f64; N], expected: [f64; N]) -> f64 {
    (0..N)
        .map(|i| ((actual[i] - expected[i]) / expected[i]).abs())
        .fold(0.0, f64::max)
}

fn widened<const N: usize>(gains: [f32; N]) -> [f64; N] {
    gains.map(f64::from)
}

#[test]
fn second_order_from_bandwidth_agrees_with_the_std_crate() {
    let (mut worst64, mut worst32) = (0.0_f64, 0.0_f64);
    for &(bandwidth, damping, ts, expected) in SECOND_ORDER {
        let g64 = Gains::<f64, 2>::second_order_from_bandwidth(bandwidth, damping, ts).unwrap();
        worst64 = worst64.max(relative_error(g64.gains(), expected));
        let g32 = Gains::<f32, 2>::second_order_from_bandwidth(
            bandwidth as f32,
            damping as f32,
            ts as f32,
        )
        .unwrap();
        worst32 = worst32.max(relative_error(widened(g32.gains()), expected));
    }
    assert!(worst64 < F64_TOLERANCE, "f64: {worst64:e}");
    assert!(worst32 < F32_TOLERANCE, "f32: {worst32:e}");
}

#[test]
fn third_order_from_poles_agrees_with_the_std_crate() {
    let (mut worst64, mut worst32) = (0.0_f64, 0.0_f64);
    for &(k, t, psi, ts, expected) in THIRD_ORDER {
        let g64 = Gains::<f64, 3>::third_order_from_poles(k, t, psi, ts).unwrap();
        worst64 = worst64.max(relative_error(g64.gains(), expected));
        let g32 =
            Gains::<f32, 3>::third_order_from_poles(k as f32, t as f32, psi as f32, ts as f32)
                .unwrap();
        worst32 = worst32.max(relative_error(widened(g32.gains()), expected));
    }
    assert!(worst64 < F64_TOLERANCE, "f64: {worst64:e}");
    assert!(worst32 < F32_TOLERANCE, "f32: {worst32:e}");
}

#[test]
fn kalman_agrees_with_the_std_crate() {
    let (mut worst64, mut worst32) = (0.0_f64, 0.0_f64);
    for &(q, r, expected) in KALMAN {
        let g64 = Gains::<f64, 3>::kalman(q, r, 50e-6).unwrap();
        worst64 = worst64.max(relative_error(g64.gains(), expected));
        let g32 = Gains::<f32, 3>::kalman(q as f32, r as f32, 50e-6).unwrap();
        worst32 = worst32.max(relative_error(widened(g32.gains()), expected));
    }
    assert!(worst64 < F64_TOLERANCE, "f64: {worst64:e}");
    assert!(worst32 < F32_TOLERANCE, "f32: {worst32:e}");
}

#[test]
fn designs_refuse_what_they_cannot_design_naming_the_parameter() {
    let parameter = |e: ConfigError| e.parameter();
    let second = Gains::<f32, 2>::second_order_from_bandwidth;
    assert_eq!(
        second(0.0, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    assert_eq!(
        second(100.0, f32::NAN, 1e-4).map_err(parameter),
        Err(Parameter::Damping)
    );
    assert_eq!(
        second(100.0, 2e3, 1e-4).map_err(parameter),
        Err(Parameter::Damping)
    );
    assert_eq!(
        second(100.0, 1.0, -1e-4).map_err(parameter),
        Err(Parameter::SamplePeriod)
    );
    assert_eq!(
        second(1e4, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    assert_eq!(
        second(f32::MAX, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    let third = Gains::<f64, 3>::third_order_from_poles;
    assert_eq!(
        third(0.0, 1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleRatio)
    );
    assert_eq!(
        third(2e6, 1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleRatio)
    );
    assert_eq!(
        third(1.0, 1e-2, 2e3, 1e-4).map_err(parameter),
        Err(Parameter::PoleFrequencyRatio)
    );
    assert_eq!(
        third(1.0, -1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleTimeConstant)
    );
    assert_eq!(
        third(100.0, 1e-3, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleTimeConstant)
    );
    let kalman = Gains::<f32, 3>::kalman;
    assert_eq!(
        kalman(0.0, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
    assert_eq!(
        kalman(1.0, f32::INFINITY, 1e-4).map_err(parameter),
        Err(Parameter::MeasurementNoise)
    );
    assert_eq!(
        kalman(1e-32, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
    assert_eq!(
        kalman(1e7, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
}
