//! The fixed point's ranges at their extremes (`docs/theory.md §13`): full-scale 16-bit
//! samples at the most samples per period the type allows, with the carrier at the slowest
//! the loop may track (the longest segments and windows), against `f32`.

extern crate std;
use std::vec::Vec;

use super::*;
use core::f64::consts::TAU;

/// The pairs of the fixed point and of `f32` on a full-scale square wave (the largest
/// product of each sample with the reference), `samples_per_period` samples per declared
/// period, the true carrier `ratio` times the declared one.
fn square_wave_pairs(
    ratio: f64,
    periods: usize,
) -> (Vec<DemodulatedPair<f32>>, Vec<DemodulatedPair<i16>>) {
    let samples_per_period = <i16 as DemodulatorNumber>::MAX_SAMPLES_PER_PERIOD as f64;
    let settings = DemodulatorSettings::<f32>::new(
        10e3,
        (10e3 * samples_per_period) as f32,
        32_767.0,
        -32_768.0,
        32_767.0,
    );
    let (d32, d16) = (
        Demodulator::<f32>::new(settings).unwrap(),
        Demodulator::<i16>::new(settings).unwrap(),
    );
    let (mut st32, mut st16) = (DemodulatorState::new(), DemodulatorState::new());
    let (mut p32, mut p16) = (Vec::new(), Vec::new());
    for j in 0..(periods as f64 * samples_per_period / ratio) as usize {
        // The cosine winding full scale (shaft at 0), the sine winding at the rail.
        let psi = TAU * ratio * j as f64 / samples_per_period;
        let c = if psi.sin() >= 0.0 { 32_767 } else { -32_767 };
        let s = -32_767;
        p32.extend(d32.push(&mut st32, f32::from(c as i16), f32::from(s as i16)));
        p16.extend(d16.push(&mut st16, c as i16, s as i16));
    }
    assert!(st16.step <= d16.step_max && st16.step >= d16.step_min);
    (p32, p16)
}

/// The segments' `i32` sums and the windows' `i32` values do not overflow (a test build
/// panics on an overflowing sum) and give the pairs of `f32`: the square wave's envelope
/// `4 / pi` of full scale at the declared carrier (the loop slips on the slower one,
/// as `f32`'s does), the sine winding's 0 (its constant removed as the window's mean).
#[test]
fn full_scale_samples_at_the_most_samples_per_period_do_not_overflow() {
    // The declared carrier, and one 15 % slower (the loop slewing to it: longer segments
    // and windows), within the loop's range of 20 %.
    for ratio in [1.0, 0.85] {
        let (p32, p16) = square_wave_pairs(ratio, 400);
        assert!(p16.len() > 300, "{ratio}: {} pairs", p16.len());
        assert_eq!(p32.len(), p16.len());
        let unit = f32::from(FIXED_PAIR_UNIT);
        let mut longest = 0;
        for (a, b) in p32.iter().zip(&p16).skip(100) {
            // The two loops lock a little apart and wobble (the square wave's harmonics 63
            // and 65 alias onto its fundamental at 64 samples a period, by phase): the
            // envelopes agree to 2 %; an overflow would be off by orders of magnitude.
            let (y_c, y_s) = (f32::from(b.y_c) / unit, f32::from(b.y_s) / unit);
            let q_c = f32::from(b.quadrature_c) / unit;
            let envelope = (y_c.hypot(q_c), a.y_c.hypot(a.quadrature_c));
            assert!(
                (envelope.0 - envelope.1).abs() < 0.02 * envelope.1 && (y_s - a.y_s).abs() < 2e-3,
                "{ratio}: {a:?} {b:?}"
            );
            assert!(
                (ratio < 1.0 || (envelope.0 - 4.0 / core::f32::consts::PI).abs() < 0.03)
                    && y_s.abs() < 2e-3,
                "{ratio}: {b:?}"
            );
            longest = longest.max(b.weight);
        }
        // Windows of the slower carrier's longer than the declared one's (weight 128).
        assert!(ratio == 1.0 || longest > 132, "{ratio}: weight {longest}");
    }
}
