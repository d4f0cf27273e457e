//! The tables' tangents: exact rotations, and integer entries that read back as they were
//! given.

use super::*;

/// Every error a fixed-point table accepts (-0.25 to 0.25 rad in Q15) reads back exactly
/// from its stored tangent.
#[test]
fn fixed_tangents_round_trip_every_error() {
    for d in -8192..=8192_i16 {
        let table = FixedAngleCorrectionTable::<4>::new([d, 0, 0, 0]).unwrap();
        assert_eq!(table.errors_q15()[0], d, "entry {d}");
    }
}

/// The integer tangent is `tan d` rounded to Q15: within half a unit plus the series'
/// truncation, over the whole range.
#[test]
fn fixed_tangents_are_the_rounded_tangents() {
    for d in (-8192..=8192_i16).step_by(7) {
        let exact = libm::tan(f64::from(d) / 32768.0) * 32768.0;
        let t = f64::from(tangent_q15(d));
        assert!(
            (t - exact).abs() <= 0.5 + 1e-3,
            "d {d}: {t} against {exact}"
        );
    }
}

/// The float table's rotation turns the sample by exactly `-d` (its angle), up to the
/// tangent series' truncation (below 6e-11 rad at 0.25 rad), for errors up to the largest
/// the table accepts.
#[test]
fn the_float_rotation_is_exact_in_angle() {
    for d in [-0.25, -0.1, -0.004, 0.0, 0.001, 0.05, 0.25_f64] {
        let table = AngleCorrectionTable::<f64, 4>::new([d; 4]).unwrap();
        for theta in [-3.0, -1.2, 0.4, 2.9_f64] {
            let (c, s) = table.rotate(0.3, 0.7 * theta.cos(), 0.7 * theta.sin());
            let turned = s.atan2(c);
            let error = (turned - (theta - d) + 3.0 * core::f64::consts::PI)
                .rem_euclid(core::f64::consts::TAU)
                - core::f64::consts::PI;
            assert!(error.abs() < 1e-10, "d {d}, theta {theta}: {error}");
            // The scale 1 / cos d, which the normalised phase detector removes.
            let scale = c.hypot(s) / 0.7;
            assert!(
                (scale - 1.0 / d.cos()).abs() < 1e-10,
                "d {d}: scale {scale}"
            );
        }
    }
}

/// The fixed-point rotation turns a full-scale sample by `-d` within two units of Q15
/// (6e-5 rad: the rounding of the tangent and of each product), for errors up to 0.25 rad.
#[test]
fn the_fixed_rotation_is_exact_in_angle_to_the_rounding() {
    for d in [-8192, -3000, -131, 0, 33, 1000, 8192_i16] {
        let table = FixedAngleCorrectionTable::<4>::new([d; 4]).unwrap();
        for theta in [-3.0, -1.2, 0.4, 2.9_f64] {
            let (c, s) = (20_000.0 * theta.cos(), 20_000.0 * theta.sin());
            let (c, s) = table.rotate(0, c.round() as i16, s.round() as i16);
            let turned = f64::from(s).atan2(f64::from(c));
            let expected = theta - f64::from(d) / 32768.0;
            let error = (turned - expected + 3.0 * core::f64::consts::PI)
                .rem_euclid(core::f64::consts::TAU)
                - core::f64::consts::PI;
            assert!(error.abs() < 2.0 / 32768.0, "d {d}, theta {theta}: {error}");
        }
    }
}

/// A full-scale sample turned by the largest error saturates instead of wrapping.
#[test]
fn the_fixed_rotation_saturates() {
    let table = FixedAngleCorrectionTable::<4>::new([8192; 4]).unwrap();
    let (c, s) = table.rotate(0, i16::MAX, i16::MAX);
    assert_eq!(c, i16::MAX);
    assert!(s > 0 && s < i16::MAX, "{s}");
    let (c, _) = table.rotate(0, i16::MIN, i16::MIN);
    assert_eq!(c, i16::MIN);
}
